"""The explorer's pictures: one view rendered (:class:`Renderer`), read under the pointer, saved as a scene.

A picture of the 8-bit path is what :func:`sunset.picture` makes of the
view's scene (``code_frame`` then ``expose``: the same bytes), and one of
the RGB back end what ``sunset render --shading rgb`` writes (one sample per
pixel). The renderer keeps what the next view may share: the last codes
(a view that changes only the hour is exposed again without tracing a ray,
as the film recorder re-exposes a tape), the islands' pass and the still
part of a wave cycle (the time slider traces only the sea), the last traced
frame or the RGB back end's geometry (the vector stage never looks at the
sun: a view that moves only the sun is coded or shaded again). Every picture
is the same bytes as one rendered afresh.

:func:`readout` says what a pixel's code means, as the colour-table player's
inspector does (:func:`sunset.recorder.player.code_meanings`), and
:func:`scene_text` writes the view as a scene file whose comment gives the
command that renders the same picture from it, byte for byte.
"""

from __future__ import annotations

import functools
import shlex
import time
from dataclasses import dataclass

import numpy as np

from .. import __version__
from ..errors import SunsetError, require_int_range
from ..model.scene import Scene
from .settings import Start, View, scene_for

__all__ = ["Picture", "Renderer", "readout", "scene_text", "rgba_for_screen"]


@dataclass(frozen=True, eq=False)
class Picture:
    """One rendered view: the scene and view it shows, its RGB bytes, its codes (8-bit path) and its time."""

    scene: Scene
    view: View
    rgb: np.ndarray
    codes: np.ndarray | None
    seconds: float


class Renderer:
    """Renders views of one start (:func:`~sunset.explorer.settings.scene_for`), keeping what the next can reuse."""

    def __init__(self, start: Start):
        self.start = start
        self._key = None
        self._codes = None
        self._geometry = None
        self._still = None
        self._islands = None
        self._last_still_key = None
        self._frame = None

    def __call__(self, view: View) -> Picture:
        """The picture of ``view``; raises :class:`~sunset.SunsetError` for a setting the scene refuses."""
        began = time.perf_counter()
        scene = scene_for(self.start, view)
        if view.shading == "codes":
            from ..pipeline.frame import expose

            key = (scene, float(view.t), view.reflections, view.seed)
            if key != self._key:
                self._key, self._codes = key, self._code(scene, float(view.t), view.reflections, view.seed)
            rgb = expose(scene, self._codes, view.hours)
            codes = self._codes
        else:
            from ..light.output import to_uint8
            from ..light.render import frame_light, shade_display
            from ..pipeline.rgb import trace_geometry

            key = (_sunless(scene), float(view.t), view.reflections, "rgb")
            if key != self._key:
                self._key, self._geometry = key, trace_geometry(scene, float(view.t), view.reflections, 1)
            # what render_rgb does, the geometry traced once for every hour and every place of the sun
            rgb = to_uint8(shade_display(self._geometry, frame_light(scene, float(view.t), view.hours), 1))
            codes = None
        return Picture(scene, view, rgb, codes, time.perf_counter() - began)

    def _code(self, scene: Scene, t: float, reflections: int, seed: int) -> np.ndarray:
        """The 8-bit codes of ``scene`` at ``t``: :func:`sunset.pipeline.frame.code_frame`'s bytes, made from what is kept.

        With the still part of the wave cycle (:meth:`_still_part`) only the
        sea is traced and coded. Otherwise the frame is traced (or, when only
        the sun moved, the last frame taken again: the vector stage never looks
        at the sun) and coded, as ``code_frame`` does.
        """
        from ..pipeline.frame import CyclePass, code_frame, encode, render

        shared = self._still_part(scene, seed)
        if isinstance(shared, CyclePass) and scene.clouds is None and not scene.posts:
            return code_frame(scene, t, reflections, seed, shared)
        islands = shared.islands if isinstance(shared, CyclePass) else shared
        key = (_sunless(scene), t, reflections)
        if self._frame is None or self._frame[0] != key:
            self._frame = (key, render(scene, t, reflections, islands=islands, sea_bounces=False))
        return encode(scene, self._frame[1], seed=seed)

    def _still_part(self, scene: Scene, seed: int):
        """What this frame can share with the last ones: a :class:`~sunset.pipeline.frame.CyclePass`, or the islands' pass.

        The islands' pass (:func:`sunset.pipeline.frame.island_pass`) is kept
        while the camera, the islands and the sea's height stay. The still part
        of a wave cycle (:func:`sunset.pipeline.cycle.cycle_pass`: the islands' and
        the sky's codes) costs most of a frame to make and saves less: it is
        made for the second frame in a row that can share it (the time
        slider, a train's direction) and kept while it can be. The codes are
        the same bytes either way (:func:`sunset.pipeline.frame.code_frame`).
        """
        from ..pipeline.cycle import cycle_pass, still_key
        from ..pipeline.frame import island_pass

        key = still_key(scene, seed)
        if self._still is not None and self._still.key == key:
            return self._still
        if self._islands is None or self._islands[0] != key[0]:
            self._islands = (key[0], island_pass(scene))
        if self._last_still_key == key:
            self._still = cycle_pass(scene, seed, self._islands[1])
            return self._still
        self._last_still_key = key
        return self._islands[1]


def _sunless(scene: Scene) -> Scene:
    """``scene`` with a standard sun: what the vector stage sees of it (it traces no ray toward the sun)."""
    from dataclasses import replace

    from ..model.sun import Sun

    return replace(scene, sun=Sun())


def rgba_for_screen(rgb: np.ndarray) -> bytes:
    """The picture as the widget's canvas takes it: rows of RGBA bytes, alpha 255 (``ImageData``'s layout).

    No image file is made: an encoder would cost a third of an update (Pillow's
    PNG at 512 × 512), and the bytes go straight into the canvas, unchanged.
    """
    height, width = rgb.shape[:2]
    out = np.empty((height, width, 4), dtype=np.uint8)
    out[..., :3] = rgb
    out[..., 3] = 255
    return out.tobytes()


@functools.lru_cache(maxsize=4)
def _meanings(scene: Scene) -> tuple[list[str], object]:
    from ..recorder.player import code_meanings
    from ..tape.codes import code_map

    cmap = code_map(scene)
    return code_meanings(scene.sun, cmap, scene.clouds), cmap


def readout(picture: Picture, col: int, row: int) -> str:
    """What the pixel (col, row) of ``picture`` shows, in three lines (the player's code inspector).

    The 8-bit path: the pixel's code and its group, what the code's number
    says, and the colour table's entry at the view's hour beside the colour
    drawn (they differ only in the sun's disk). The RGB back end writes no
    codes: its pixel's colour only.
    """
    height, width = picture.rgb.shape[:2]
    require_int_range("col", col, 0, width - 1)
    require_int_range("row", row, 0, height - 1)
    drawn = ", ".join(str(int(v)) for v in picture.rgb[row, col])
    if picture.codes is None:
        return (f"pixel ({col}, {row}): drawn ({drawn}) by the RGB back end\n"
                "the RGB back end writes no codes: 8-bit shading shows the code map")
    from ..recorder.colour_tables import tables

    code = int(picture.codes[row, col])
    meanings, cmap = _meanings(picture.scene)
    group = cmap.ranges[int(cmap.group(code))]
    entry = tables(picture.scene.sun, picture.view.hours, picture.scene.clouds)[:, code]
    return (f"pixel ({col}, {row}): code {code}, {group.name} (codes {group.start}–{group.stop - 1})\n"
            f"{meanings[code]}\n"
            f"table entry at this hour: red {entry[0]}, green {entry[1]}, blue {entry[2]}; drawn ({drawn})")


def _command(view: View, name: str) -> str:
    """The ``sunset render`` command that draws ``view``'s picture from the scene file ``name``."""
    shading = " --shading rgb" if view.shading == "rgb" else ""
    seed = "" if view.shading == "rgb" else f" --seed {view.seed}"
    return (f"sunset render {shlex.quote(name)}{shading} --time={float(view.t)!r} --hours={float(view.hours)!r} "
            f"--reflections {view.reflections}{seed} -o picture.png")


def scene_text(picture: Picture, name: str = "scene.toml") -> str:
    """The picture's scene as TOML, headed by the command that renders the same picture from it.

    ``name`` is the file's name as the command should give it. The scene's
    camera has the picture's size, so ``sunset render`` (and ``film``,
    ``player``) draw it at that size; the hours, time, reflections, shading
    and seed are not the scene's, and the comment gives them.
    """
    if any(c in name for c in "\n\r"):
        raise SunsetError(f"name must be one line, got {name!r}")
    view = picture.view
    python = (f"sunset.picture({name!r}, t={float(view.t)!r}, hours={float(view.hours)!r}, size=None, "
              f"reflections={view.reflections}, seed={view.seed})")
    lines = [f"# Saved by sunset.explore (sunset {__version__}). The explorer's picture again, byte for byte:",
             f"#   {_command(view, name)}"]
    if view.shading == "codes":
        lines.append(f"#   or in Python: {python}")
    return "\n".join(lines) + "\n" + picture.scene.to_toml()
