"""The RGB back end's frame and film, through the pipeline: the rays traced here, shaded by :mod:`sunset.light`.

``--shading rgb`` traces the picture at k times its width and height for
``samples`` = k² rays per pixel (:func:`sunset.light.render.supersampled`),
keeps every ray's :class:`~sunset.light.geometry.Geometry` and shades it
(:mod:`sunset.light.render`). The rays are the vector stage's full frame,
with the sea's bounces (:func:`trace_geometry`); the budget is checked once,
where a frame or a film begins (:func:`sunset.pipeline.budget.rgb_work`), and
its :class:`~sunset.vector.budget.Work` passed down to every frame traced.

A film (:func:`trace_cycle`, :func:`film_frames`) traces one wave cycle once
and re-shades it for every hour (:mod:`sunset.light.film`). What changes
from film frame to film frame is only the hour (each has its own) and which
stored geometry it shows, so the frames are independent: :func:`film_frames`
shares them out to ``workers`` processes (``--jobs``), which inherit the
cycle's geometries, and collects them in order; each frame is computed by
the same code as in one process, so the film is the same bytes for any
number of workers (tests).
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import SunsetError, require_finite, require_instance, require_int_range, require_time
from ..light.film import film_frame
from ..light.geometry import Geometry
from ..light.glitter import Glitter
from ..light.output import check_rgb_output, save_rgb
from ..light.render import check_samples, frame_light, shade_display, shade_scene_linear, supersampled
from ..vector.budget import Work
from .budget import check_geometry_bytes, rgb_work, workers_within_budget
from .frame import render
from .workers import start_method

__all__ = ["trace_geometry", "render_rgb", "write_rgb_frame", "trace_cycle", "film_frames"]


def trace_geometry(scene, t: float = 0.0, reflections: int = 2, samples: int = 1, *,
                   work: Work | None = None) -> Geometry:
    """The vector stage at ``samples`` rays per pixel, kept as a :class:`Geometry` (of the k× finer raster).

    ``work``: the budget of the supersampled frame, checked already where a
    film began (:func:`sunset.pipeline.budget.rgb_work`, once for all its
    frames); by default it is checked here, once, and passed down to the
    vector stage (:func:`sunset.pipeline.frame.render`).
    """
    k = check_samples(samples)
    require_time("t", t)
    if work is None:
        work = rgb_work(scene, samples)                # before the picture is supersampled
    else:
        require_instance("work", work, Work)
    frame = render(supersampled(scene, k) if k > 1 else scene, float(t), reflections, sea_bounces=True, work=work)
    geometry = Geometry.from_frame(frame)
    if scene.sea.wind is not None:       # the sun's glitter off the facets the tile cannot resolve
        geometry.glitter = Glitter.from_frame(frame, scene.sea.wind)
    return geometry


def render_rgb(scene, t: float = 0.0, hours: float = 0.35, samples: int = 1, reflections: int = 2):
    """Linear display RGB (H, W, 3) float64 in [0, 1] of ``scene`` at time ``t``, ``hours`` before sunset.

    Encode with :func:`sunset.light.tone.encode_srgb` for an image.
    """
    k = check_samples(samples)
    require_finite("hours", hours)
    geometry = trace_geometry(scene, t, reflections, samples)
    return shade_display(geometry, frame_light(scene, t, hours), k)


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
    work = rgb_work(scene, samples, frames=len(times))     # the budget, once for the cycle
    check_geometry_bytes(scene, samples, len(times))
    out = []
    with _bar(len(times), "tracing the wave cycle", progress) as bar:
        for t in times:
            out.append(trace_geometry(scene, float(t), reflections, samples, work=work))
            bar.update(1)
    return out


#: What the film's worker processes share: the scene, the cycle's geometries and times, the hours, k.
_FILM: dict = {}


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
        than the memory budget allows (:func:`sunset.pipeline.budget.workers_within_budget`).
    """
    import multiprocessing
    from collections import deque
    from concurrent.futures import ProcessPoolExecutor

    k = check_samples(samples)
    require_int_range("workers", workers, 1)
    hours = [float(h) for h in hours]
    if times is not None:
        times = [float(t) for t in times]
        if len(times) != len(geometries):
            raise SunsetError(f"film: {len(times)} times for {len(geometries)} geometries")
    n = workers_within_budget(min(int(workers), len(hours)), geometries)
    if n <= 1:
        lights: dict = {}
        for j in range(len(hours)):
            yield film_frame(scene, geometries, times, hours, k, j, lights)
        return
    state = {"scene": scene, "geometries": geometries, "times": times, "hours": hours, "k": k}
    method = start_method()
    fork = method == "fork"
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
