"""What the explorer's controls say, and the scene they make: :class:`View`, :class:`Start`, :func:`scene_for`.

A :class:`View` holds the value of every control of :func:`sunset.explore`;
:func:`scene_for` turns a scene (its :class:`Start`) and a view into the
:class:`~sunset.Scene` the explorer renders, and every picture the explorer
shows is that scene rendered with the view's hours, time, reflections and
shading. What each control changes in the scene:

``azimuth``
    ``sun.azimuth``, degrees from the view axis toward +x, where the sun sets.
``trains[i].amplitude``, ``trains[i].direction``
    ``sea.trains[i].amplitude`` (metres) and ``.direction`` (degrees from +x
    toward +y, the way the train travels).
``trains[i].rung``
    The train's wavelength on the ladder λ₁/n² of a repeating sea
    (:meth:`sunset.Sea.periodic`; λ₁ the scene's longest wavelength): rung n
    gives λ₁/n², so every rung keeps the sea's cycle. A train left on the rung
    it started on keeps its own wavelength, on the ladder or not.
``eye_height``
    ``camera.eye_height``, metres above mean sea level.
``pitch``
    Where the window looks, degrees above the horizon (its centre's
    direction). The picture plane stays vertical (the vertical scan lines of
    the paper's method need it), so pitching slides the window up or down
    the plane, as a view camera's rising front does: the window keeps its
    height ``zy_max − zy_min`` and its centre moves to ζ = tan(pitch).
    Verticals stay vertical.
``heading``
    Turns the eye to the right (degrees, clockwise seen from above). The
    renderer looks along +y, so the world turns the other way about the eye
    instead (:func:`turned`): every island, post, wave train and the sun's
    circle turn by −heading. A scene with clouds or a wind sea cannot turn
    (its cloud cells are ellipses along x and y, the wind sea's tile a lattice
    along them; :func:`cannot_turn`): its heading slider is disabled, its
    tooltip says why, and a view that asks for a heading is refused in one
    line.
``hours``, ``t``, ``reflections``, ``shading``, ``seed``
    Not the scene's: the hours before sunset of the colour tables (or the
    RGB back end's light), the sea's time in seconds, the reflection mode
    0/1/2, ``"codes"`` (the paper's 8-bit tape and tables) or ``"rgb"``
    (the RGB back end, one sample per pixel), and the dither seed.

A setting the scene refuses (a wave too steep for its wavelength, an island
turned behind the eye, a window that asks too much work) raises the
:class:`~sunset.SunsetError` of the scene's own check, its field named as a
scene file names it (``sea.trains[2].amplitude must be at most ...``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..errors import SunsetError, require_int_range, require_range, require_time
from ..model.camera import Camera
from ..model.islands import Island, Paraboloid
from ..model.scene import Scene, SceneLike, as_scene
from ..model.sun import require_hours

__all__ = ["SHADINGS", "TrainControl", "View", "Start", "scene_for", "cannot_turn", "turned", "pitched", "rung_of",
           "pitch_of"]

#: The two shadings: the paper's 8-bit codes and colour tables, or the RGB back end.
SHADINGS = ("codes", "rgb")


@dataclass(frozen=True)
class TrainControl:
    """The controls of one wave train: amplitude (m), rung n (λ = λ₁/n²) and direction (degrees)."""

    amplitude: float
    rung: int
    direction: float


@dataclass(frozen=True)
class View:
    """Every control of the explorer at one moment (the module docstring says what each changes)."""

    hours: float
    t: float
    azimuth: float
    trains: tuple[TrainControl, ...]
    eye_height: float
    heading: float
    pitch: float
    reflections: int = 2
    shading: str = "codes"
    seed: int = 0

    def __post_init__(self):
        object.__setattr__(self, "trains", tuple(self.trains))
        require_int_range("reflections", self.reflections, 0, 2)
        if self.shading not in SHADINGS:
            raise SunsetError(f"shading must be one of {', '.join(SHADINGS)}, got {self.shading!r}")
        require_int_range("seed", self.seed, 0, 2**32 - 1)


def rung_of(wavelength: float, fundamental: float) -> int:
    """The rung n whose λ₁/n² is nearest ``wavelength`` (n >= 1)."""
    return max(1, round(math.sqrt(fundamental / wavelength)))


def pitch_of(camera: Camera) -> float:
    """The window's pitch: its centre's direction above the horizon, degrees, rounded to 0.1°."""
    return round(math.degrees(math.atan(0.5 * (camera.zy_min + camera.zy_max))), 1)


@dataclass(frozen=True)
class Start:
    """The scene the explorer opened, the picture size and what its controls start at.

    ``fundamental`` is λ₁, the scene's longest wavelength (the top of the
    rung ladder; 0 for still water), ``view`` the controls' first values
    (which reproduce ``scene`` at ``size`` exactly).
    """

    scene: Scene
    size: tuple[int, int]
    fundamental: float
    view: View

    @classmethod
    def of(cls, scene: SceneLike, size: tuple[int, int] = (512, 512), hours: float = 0.35, t: float = 0.0,
           reflections: int = 2, shading: str = "codes", seed: int = 0) -> "Start":
        """The start of an explorer of ``scene`` (a Scene, a packaged scene's name or a TOML file)."""
        scene = as_scene(scene)
        require_hours("hours", hours)
        require_time("t", t)
        try:
            width, height = size
        except (TypeError, ValueError):
            raise SunsetError(f"size must be (width, height), got {size!r}") from None
        scene = scene.with_size(width, height)
        trains = scene.sea.trains
        fundamental = max((tr.wavelength for tr in trains), default=0.0)
        view = View(hours=hours, t=t, azimuth=scene.sun.azimuth,
                    trains=tuple(TrainControl(tr.amplitude, rung_of(tr.wavelength, fundamental), tr.direction)
                                 for tr in trains),
                    eye_height=scene.camera.eye_height, heading=0.0, pitch=pitch_of(scene.camera),
                    reflections=reflections, shading=shading, seed=seed)
        return cls(scene, (width, height), fundamental, view)


def _field(prefix: str, exc: SunsetError) -> SunsetError:
    """The scene's own message with the field's place in a scene file in front (``sea.trains[1].``)."""
    return SunsetError(f"{prefix}{exc}")


def scene_for(start: Start, view: View) -> Scene:
    """The scene that ``view``'s controls make of ``start``'s scene.

    Raises :class:`~sunset.SunsetError` (one line, naming the field) for a
    setting the scene refuses. The controls at their start give back
    ``start.scene`` itself.
    """
    scene = start.scene
    base = start.view
    if len(view.trains) != len(scene.sea.trains):
        raise SunsetError(f"trains: the scene has {len(scene.sea.trains)} wave trains, the view {len(view.trains)}")
    if view.azimuth != base.azimuth:
        try:
            scene = replace(scene, sun=replace(scene.sun, azimuth=view.azimuth))
        except SunsetError as exc:
            raise _field("sun.", exc) from None
    trains = []
    for i, (train, ctl, ctl0) in enumerate(zip(scene.sea.trains, view.trains, base.trains)):
        if ctl == ctl0:
            trains.append(train)
            continue
        require_int_range(f"sea.trains[{i}] rung", ctl.rung, 1)
        wavelength = train.wavelength if ctl.rung == ctl0.rung else start.fundamental / ctl.rung**2
        try:
            trains.append(replace(train, amplitude=ctl.amplitude, wavelength=wavelength, direction=ctl.direction))
        except SunsetError as exc:
            raise _field(f"sea.trains[{i}].", exc) from None
    if trains != list(scene.sea.trains):
        scene = replace(scene, sea=replace(scene.sea, trains=tuple(trains)))
    camera = scene.camera
    if view.eye_height != base.eye_height:
        try:
            camera = replace(camera, eye_height=view.eye_height)
        except SunsetError as exc:
            raise _field("camera.", exc) from None
    if view.pitch != base.pitch:
        camera = pitched(camera, view.pitch)
    if camera != scene.camera:
        scene = replace(scene, camera=camera)
    return turned(scene, view.heading)


def pitched(camera: Camera, pitch: float) -> Camera:
    """The camera whose window's centre looks ``pitch`` degrees above the horizon, its height kept."""
    require_range("pitch", pitch, -80.0, 80.0, "degrees")
    half = 0.5 * (camera.zy_max - camera.zy_min)
    centre = math.tan(math.radians(pitch))
    try:
        return replace(camera, zy_min=centre - half, zy_max=centre + half)
    except SunsetError as exc:
        raise SunsetError(f"pitch {pitch:g}° puts the window outside the picture plane's range: "
                          f"camera.{exc}") from None


def _angle(degrees: float) -> float:
    """An angle folded into [−180, 180) degrees."""
    return (degrees + 180.0) % 360.0 - 180.0


def cannot_turn(scene: Scene) -> str | None:
    """Why the eye of ``scene`` cannot turn (its heading stays 0), or None where it can.

    A cloud layer's cells are ellipses along x and y, and a wind sea's tile is
    a lattice along them: turning the world would turn them too, and a
    turned lattice is another sea (its waves would jump as the eye turns).
    The explorer disables its heading slider for such a scene, with this
    reason as the slider's tooltip.
    """
    if scene.clouds is not None:
        return "a scene with clouds cannot turn (its cloud cells are ellipses along x and y)"
    if getattr(scene.sea, "wind", None) is not None:
        return "a scene with a wind sea cannot turn (its tile's lattice lies along x and y)"
    return None


def turned(scene: Scene, heading: float) -> Scene:
    """The scene as the eye sees it after turning ``heading`` degrees to the right (clockwise from above).

    The eye stays at the origin looking along +y and the world turns about
    the eye's vertical by −heading: a point p goes to R p, R the rotation by
    ``heading`` counter-clockwise seen from above, so that what lay
    ``heading`` degrees to the right of the view axis lies on it. Islands
    (their apexes, the quadratic forms of their paraboloids, the wave vectors
    of their cosine hills), posts, the wave trains' directions and the sun's
    azimuth turn with it; heights do not change. A heading of 0 gives back
    ``scene`` itself.
    """
    require_range("heading", heading, -180.0, 180.0, "degrees")
    if heading == 0:
        return scene
    why = cannot_turn(scene)
    if why is not None:
        raise SunsetError(f"heading: {why}; set heading to 0")
    a = math.radians(heading)
    c, s = math.cos(a), math.sin(a)

    def rot(x: float, y: float) -> tuple[float, float]:
        return c * x - s * y, s * x + c * y

    def form(p: Paraboloid) -> Paraboloid:
        # P = height − uᵀQu, Q = [[e, f/2], [f/2, g]]; in the turned frame u' = R u, so Q' = R Q Rᵀ
        e = c * c * p.e - c * s * p.f + s * s * p.g
        f = 2.0 * c * s * (p.e - p.g) + (c * c - s * s) * p.f
        g = s * s * p.e + c * s * p.f + c * c * p.g
        return replace(p, e=e, f=f, g=g)

    def island(k: int, isl: Island) -> Island:
        x, y = rot(isl.x, isl.y)
        cosines = tuple(replace(cos, l=lm[0], m=lm[1]) for cos in isl.cosines for lm in [rot(cos.l, cos.m)])
        try:
            return replace(isl, x=x, y=y, cliff=form(isl.cliff), beach=form(isl.beach), cosines=cosines)
        except SunsetError as exc:
            raise _field(f"heading: islands[{k}].", exc) from None

    islands = tuple(island(k, isl) for k, isl in enumerate(scene.islands))
    posts = tuple(replace(p, x=xy[0], y=xy[1]) for p in scene.posts for xy in [rot(p.x, p.y)])
    trains = tuple(replace(tr, direction=_angle(tr.direction + heading)) for tr in scene.sea.trains)
    try:
        return replace(scene, islands=islands, posts=posts, sea=replace(scene.sea, trains=trains),
                       sun=replace(scene.sun, azimuth=_angle(scene.sun.azimuth - heading)))
    except SunsetError as exc:
        raise SunsetError(f"heading: {exc}") from None

