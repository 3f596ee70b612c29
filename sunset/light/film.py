"""Deferred shading over a wave cycle: its geometry traced once, re-shaded for every hour.

The paper's colour-table animation replayed one cycle of codes through the
tables of each hour (:mod:`sunset.recorder.film`). The same idea, generalised:
the :class:`~sunset.light.geometry.Geometry` of each frame of one wave cycle
is kept, and film frame j shows cycle frame j mod N shaded by the light of its
own hour (:class:`~sunset.light.lighting.Lighting`). No ray is traced twice;
per film frame only the hour's light (its sky grid) and the shading are
computed: the light of its hour (:func:`sunset.light.render.frame_light`, with
the ripples on the posts at its cycle frame's time, so that a film frame is
the same bytes as the single frame ``sunset render --shading rgb`` makes for
that time and hour) and the shading. The geometries are held in memory, so
their size is bounded (:data:`MAX_GEOMETRY_BYTES`).

What changes from film frame to film frame is only the hour (each has its
own) and which stored geometry it shows, so the frames are independent:
:func:`film_frames` shares them out to ``workers`` processes (``--jobs``),
which inherit the cycle's geometries, and collects them in order; each frame
is computed by the same code as in one process, so the film is the same bytes
for any number of workers (tests). ``sunset film --shading rgb`` puts these
together with the cycle's times and the film's hours and encoder.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import SunsetError, require_finite, require_int_range
from .lighting import Lighting
from .output import check_rgb_output, save_rgb, to_uint8
from .render import check_samples, frame_light, shade_display, shade_scene_linear, trace_geometry

__all__ = ["MAX_GEOMETRY_BYTES", "GEOMETRY_BYTES_PER_RAY", "write_rgb_frame", "trace_cycle", "film_frame", "film_frames"]

#: Most bytes the stored geometries of one cycle may take.
MAX_GEOMETRY_BYTES = 3 * 2**30
#: A bound on one ray's stored geometry (final ray, normal, kind, throughput, sky lookup, up to three water bounces).
GEOMETRY_BYTES_PER_RAY = 112


def write_rgb_frame(scene, path, t: float = 0.0, hours: float = 0.35, samples: int = 1, reflections: int = 2,
                    depth: int = 8, metadata: dict | None = None) -> Path:
    """Render one RGB frame and write it (PNG 8/16 bit or float32 .npy, :mod:`sunset.light.output`)."""
    path = check_rgb_output(path, depth)
    k = check_samples(samples)
    require_finite("hours", hours)
    geometry = trace_geometry(scene, t, reflections, samples)
    light = frame_light(scene, t, hours)
    if path.suffix.lower() == ".npy":
        return save_rgb(path, None, shade_scene_linear(geometry, light, k), depth=depth)
    return save_rgb(path, shade_display(geometry, light, k), depth=depth, metadata=metadata)


def _bar(total: int, desc: str, progress: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="frame", file=sys.stderr, disable=not progress, leave=False)


def trace_cycle(scene, times, reflections: int = 2, samples: int = 1, progress: bool = True) -> list:
    """The geometries of the frames at ``times`` (one wave cycle), each traced once."""
    require_int_range("reflections", reflections, 0, 2)
    check_samples(samples)
    from .budget import check_rgb_work

    check_rgb_work(scene, samples, frames=len(times))
    cam = scene.camera
    need = len(times) * cam.width * cam.height * samples * GEOMETRY_BYTES_PER_RAY
    if need > MAX_GEOMETRY_BYTES:
        per = f"{samples} sample{'s' * (samples != 1)} per pixel"
        raise SunsetError(f"frames: {len(times)} frames at {cam.width}x{cam.height}, {per}, would keep up to "
                          f"{need / 2**30:.1f} GiB of geometry (at most "
                          f"{MAX_GEOMETRY_BYTES / 2**30:g} GiB): use fewer frames, fewer samples or a smaller picture")
    out = []
    with _bar(len(times), "tracing the wave cycle", progress) as bar:
        for t in times:
            out.append(trace_geometry(scene, float(t), reflections, samples))
            bar.update(1)
    return out


#: What the film's worker processes share: the scene, the cycle's geometries and times, the hours, k.
_FILM: dict = {}


#: Most lights :func:`film_frames` keeps for frames that come back to the same time and hour.
LIGHT_CACHE = 64


def film_frame(scene, geometries, times, hours, k: int, j: int, lights: dict | None = None):
    """Film frame j, sRGB (H, W, 3) uint8: geometry j mod N, traced at ``times[j mod N]``, shaded for ``hours[j]``.

    ``times`` None: the light of the hour alone (:meth:`Lighting.for_scene`, no ripples on the posts).
    ``lights``: a dict that keeps the light of each (time, hour) met, so that a film whose hours repeat (a
    film at one hour) computes each light once (at most :data:`LIGHT_CACHE` of them).
    """
    n = len(geometries)
    t = None if times is None else float(times[j % n])
    key = (t, float(hours[j]))
    light = None if lights is None else lights.get(key)
    if light is None:
        light = Lighting.for_scene(scene, key[1]) if t is None else frame_light(scene, t, key[1])
        if lights is not None:
            if len(lights) >= LIGHT_CACHE:
                lights.pop(next(iter(lights)))
            lights[key] = light
    return to_uint8(shade_display(geometries[j % n], light, k))


def _film_task(j: int):
    from ..kernels import use_threads

    with use_threads(1):                  # the frames run side by side in the processes, one thread each
        return film_frame(_FILM["scene"], _FILM["geometries"], _FILM["times"], _FILM["hours"], _FILM["k"], j,
                          _FILM.setdefault("lights", {}))


def _start_film_worker(state) -> None:
    import signal

    # Ctrl-C reaches the whole process group: only the parent reports it and stops the film
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_IGN)
    if state is not None:                 # a spawned worker gets the state pickled; a forked one has it already
        _FILM.update(state)


def _workers_within_budget(n: int, geometries) -> int:
    """At most ``n`` workers that, each shading one frame, keep the film within MAX_FRAME_BYTES.

    The cycle's geometries are held once (the workers are forked and share them); each worker adds one
    frame's light and shading (:func:`sunset.light.budget.rgb_bytes` with no geometry kept), and its own copy
    of the geometries where the workers cannot be forked. A large film is shaded by fewer processes rather
    than by more memory than the budget.
    """
    import multiprocessing
    import sys

    from ..constants import MAX_FRAME_BYTES, RGB_BYTES_PER_RAY, RGB_LIGHT_BYTES

    if n <= 1 or not geometries:
        return max(1, n)
    kept = sum(g.nbytes for g in geometries)
    per_worker = RGB_LIGHT_BYTES + geometries[0].final_kind.size * RGB_BYTES_PER_RAY
    if not ("fork" in multiprocessing.get_all_start_methods() and sys.version_info < (3, 12)):
        per_worker += kept
    return max(1, min(n, (MAX_FRAME_BYTES - kept) // per_worker))


def film_frames(scene, geometries, hours, samples: int = 1, times=None, workers: int = 1):
    """Yield an sRGB frame (H, W, 3) uint8 per entry of ``hours``: geometry j mod N shaded for hour j.

    Parameters
    ----------
    times : sequence of float, optional
        The cycle's times, one per geometry: each frame then gets the ripples
        of light on the posts at its time (:func:`film_frame`).
    workers : int
        Processes that shade the frames (1: here, one after the other). They
        are forked where the platform allows and inherit the geometries; at
        most 2 × ``workers`` frames are in flight, and no more workers run
        than the memory budget allows (:func:`_workers_within_budget`).
    """
    import multiprocessing
    import sys
    from collections import deque
    from concurrent.futures import ProcessPoolExecutor

    k = check_samples(samples)
    require_int_range("workers", workers, 1)
    hours = [float(h) for h in hours]
    if times is not None:
        times = [float(t) for t in times]
        if len(times) != len(geometries):
            raise SunsetError(f"film: {len(times)} times for {len(geometries)} geometries")
    n = _workers_within_budget(min(int(workers), len(hours)), geometries)
    if n <= 1:
        lights: dict = {}
        for j in range(len(hours)):
            yield film_frame(scene, geometries, times, hours, k, j, lights)
        return
    state = {"scene": scene, "geometries": geometries, "times": times, "hours": hours, "k": k}
    methods = multiprocessing.get_all_start_methods()
    fork = "fork" in methods and sys.version_info < (3, 12)      # as sunset.tape.cycle.code_frames chooses
    method = "fork" if fork else ("forkserver" if "forkserver" in methods else "spawn")
    _FILM.clear()
    _FILM.update(state)
    pool = ProcessPoolExecutor(max_workers=n, mp_context=multiprocessing.get_context(method),
                               initializer=_start_film_worker, initargs=(None if fork else state,))
    try:
        pending = deque()
        following = 0
        while following < len(hours) and len(pending) < 2 * n:
            pending.append(pool.submit(_film_task, following))
            following += 1
        while pending:
            yield pending.popleft().result()
            if following < len(hours):
                pending.append(pool.submit(_film_task, following))
                following += 1
    except BaseException:                 # Ctrl-C, an error, the consumer gone: no new frames
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    finally:
        _FILM.clear()
    pool.shutdown(wait=True)
