"""The vector stage, end to end: a scene and a time in, a :class:`Frame` out.

``render`` runs the paper's pipeline for the rays: direct rays by the
height-field scan line (:mod:`sunset.heightfield`, :mod:`sunset.islands`),
then reflected rays (:mod:`sunset.pierce`).

Reflection modes
----------------
0
    Reflected rays go straight to the sky: no islands are pierced and no
    secondary reflection is looked for (a diagnostic; the cheapest mode).
1
    One reflection from the waves, each reflected R_z replaced by |R_z|, then
    the islands or the sky (Figure 5; Figure 4 is this mode on still water).
2
    Up to two reflections: secondary reflections off a parabolic cylinder
    fitted to the crest ahead, gathered and scattered (Figure 6).
"""

from __future__ import annotations

import numpy as np

from .errors import require_finite, require_int_range
from .frame import Frame
from .scene import Scene

def render(scene: Scene, t: float = 0.0, reflections: int = 2) -> Frame:
    """Trace every pixel of ``scene`` at time ``t`` (seconds).

    Parameters
    ----------
    scene : Scene
    t : float
        Time in seconds (the sea moves; nothing else does).
    reflections : {0, 1, 2}
        See the module docstring.

    Returns
    -------
    Frame
        Direct-ray and final-ray fields for every pixel.
    """
    from .heightfield import trace_direct
    from .pierce import trace_reflections

    require_finite("t", t)
    require_int_range("reflections", reflections, 0, 2)
    return trace_reflections(scene, trace_direct(scene, t), reflections)


# --------------------------------------------------------------------------- many frames, both cores
def code_frame(scene: Scene, t: float, reflections: int = 2, seed: int = 0):
    """The vector stage for one frame: :func:`render` then :func:`sunset.codes.encode` (uint8 (H, W))."""
    from .codes import encode

    return encode(scene, render(scene, float(t), reflections), seed=seed)


def _code_frame_task(args):
    return code_frame(*args)


def frame_workers(workers: int | None = None, frames: int = 1) -> int:
    """How many processes render frames: ``workers``, else ``$SUNSET_WORKERS``, else the CPU count (at most 2… frames).

    The machine the project targets has two cores; more processes than frames
    or cores buy nothing.
    """
    import os

    if workers is None:
        env = os.environ.get("SUNSET_WORKERS", "")
        workers = int(env) if env.strip().isdigit() else min(2, os.cpu_count() or 1)
    require_int_range("workers", workers, 1)
    return max(1, min(int(workers), int(frames)))


def code_frames(scene: Scene, times, reflections: int = 2, seed: int = 0, workers: int | None = None,
                on_frame=None):
    """Code the frames at ``times`` (seconds), in order, over ``workers`` processes.

    Frames are independent, so they are shared out to a process pool (frames
    i, i + w, … go to whichever worker is free); the results are collected in
    order, and each frame is computed by the same deterministic code as in
    one process, so the codes are byte-identical to the serial path. The first
    frame is rendered here first, so that the workers (forked where the
    platform allows) inherit compiled kernels instead of loading them each.

    Parameters
    ----------
    on_frame : callable, optional
        Called with (index, codes) as each frame arrives (a progress bar).

    Returns
    -------
    ndarray (N, H, W) uint8
    """
    import multiprocessing
    import sys
    from concurrent.futures import ProcessPoolExecutor

    times = [float(t) for t in times]
    cam = scene.camera
    out = np.empty((len(times), cam.height, cam.width), np.uint8)
    n = frame_workers(workers, len(times))

    def put(i, codes):
        out[i] = codes
        if on_frame is not None:
            on_frame(i, codes)

    if not times:
        return out
    put(0, code_frame(scene, times[0], reflections, seed))
    rest = [(scene, t, reflections, seed) for t in times[1:]]
    if n <= 1 or not rest:
        for i, args in enumerate(rest, start=1):
            put(i, code_frame(*args))
        return out
    methods = multiprocessing.get_all_start_methods()
    # fork is cheapest (the children share the loaded kernels); Python 3.12+ warns about forking a
    # process that has threads (BLAS has), so there the forkserver starts the workers
    method = "fork" if "fork" in methods and sys.version_info < (3, 12) else (
        "forkserver" if "forkserver" in methods else "spawn")
    with ProcessPoolExecutor(max_workers=n, mp_context=multiprocessing.get_context(method)) as pool:
        for i, codes in enumerate(pool.map(_code_frame_task, rest), start=1):
            put(i, codes)
    return out
