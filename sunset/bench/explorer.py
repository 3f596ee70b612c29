"""The explorer's rows of ``make bench`` (:func:`sunset.explore`): one update per moved slider.

An update is what the explorer's render thread does when a control moves:
the view's scene (:func:`~sunset.explorer.settings.scene_for`), its picture
(:class:`~sunset.explorer.picture.Renderer`) and the bytes sent to the
screen (:func:`~sunset.explorer.picture.rgba_for_screen`). Every timed update moves
its slider to a value not rendered before, so no frame is reused where the
explorer would not reuse it: the time and the sun's azimuth trace and code a
new frame (the 8-bit path's whole pipeline), the hours re-expose the frame's
codes, a wave train's amplitude traces the sea anew (the islands' pass kept),
the heading (the slowest 8-bit update) turns the whole world and the sun
about the eye (the islands' pass, the frame, its codes and the colour tables
all made anew), and RGB shading traces and shades a new frame.
"""

from __future__ import annotations

from dataclasses import replace

from .extra import timed

__all__ = ["EXPLORER_SIZE", "measure_explorer"]

#: The explorer's picture, (width, height): the size its updates are timed at.
EXPLORER_SIZE = (512, 512)


def measure_explorer(width: int, height: int, repeats: int) -> dict:
    """Seconds per update of Carla's Island at ``width`` × ``height`` for each kind of slider (after a warm-up)."""
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

    period = start.scene.sea.period or 60.0
    rows = {"time (8-bit)": timed(moved("t", 0.0, period / 97.0), repeats),
            "sun's azimuth (8-bit)": timed(moved("azimuth", view.azimuth, 0.1), repeats)}
    count[0] = 0
    update(t=0.5)                                       # the frame whose codes the hours slider re-exposes
    rows["hours (8-bit)"] = timed(moved("hours", view.hours, 0.01, t=0.5), repeats)
    count[0] = 0
    first = view.trains[0]

    def amplitude() -> None:
        count[0] += 1
        update(trains=(replace(first, amplitude=first.amplitude * (1.0 - 0.01 * count[0])), *view.trains[1:]))

    rows["wave amplitude (8-bit)"] = timed(amplitude, repeats)
    count[0] = 0
    rows["heading (8-bit)"] = timed(moved("heading", 0.0, 0.5), repeats)
    rows["time (RGB)"] = timed(moved("t", 0.0, period / 89.0, shading="rgb"), repeats)
    return rows
