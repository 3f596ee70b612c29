"""Figures 4–7 of the paper: one pipeline, three reflection modes, two lightings.

Figure 4: still water (mirror reflections), Figure 5: one reflection with
|R_z|, Figure 6: two reflections, all near sunset; Figure 7: Figure 6's tape
through early-afternoon colour tables, with no re-rendering.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import __version__
from ..pipeline.frame import expose
from ..errors import require_int_range
from ..io import save_png
from ..model.scene import Scene
from . import shared
from ..tape.tapefile import Tape, read_tape, write_tape

#: Hours before sunset for the sunset figures (4, 5, 6) and for Figure 7.
SUNSET_HOURS = 0.35
AFTERNOON_HOURS = 4.5


@dataclass(frozen=True)
class PaperFigure:
    """How one of the paper's figures is made."""

    number: str
    caption: str
    still: bool
    reflections: int
    hours: float
    reuses: str | None = None


PAPER_FIGURES = {
    "4": PaperFigure("4", "Islands near sunset in still water.", True, 1, SUNSET_HOURS),
    "5": PaperFigure("5", "Islands near sunset with one reflection from waves.", False, 1, SUNSET_HOURS),
    "6": PaperFigure("6", "Islands near sunset allowing two reflections from waves.", False, 2, SUNSET_HOURS),
    "7": PaperFigure("7", "The same data as in figure 6, with early afternoon lighting.", False, 2, AFTERNOON_HOURS,
                     reuses="6"),
}


def png_metadata(scene: Scene, settings: dict) -> dict[str, str]:
    """What every PNG records of its making: the scene and the settings; the writer adds the versions and the
    kernels' path when it writes (:func:`sunset.provenance.stamped`: after the picture is made, so the path is
    the one its kernels took)."""
    return {
        "Software": f"sunset {__version__}",
        "sunset:settings": json.dumps(settings, sort_keys=True),
        "sunset:scene": scene.to_toml(),
    }


def render_tape(scene: Scene, t: float, reflections: int, seed: int) -> Tape:
    """The vector stage for one frame: render, then code to 8 bits (:func:`sunset.figures.shared.codes`)."""
    codes = shared.codes(scene, t, reflections, seed)
    return Tape(scene=scene, codes=codes[None], times=np.array([t]), reflections=reflections, seed=seed)


def expose_png(tape: Tape, hours: float, path: Path, frame: int = 0, extra: dict | None = None,
               rgb: np.ndarray | None = None) -> Path:
    """The film-recorder stage for one frame of a tape, written as a PNG (``rgb``: that exposure, made already)."""
    require_int_range("frame", frame, 0, len(tape) - 1)
    if rgb is None:
        rgb = expose(tape.scene, tape.codes[frame], hours)
    settings = {"t": float(tape.times[frame]), "reflections": tape.reflections, "seed": tape.seed,
                "hours": float(hours), **(extra or {})}
    return save_png(path, rgb, png_metadata(tape.scene, settings))


def paper_figure(number: str, out: Path, scene: Scene, seed: int = 0,
                 t: float = 0.0, reuse_from: Path | None = None) -> Path:
    """Write figure ``number`` (4–7) as ``out/figN.png``.

    Figure 6 also leaves ``fig6.tape``.

    Figure 7 reads ``fig6.tape`` when it is there (in ``out``, else in
    ``reuse_from``) and matches the scene, and renders it once otherwise: it
    never re-renders what Figure 6 computed.
    """
    spec = PAPER_FIGURES[number]
    out = Path(out)
    source = spec.reuses or number
    tape_path = out / f"fig{source}.tape"
    tape = None
    places = [tape_path] if spec.reuses else []
    if spec.reuses and reuse_from is not None:
        places.append(Path(reuse_from) / tape_path.name)
    for place in places:
        if not place.is_file():
            continue
        cached = read_tape(place)
        same = cached.scene == scene and cached.seed == seed
        if same and float(cached.times[0]) == t:
            tape = cached
            break
    rgb = None
    if tape is None:
        src = PAPER_FIGURES[source]
        source_scene = scene.still() if src.still else scene
        tape = render_tape(source_scene, t, src.reflections, seed)
        # another figure re-exposes it
        if any(f.reuses == source for f in PAPER_FIGURES.values()):
            write_tape(tape_path, tape)
        # (the RGB Figure 6 shows the same exposure beside its own)
        rgb = shared.exposure(source_scene, t, src.reflections, seed, spec.hours)
    return expose_png(tape, spec.hours, out / f"fig{number}.png",
                      extra={"figure": number}, rgb=rgb)
