"""A scene: the camera, the sea, the islands and the sun, loaded from TOML.

A scene file has four parts, each checked on load::

    [camera]          eye height, picture window, size, σ   (sunset.model.camera.Camera)
    [sun]             the sun's great circle and δ           (sunset.model.sun.Sun)
    [sea]             gravity (optional, m s⁻²; standard gravity by default)
    [[sea.trains]]    the wave trains of eq. 1               (sunset.model.waves.WaveTrain)
    [sea.wind]        or a sea given by its wind (FFT tile)   (sunset.model.windsea.WindSea)
    [[islands]]       paraboloids and cosine hills, eqs. 3–4 (sunset.model.islands.Island)
                      with [islands.cliff], [islands.beach], [[islands.cosines]]
                      (a cosine's ``phase`` is optional, 0 by default)
    [clouds]          optional: a cloud layer, its mean level and [[clouds.cells]]
                      with [[clouds.cells.billows]]   (sunset.model.clouds.Clouds)
    [[posts]]         optional: posts standing in the water  (sunset.model.posts.Post)

An unknown key, a missing field, a value of the wrong type, a NaN, a
non-positive size, an island behind the eye or an eye below the sea raises a
:class:`~sunset.errors.SunsetError` whose message names the field, such as
``islands[2].cliff.e must be positive, got -0.01``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import sys
import tomllib
import typing
from dataclasses import dataclass, field, replace
from importlib import resources
from pathlib import Path

from ..constants import MAX_COSINES, MAX_ISLANDS, MAX_SCENE_BYTES, MAX_SCENE_DEPTH, MAX_TEXT_CHARS, MAX_TRAINS
from .camera import Camera
from .clouds import Billow, CloudCell, Clouds
from .posts import Post
from ..constants import CLOUD_MAX_CELLS, POST_MAX_COUNT
from ..errors import SunsetError, require_instance, require_items, require_text, shown, typed
from .islands import Cosine, Island, Paraboloid
from .sun import Sun
from .waves import Sea, WaveTrain
from .windsea import WindSea

#: Name of the default scene shipped with the package.
DEFAULT_SCENE = "carlas-island"


@dataclass(frozen=True, repr=False)
class Scene:
    """Everything the vector stage needs to render a frame at time t."""

    camera: Camera = field(default_factory=Camera)
    sun: Sun = field(default_factory=Sun)
    sea: Sea = field(default_factory=Sea)
    islands: tuple[Island, ...] = field(default_factory=tuple)
    title: str = ""
    clouds: Clouds | None = None
    posts: tuple[Post, ...] = field(default_factory=tuple)

    def __post_init__(self):
        check_text("title", self.title)
        for name, kind in (("camera", Camera), ("sun", Sun), ("sea", Sea)):
            require_instance(name, getattr(self, name), kind)
        if self.clouds is not None:
            require_instance("clouds", self.clouds, Clouds)
        object.__setattr__(self, "islands", require_items("islands", self.islands, Island, MAX_ISLANDS))
        for k, island in enumerate(self.islands):
            check_text(f"islands[{k}].name", island.name)
        object.__setattr__(self, "posts", require_items("posts", self.posts, Post, POST_MAX_COUNT))
        h = self.camera.eye_height
        for k, island in enumerate(self.islands):
            ground = float(island.height(0.0, 0.0))
            if ground >= h:
                raise SunsetError(f"islands[{k}] puts the eye inside it: its surface at the eye (x = y = 0) is "
                                  f"{ground:.3g} m above the sea, the eye only {h:g} m")
        if self.clouds is not None and self.clouds.base <= h:
            raise SunsetError(f"clouds: the eye ({h:g} m) must be below the cloud base "
                              f"({self.clouds.base:g} m: the level less the deepest cloud)")

    def __repr__(self) -> str:
        cam = self.camera
        title = f"{self.title!r}, " if self.title else ""
        n = len(self.islands)
        clouds = ", clouds" if getattr(self, "clouds", None) is not None else ""
        return (f"Scene({title}{cam.width}×{cam.height}, {self.sea!r}, {n} island{'s' * (n != 1)}{clouds}, "
                f"sun tilt {self.sun.tilt:g}°)")

    # -- derived scenes -------------------------------------------------------
    def still(self) -> "Scene":
        """The same scene on perfectly still water (Figure 4)."""
        return replace(self, sea=Sea(()))

    def with_size(self, width: int, height: int) -> "Scene":
        """The same scene rendered at another pixel size."""
        return replace(self, camera=self.camera.with_size(width, height))

    # -- TOML -----------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: dict) -> "Scene":
        """Build and validate a scene from the parsed TOML tables."""
        return _build(cls, data, "")

    def to_dict(self) -> dict:
        """The scene as TOML-ready tables (inverse of :meth:`from_dict`)."""
        return _unbuild(self)

    @classmethod
    def from_toml(cls, path_or_text: str | Path) -> "Scene":
        """Load a scene from a TOML file (a path) or TOML text.

        A :class:`~pathlib.Path`, or a string with neither a newline nor an
        ``=``, is a file; any other string is the TOML text itself (see
        ``sunset.model.scene.scene_from_text``, which never reads a file). Raises
        :class:`SunsetError` naming the file and the field for any malformed
        or invalid content.
        """
        if isinstance(path_or_text, Path) or ("\n" not in str(path_or_text) and "=" not in str(path_or_text)):
            return scene_from_file(Path(path_or_text))
        return scene_from_text(str(path_or_text))

    def to_toml(self) -> str:
        """The scene as TOML text; ``Scene.from_toml(s.to_toml()) == s`` exactly."""
        return _dump_toml(self.to_dict())

    @classmethod
    def default(cls) -> "Scene":
        """The default scene, ``sunset/scenes/carlas-island.toml``."""
        return load_named_scene(DEFAULT_SCENE)

    @classmethod
    def named(cls, name: str) -> "Scene":
        """A scene shipped in ``sunset/scenes/``, by name (e.g. ``"storm-swell"``; see :func:`scene_names`)."""
        return load_named_scene(name)


def check_text(name: str, value) -> None:
    """Raise :class:`SunsetError` unless ``value`` is a scene's text: at most MAX_TEXT_CHARS printable characters.

    :func:`sunset.errors.require_text` says which characters; every format
    the text reaches escapes it again (:mod:`sunset.escape`).
    """
    require_text(name, value, MAX_TEXT_CHARS)


def scene_names() -> list[str]:
    """The names of the scenes shipped in ``sunset/scenes/``, sorted (``Scene.named`` loads one)."""
    folder = resources.files("sunset") / "scenes"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def scene_from_file(path: Path) -> Scene:
    """Load a scene file; errors start with the file's name."""
    name = shown(path)
    try:
        if path.is_dir():
            raise SunsetError(f"{name}: is a directory, not a scene file")
        if path.exists() and not path.is_file():
            raise SunsetError(f"{name}: not a regular file (a device or a pipe), not a scene file")
        with open(path, "rb") as fh:
            raw = fh.read(MAX_SCENE_BYTES + 1)
    except FileNotFoundError:
        raise SunsetError(f"{name}: no such scene file") from None
    except OSError as exc:
        raise SunsetError(f"{name}: cannot read scene file ({exc.strerror or exc})") from None
    if len(raw) > MAX_SCENE_BYTES:
        raise SunsetError(f"{name}: scene file larger than {MAX_SCENE_BYTES // 1024} KiB")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SunsetError(f"{name}: cannot read scene file (not UTF-8: {exc.reason} at byte {exc.start})") from None
    return scene_from_text(text, f"{name}: ")


def _depth(text: str) -> int:
    """A bound on the nesting of TOML text: brackets and braces, plus the dots of a dotted key.

    Strings and comments are skipped; a dot between two digits belongs to a
    number. tomllib recurses on brackets and takes time quadratic in a dotted
    key's length, so both are bounded before it runs.
    """
    depth = most = dots = 0
    quote = None
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if quote:
            if c == "\\" and quote == '"':
                i += 2
                continue
            if c == quote or c == "\n":
                quote = None
        elif c in "\"'":
            quote = c
        elif c == "#":
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        elif c in "[{":
            depth += 1
        elif c in "]}":
            depth -= 1
            dots = 0
        elif c == "." and not (0 < i < n - 1 and text[i - 1].isdigit() and text[i + 1].isdigit()):
            dots += 1
        elif c in "=,\n":
            dots = 0
        most = max(most, depth + dots)
        i += 1
    return most


def scene_from_text(text: str, where: str = "") -> Scene:
    """Build a scene from TOML text (never from a file: a tape's scene is text).

    ``where`` (a file name and ": ") starts every error message. Text larger
    than MAX_SCENE_BYTES, or nested deeper than MAX_SCENE_DEPTH, is refused
    before it is parsed.
    """
    if not isinstance(text, str):
        raise SunsetError(f"{where}a scene must be TOML text, got {type(text).__name__}")
    if len(text) > MAX_SCENE_BYTES:
        raise SunsetError(f"{where}scene larger than {MAX_SCENE_BYTES // 1024} KiB")
    if _depth(text) > MAX_SCENE_DEPTH:
        raise SunsetError(f"{where}malformed TOML (nested deeper than {MAX_SCENE_DEPTH} levels)")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SunsetError(f"{where}malformed TOML ({shown(str(exc))})") from None
    except ValueError as exc:               # an integer literal past the digits Python converts (4300)
        what = (f"an integer literal of more than {sys.get_int_max_str_digits()} digits (no field of a scene "
                f"takes one)" if "digits" in str(exc) else f"malformed TOML ({shown(str(exc))})")
        raise SunsetError(f"{where}{what}") from None
    except RecursionError:
        raise SunsetError(f"{where}malformed TOML (nested too deep)") from None
    try:
        return Scene.from_dict(data)
    except SunsetError as exc:
        raise SunsetError(f"{where}{exc}") from None
    except RecursionError:
        raise SunsetError(f"{where}scene nested too deep") from None


def load_named_scene(name: str) -> Scene:
    """Load a scene shipped in ``sunset/scenes/`` by name (without .toml)."""
    if not isinstance(name, str) or name not in scene_names():
        raise SunsetError(f"no scene named {name!r} in the package (packaged scenes: {', '.join(scene_names())})")
    ref = resources.files("sunset") / "scenes" / f"{name}.toml"
    try:
        return scene_from_text(ref.read_text(encoding="utf-8"))
    except SunsetError as exc:   # pragma: no cover - tests load every packaged scene
        raise SunsetError(f"packaged scene {name}: {exc}") from None


#: What the public functions accept for a scene: a Scene, a packaged scene's name, or a scene TOML file.
SceneLike = typing.Union[Scene, str, os.PathLike[str]]


def as_scene(scene: SceneLike) -> Scene:
    """A :class:`Scene` from a scene, the name of a packaged scene, or a scene TOML file.

    What every public function that takes a scene accepts: ``"storm-swell"``
    is the packaged scene of that name; any other string or path is a file.
    """
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, str) and scene in scene_names():
        return load_named_scene(scene)
    if isinstance(scene, (str, os.PathLike)):
        path = Path(scene)
        if not path.exists() and isinstance(scene, str) and "/" not in scene and not scene.endswith(".toml"):
            raise SunsetError(f"no scene named {shown(repr(scene))} in the package and no such file "
                              f"(packaged scenes: {', '.join(scene_names())})")
        return Scene.from_toml(path)
    raise SunsetError(f"expected a Scene, the name of a packaged scene or a scene file, got {shown(scene)}")


def default_scene() -> Scene:
    """The default scene (Carla's Island)."""
    return Scene.default()


# ----------------------------------------------------------------------------
# Generic validated loading of the frozen dataclasses above.

_NESTED = {
    Scene: {"camera": Camera, "sun": Sun, "sea": Sea, "islands": Island, "clouds": Clouds, "posts": Post},
    Clouds: {"cells": CloudCell},
    CloudCell: {"billows": Billow},
    Sea: {"trains": WaveTrain, "wind": WindSea},
    Island: {"cliff": Paraboloid, "beach": Paraboloid, "cosines": Cosine},
}


def _field_types(cls) -> dict[str, typing.Any]:
    hints = typing.get_type_hints(cls)
    return {name: hints[name] for name in _file_fields(cls)}


#: Fields a scene file may leave out (they take their defaults); every other
#: field must be written out, so that a scene file says what it renders.
_OPTIONAL = {
    (Scene, "title"), (Scene, "sea"), (Scene, "islands"), (Sea, "trains"),
    (WaveTrain, "phase"), (WaveTrain, "stokes_order"), (Island, "name"), (Island, "cosines"),
    (Scene, "clouds"), (CloudCell, "billows"), (Scene, "posts"), (Post, "albedo"),
    (Sea, "gravity"), (Cosine, "phase"),
    (Sea, "wind"), (WindSea, "height"), (WindSea, "spreading"), (WindSea, "choppiness"),
}

#: Fields added after the file format's first version: written out only when
#: they differ from their defaults, so that every earlier scene's TOML (and the
#: PNGs and tapes that embed it) stays byte for byte what it was.
_WRITTEN_WHEN_SET = {(Sea, "gravity"), (Cosine, "phase")}

#: Fields a scene file does not have: a train's gravity is its sea's.
_NOT_IN_FILE = {(WaveTrain, "gravity"), (WindSea, "gravity")}


def _file_fields(cls) -> dict[str, dataclasses.Field]:
    return {f.name: f for f in dataclasses.fields(cls) if (cls, f.name) not in _NOT_IN_FILE}


def _required(cls, f: dataclasses.Field) -> bool:
    return (cls, f.name) not in _OPTIONAL


def _join(path: str, name: str) -> str:
    return f"{path}.{name}" if path else name


def _convert(value, typ, where: str):
    if typ is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SunsetError(f"{where} must be a number, got {typed(value)}")
        if isinstance(value, float) and math.isnan(value):
            raise SunsetError(f"{where} must be a finite number, got nan")
        try:
            return float(value)
        except OverflowError:
            bits = abs(value).bit_length()    # str() stops at 4300 digits
            digits = len(str(abs(value))) if bits <= 14000 else f"about {math.floor(bits * math.log10(2)) + 1}"
            raise SunsetError(f"{where} must be a finite number, got an integer of {digits} digits") from None
    if typ is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise SunsetError(f"{where} must be an integer, got {typed(value)}")
        return value
    if typ is str:
        if not isinstance(value, str):
            raise SunsetError(f"{where} must be a string, got {shown(value)}")
        return value
    raise TypeError(f"unsupported field type {typ!r}")  # pragma: no cover - programming error


#: The most entries of an array of tables, checked before they are built.
_MAX_ITEMS = {(Scene, "islands"): MAX_ISLANDS, (Sea, "trains"): MAX_TRAINS, (Island, "cosines"): MAX_COSINES,
              (Clouds, "cells"): CLOUD_MAX_CELLS, (CloudCell, "billows"): MAX_COSINES}


def _build(cls, data, path: str):
    if not isinstance(data, dict):
        raise SunsetError(f"{path or 'scene'} must be a table, got {shown(data)}")
    fields = _file_fields(cls)
    unknown = sorted(set(data) - set(fields))
    if unknown:
        raise SunsetError(f"unknown key {shown(repr(_join(path, unknown[0])))}" + (f" (expected one of: {', '.join(fields)})"))
    nested = _NESTED.get(cls, {})
    types = _field_types(cls)
    kwargs = {}
    for name, f in fields.items():
        where = _join(path, name)
        if name not in data:
            if _required(cls, f):
                raise SunsetError(f"missing field {where!r}")
            continue
        value = data[name]
        if name in nested:
            sub = nested[name]
            origin = typing.get_origin(types[name])
            if origin is tuple:
                if not isinstance(value, list):
                    raise SunsetError(f"{where} must be an array of tables")
                most = _MAX_ITEMS.get((cls, name))
                if most is not None and len(value) > most:
                    raise SunsetError(f"{where} must hold at most {most} entries, got {len(value)}")
                kwargs[name] = tuple(_build(sub, v, f"{where}[{i}]") for i, v in enumerate(value))
            else:
                kwargs[name] = _build(sub, value, where)
        else:
            kwargs[name] = _convert(value, types[name], where)
    try:
        return cls(**kwargs)
    except SunsetError as exc:
        msg = str(exc)
        head = msg.split(" ", 1)[0]
        if head.split("[", 1)[0] in fields:
            raise SunsetError(f"{_join(path, head)} {msg.split(' ', 1)[1]}") from None
        raise SunsetError(f"{path or 'scene'}: {msg}") from None


def _unbuild(obj):
    if dataclasses.is_dataclass(obj):
        out = {}
        cls = type(obj)
        for f in _file_fields(cls).values():
            v = getattr(obj, f.name)
            if v is None:                      # an optional part left out (a scene without clouds)
                continue
            if (cls, f.name) in _WRITTEN_WHEN_SET and v == f.default:
                continue
            if isinstance(v, tuple):
                out[f.name] = [_unbuild(x) for x in v]
            else:
                out[f.name] = _unbuild(v)
        return out
    return obj


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        # TOML basic strings: escape \\ and ", and every control character
        # (U+0000..U+001F, U+007F), which TOML does not allow raw.
        out = v.replace("\\", "\\\\").replace('"', '\\"')
        out = "".join(f"\\u{ord(c):04X}" if ord(c) < 0x20 or ord(c) == 0x7F else c for c in out)
        return '"' + out + '"'
    raise TypeError(f"cannot write {v!r} to TOML")  # pragma: no cover


def _dump_table(table: dict, header: str, array: bool, lines: list[str]) -> None:
    scalars = {k: v for k, v in table.items() if not isinstance(v, (dict, list))}
    lines.append(f"[[{header}]]" if array else f"[{header}]")
    for k, v in scalars.items():
        lines.append(f"{k} = {_toml_value(v)}")
    lines.append("")
    for k, v in table.items():
        if isinstance(v, dict):
            _dump_table(v, f"{header}.{k}", False, lines)
        elif isinstance(v, list):
            for item in v:
                _dump_table(item, f"{header}.{k}", True, lines)


def _dump_toml(data: dict) -> str:
    lines = []
    for k, v in data.items():
        if not isinstance(v, (dict, list)):
            lines.append(f"{k} = {_toml_value(v)}")
    lines.append("")
    for k, v in data.items():
        if isinstance(v, dict):
            _dump_table(v, k, False, lines)
        elif isinstance(v, list):
            for item in v:
                _dump_table(item, k, True, lines)
    return "\n".join(lines).rstrip() + "\n"
