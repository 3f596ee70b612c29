"""The explorer's rows of ``make bench`` (:func:`sunset.explore`): one update per moved slider.

An update is what the explorer's render thread does when a control moves:
the view's scene (:func:`~sunset.explorer.settings.scene_for`), its picture
(:class:`~sunset.explorer.picture.Renderer`) and the bytes sent to the
screen (:func:`~sunset.explorer.picture.rgba_for_screen`). Every timed update moves
its slider to a value not rendered before, so no frame is reused where the
explorer would not reuse it: the time and a wave train's amplitude trace and
code the sea anew (the still part of the cycle, the islands' and the sky's
codes, kept), the sun's azimuth codes the last traced frame again and
exposes it through new colour tables, the hours re-expose the frame's codes,
the heading (the slowest 8-bit update) turns the whole world and the sun
about the eye (the islands' pass, the frame, its codes and the colour tables
all made anew), and RGB shading traces and shades a new frame. Each row
holds the updates' wall-clock seconds and their CPU seconds (every thread's):
the wall clock says what a reader waits on this machine as loaded as it
is, the CPU what an update costs whatever else runs.
"""

from __future__ import annotations

import time
from dataclasses import replace

__all__ = ["EXPLORER_SIZE", "measure_explorer"]

#: The explorer's picture, (width, height): the size its updates are timed at.
EXPLORER_SIZE = (512, 512)


def timed_with_cpu(fn, repeats: int, cpu: list) -> list[float]:
    """Wall-clock seconds of ``repeats`` calls of ``fn`` after one warm-up call; their CPU seconds appended to ``cpu``.

    The CPU seconds are the process's, every thread's together: the work of
    an update, whatever else the machine runs (on an idle machine an update
    takes about that long, or less where its threads share the work).
    """
    fn()
    times = []
    for _ in range(repeats):
        wall, cpu0 = time.perf_counter(), time.process_time()
        fn()
        times.append(time.perf_counter() - wall)
        cpu.append(time.process_time() - cpu0)
    return times


def measure_explorer(width: int, height: int, repeats: int) -> dict:
    """Seconds per update of Carla's Island at ``width`` × ``height`` for each kind of slider (after a warm-up).

    ``{stage: [wall seconds]}``, and under ``"cpu"`` ``{stage: [CPU seconds]}`` of the same updates.
    """
    from ..explorer.picture import Renderer, rgba_for_screen
    from ..explorer.settings import Start
    from ..kernels import keep_freed_memory

    keep_freed_memory()
    start = Start.of("carlas-island", size=(width, height))
    renderer = Renderer(start)
    view = start.view
    count = [0]

    def update(**change) -> None:
        rgba_for_screen(renderer(replace(view, **change)).rgb)

    def moved(name: str, first: float, step: float, **fixed):
        def once() -> None:
            count[0] += 1
            update(**{name: first + step * count[0]}, **fixed)
        return once

    cpu: dict[str, list[float]] = {}

    def timed(stage: str, fn) -> None:
        rows[stage] = timed_with_cpu(fn, repeats, cpu.setdefault(stage, []))

    period = start.scene.sea.period or 60.0
    rows: dict = {}
    timed("time (8-bit)", moved("t", 0.0, period / 97.0))
    timed("sun's azimuth (8-bit)", moved("azimuth", view.azimuth, 0.1))
    count[0] = 0
    update(t=0.5)                                       # the frame whose codes the hours slider re-exposes
    timed("hours (8-bit)", moved("hours", view.hours, 0.01, t=0.5))
    count[0] = 0
    first = view.trains[0]

    def amplitude() -> None:
        count[0] += 1
        update(trains=(replace(first, amplitude=first.amplitude * (1.0 - 0.01 * count[0])), *view.trains[1:]))

    timed("wave amplitude (8-bit)", amplitude)
    count[0] = 0
    timed("heading (8-bit)", moved("heading", 0.0, 0.5))
    timed("time (RGB)", moved("t", 0.0, period / 89.0, shading="rgb"))
    return {**rows, "cpu": cpu}
