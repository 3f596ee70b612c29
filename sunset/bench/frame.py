"""One Figure 6 frame for ``make bench``, stage by stage (the frame's rows and what the profile times)."""

from __future__ import annotations

import time


def _frame_once(scene, t: float = 0.0) -> dict:
    """One Figure 6 frame, stage by stage: seconds per stage (see :data:`sunset.bench.STAGES`), and the CPU time of all threads.

    ``cpu time`` over ``total`` is how many cores the frame kept busy on
    average. (On a machine shared by several login sessions, Linux's
    autogroup scheduler gives each session a share of the CPUs, so a loaded
    machine lends a frame's second thread little extra time.)
    """
    from ..pipeline.frame import encode, expose, trace_direct, trace_reflections

    info: dict = {}
    c0 = time.process_time()
    t0 = time.perf_counter()
    frame = trace_direct(scene, t, info=info)
    t1 = time.perf_counter()
    # the 8-bit pipeline: the RGB back end's fields are not made; Frame.finish_direct is
    # trace_reflections' (which leaves the rows that are all sea to the reflected rays)
    trace_reflections(scene, frame, 2, sea_bounces=False)
    t2 = time.perf_counter()
    codes = encode(scene, frame, seed=0)
    t3 = time.perf_counter()
    expose(scene, codes, 0.35)
    t4 = time.perf_counter()
    c4 = time.process_time()
    sec = info["seconds"]
    direct_other = (t1 - t0) - sum(sec.values())  # bookkeeping: with the points
    return {"sea scan line": sec["sea"], "islands": sec["islands"],
            "points & normals": sec["assemble"] + direct_other, "reflections": t2 - t1, "codes": t3 - t2,
            "film recorder": t4 - t3, "vector stage": t3 - t0, "total": t4 - t0, "cpu time": c4 - c0}


def _measure_frame(width: int, height: int, repeats: int) -> dict:
    """Time a Figure 6 frame (two reflections, default scene), stage by stage."""
    from ..model.scene import Scene

    scene = Scene.default().with_size(width, height)
    _frame_once(scene)  # warm-up (and the compiled kernels' load)
    runs = [_frame_once(scene) for _ in range(repeats)]
    return {k: [r[k] for r in runs] for k in runs[0]}


#: The two ways to a frame's picture that the "paths" rows time, in the order they run.
PATHS = ("8-bit path", "API")


def _paths_once(scene, t: float = 0.0) -> dict:
    """One Figure 6 frame's picture two ways, one after the other: seconds of each.

    ``8-bit path``: :func:`~sunset.pipeline.frame.code_frame` (the strips
    traced and coded in one pass each, what the figures and the film run)
    then :func:`~sunset.pipeline.frame.expose`; ``API``: the public
    ``sunset.render`` → ``sunset.encode`` → ``sunset.expose``, the whole
    :class:`~sunset.vector.frame.Frame` made on the way (without the sea's
    bounces, which ``render`` records only when asked).
    """
    import sunset
    from ..pipeline.frame import code_frame, expose

    t0 = time.perf_counter()
    expose(scene, code_frame(scene, t), 0.35)
    t1 = time.perf_counter()
    sunset.expose(scene, sunset.encode(scene, sunset.render(scene, t, 2)), 0.35)
    t2 = time.perf_counter()
    return {"8-bit path": t1 - t0, "API": t2 - t1}


def _measure_paths(width: int, height: int, repeats: int) -> dict:
    """Time a Figure 6 frame's picture by the 8-bit path and by the public API, in the same process."""
    from ..model.scene import Scene

    scene = Scene.default().with_size(width, height)
    _paths_once(scene)  # warm-up (and the compiled kernels' load)
    runs = [_paths_once(scene) for _ in range(repeats)]
    return {k: [r[k] for r in runs] for k in PATHS}
