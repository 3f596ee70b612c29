"""The explorer as widgets: sliders and buttons (ipywidgets), the picture (anywidget), a render thread.

Every control's change puts the controls' :class:`~sunset.explorer.settings.View`
in the render thread's slot (:class:`~sunset.explorer.worker.Latest`: the
newest request wins); the thread renders it (:class:`~sunset.explorer.picture.Renderer`)
and shows the picture, or, for a setting the scene refuses, shows the error's
one line and keeps the last good picture. The picture's front end
(``picture.js``) reports the pixel under the pointer; Python answers with
what its code means (:func:`~sunset.explorer.picture.readout`).
"""

from __future__ import annotations

import html
import math
import os
from importlib import resources
from pathlib import Path

import anywidget
import ipywidgets as w
import traitlets

from ..constants import MIN_WAVELENGTH
from ..errors import SunsetError
from .picture import Picture, Renderer, readout, rgba_for_screen, scene_text
from .settings import Start, TrainControl, View, cannot_turn
from .worker import Latest

__all__ = ["PictureView", "Explorer", "RUNG_MAX", "SNAP"]

#: The highest rung a train's slider offers (λ₁/16² = λ₁/256).
RUNG_MAX = 16
#: A slider's value this close to its first value (relative, or absolute below 1) is its first value.
SNAP = 1e-9


class PictureView(anywidget.AnyWidget):
    """The picture (``rgba``: rows of RGBA bytes, ``width`` × ``height``), and the pixel under the pointer.

    ``pointer`` is [col, row] (or [] off the picture); ``readout`` what Python
    says of it; ``serial`` which picture is shown (counted from 1).
    """

    _esm = resources.files("sunset.explorer").joinpath("picture.js").read_text(encoding="utf-8")
    rgba = traitlets.Bytes(b"").tag(sync=True)
    width = traitlets.Int(512).tag(sync=True)
    height = traitlets.Int(512).tag(sync=True)
    serial = traitlets.Int(0).tag(sync=True)
    pointer = traitlets.List(traitlets.Int(), []).tag(sync=True)
    readout = traitlets.Unicode("").tag(sync=True)


def _slider(description: str, value: float, lo: float, hi: float, step: float, fmt: str = ".2f") -> w.FloatSlider:
    """A float slider whose range holds ``value`` (a scene's own value is never clamped)."""
    return w.FloatSlider(value=value, min=min(lo, value), max=max(hi, value), step=step, description=description,
                         readout_format=fmt, continuous_update=True, style={"description_width": "9em"},
                         layout=w.Layout(width="26em"))


class Explorer(w.HBox):
    """An explorer of one scene (made by :func:`sunset.explore`).

    Attributes
    ----------
    controls : dict of str to widget
        ``hours``, ``t``, ``azimuth``, ``trains[i].amplitude``, ``trains[i].rung``,
        ``trains[i].direction`` for each wave train i, ``eye_height``, ``heading``,
        ``pitch``, ``reflections`` and ``shading``: set a control's ``value`` and
        the picture follows.
    picture : Picture or None
        The picture shown (the last good one).
    error : str
        The message of the newest request's error, "" when it rendered.
    image : PictureView
        The picture's widget.
    """

    def __init__(self, start: Start, renderer=None):
        self.start = start
        self.renderer = renderer if renderer is not None else Renderer(start)
        self.picture: Picture | None = None
        self.error = ""
        v = start.view
        sea = start.scene.sea
        period = sea.period
        c = {
            "hours": _slider("hours to sunset", v.hours, -1.0, 6.0, 0.01),
            "t": _slider("time (s)", v.t, 0.0, period if period else 60.0, 0.01),
            "azimuth": _slider("sun's azimuth (°)", v.azimuth, -45.0, 45.0, 0.1, ".1f"),
        }
        c["t"].disabled = period == 0.0
        for i, (train, ctl) in enumerate(zip(sea.trains, v.trains)):
            rungs = max(ctl.rung, min(RUNG_MAX, int(math.sqrt(start.fundamental / MIN_WAVELENGTH))))
            c[f"trains[{i}].amplitude"] = _slider(f"train {i + 1} a (m)", ctl.amplitude, 0.0,
                                                  max(1.0, 2.0 * ctl.amplitude), 0.001, ".3f")
            c[f"trains[{i}].rung"] = w.IntSlider(value=ctl.rung, min=1, max=rungs, description=f"train {i + 1} rung",
                                                 continuous_update=True, style={"description_width": "9em"},
                                                 layout=w.Layout(width="26em"))
            c[f"trains[{i}].direction"] = _slider(f"train {i + 1} dir. (°)", ctl.direction, 0.0, 360.0, 1.0, ".0f")
        c["eye_height"] = _slider("eye height (m)", v.eye_height, 0.5, 50.0, 0.1, ".1f")
        c["heading"] = _slider("heading (°)", v.heading, -90.0, 90.0, 0.5, ".1f")
        fixed = cannot_turn(start.scene)          # clouds or a wind sea: their cells and tile lie along x and y
        c["heading"].disabled = fixed is not None
        c["heading"].tooltip = fixed or "turn the eye to the right, degrees"
        c["pitch"] = _slider("pitch (°)", v.pitch, -30.0, 30.0, 0.1, ".1f")
        c["reflections"] = w.ToggleButtons(options=[0, 1, 2], value=v.reflections, description="reflections",
                                           style={"description_width": "9em", "button_width": "3em"})
        c["shading"] = w.ToggleButtons(options=[("8-bit", "codes"), ("RGB", "rgb")], value=v.shading,
                                       description="shading", style={"description_width": "9em",
                                                                     "button_width": "5em"})
        self.controls = c
        width, height = start.size
        self.image = PictureView(width=width, height=height)
        self.status = w.HTML("rendering ...")
        self.file = w.Text(value="explored.toml", description="scene file", style={"description_width": "9em"},
                           layout=w.Layout(width="26em"))
        self.save_button = w.Button(description="save scene", tooltip="write these settings as a scene TOML file")
        self.saved = w.HTML("")
        self._serial = 0
        self._worker = Latest(self.renderer, self._deliver)
        for control in c.values():
            control.observe(self._changed, names="value")
        self.image.observe(self._pointed, names="pointer")
        self.save_button.on_click(lambda _: self._save_clicked())
        trains = [c[k] for k in c if k.startswith("trains[")]
        panel = w.VBox([w.HTML("<b>The sun and the time</b>"), c["hours"], c["t"], c["azimuth"],
                        w.HTML("<b>The sea</b>"), *trains,
                        w.HTML("<b>The camera</b>"), c["eye_height"], c["heading"], c["pitch"],
                        w.HTML("<b>The picture</b>"), c["reflections"], c["shading"],
                        w.HBox([self.file, self.save_button]), self.saved])
        super().__init__([w.VBox([self.image, self.status]), panel])
        self._submitted = self.settings()
        self._worker.submit(self._submitted)

    # -- the controls -----------------------------------------------------------------
    def settings(self) -> View:
        """The controls' values now, as a :class:`~sunset.explorer.settings.View`.

        A slider's front end puts its value on its grid (min + k·step, in
        floating point) and sends it back: −6.800000000000001 for −6.8. A value
        within :data:`SNAP` of the control's first value is taken as that value,
        so that a slider left alone leaves the scene's own number (and its
        picture) as they were.
        """
        c, v0 = self.controls, self.start.view

        def value(name: str, first):
            v = c[name].value
            return first if isinstance(v, float) and abs(v - first) <= SNAP * max(1.0, abs(first)) else v

        trains = tuple(TrainControl(value(f"trains[{i}].amplitude", tc.amplitude), c[f"trains[{i}].rung"].value,
                                    value(f"trains[{i}].direction", tc.direction)) for i, tc in enumerate(v0.trains))
        return View(hours=value("hours", v0.hours), t=value("t", v0.t), azimuth=value("azimuth", v0.azimuth),
                    trains=trains, eye_height=value("eye_height", v0.eye_height), heading=value("heading", v0.heading),
                    pitch=value("pitch", v0.pitch), reflections=c["reflections"].value, shading=c["shading"].value,
                    seed=v0.seed)

    def _changed(self, _change=None) -> None:
        view = self.settings()
        if view != self._submitted:          # a front end's echo of the same settings renders nothing
            self._submitted = view
            self._worker.submit(view)

    # -- the render thread's answers -----------------------------------------------------
    def _deliver(self, view: View, picture: Picture | None, error: BaseException | None) -> None:
        if error is not None:
            self.error = str(error) if isinstance(error, SunsetError) else f"{type(error).__name__}: {error}"
            self.status.value = (f'<span class="sunset-explorer-error" style="color: #b00020">'
                                 f"{html.escape(self.error)}</span>")
            return
        self.error = ""
        self.picture = picture
        self._serial += 1
        rgba = rgba_for_screen(picture.rgb)
        shading = "8-bit codes" if view.shading == "codes" else "RGB"
        with self.image.hold_sync():
            self.image.rgba = rgba
            self.image.serial = self._serial
        self.status.value = (f'<span class="sunset-explorer-ok">rendered in {picture.seconds:.3f} s '
                             f"({shading}, {picture.rgb.shape[1]}×{picture.rgb.shape[0]})</span>")
        self._pointed()

    def _pointed(self, _change=None) -> None:
        where = self.image.pointer
        picture = self.picture
        self.image.readout = readout(picture, where[0], where[1]) if picture is not None and len(where) == 2 else ""

    # -- what a notebook calls -------------------------------------------------------------
    @property
    def serial(self) -> int:
        """How many pictures have been shown (the picture's front end shows the same number)."""
        return self._serial

    def wait(self, timeout: float | None = 60.0) -> bool:
        """Wait until the newest setting is rendered (or refused); False if ``timeout`` seconds passed first."""
        return self._worker.wait(timeout)

    def readout(self, col: int, row: int) -> str:
        """What the pixel (col, row) of the picture shown means: the pointer's readout there."""
        if self.picture is None:
            raise SunsetError("no picture yet: wait() for the first render")
        return readout(self.picture, col, row)

    def save_scene(self, path: str | os.PathLike) -> Path:
        """Write the picture's settings as a scene TOML file (atomically); its comment gives the render command.

        ``sunset render`` with that command draws the picture shown, byte
        for byte. Waits for a render in progress first.
        """
        from ..io import write_bytes

        self.wait()
        if self.picture is None:
            raise SunsetError("no picture to save: the scene's first settings were refused")
        path = Path(path)
        write_bytes(path, scene_text(self.picture, path.name).encode("utf-8"))
        return path

    def _save_clicked(self) -> None:
        try:
            path = self.save_scene(self.file.value)
        except (SunsetError, OSError) as exc:
            self.saved.value = f'<span style="color: #b00020">{html.escape(str(exc))}</span>'
        else:
            self.saved.value = f"saved {html.escape(str(path))}"

    def close(self) -> None:
        """Stop the render thread and close the widgets."""
        self._worker.close()
        for control in self.controls.values():
            control.close()
        self.image.close()
        super().close()
