"""A profile of one frame for ``make bench``: the functions where its time goes (cProfile)."""

from __future__ import annotations

from pathlib import Path


def _measure_profile(width: int, height: int, repeats: int) -> dict:
    """cProfile of ``repeats`` frames: the functions with the most time of their own."""
    import cProfile
    import pstats

    from ..model.scene import Scene
    from .frame import _frame_once

    scene = Scene.default().with_size(width, height)
    _frame_once(scene)
    prof = cProfile.Profile()
    prof.enable()
    for _ in range(repeats):
        _frame_once(scene)
    prof.disable()
    stats = pstats.Stats(prof).stats
    total = sum(v[2] for v in stats.values())
    rows = []
    for (file, line, name), (_cc, _nc, tottime, cumtime, _callers) in stats.items():
        rows.append({"function": _function_name(file, name), "own_s": tottime / repeats, "share": tottime / total})
    rows.sort(key=lambda r: -r["own_s"])
    return {"profile": rows[:15], "profile_total_s": total / repeats}


def _function_name(file: str, name: str) -> str:
    """A readable name for a cProfile entry: ``module.py:function``, or the NumPy method / built-in."""
    import re

    if file.startswith(("/", ".")):
        return f"{Path(file).name}:{name}"
    m = re.match(r"<method '(\w+)' of '([\w.]+)' objects>", name)
    if m:
        return f"{m.group(2)}.{m.group(1)}"
    m = re.match(r"<built-in method ([\w.]+)>", name)
    return m.group(1) if m else name
