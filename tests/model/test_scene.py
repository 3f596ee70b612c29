"""Scenes and their TOML files (sunset/model/scene.py).

The default scene loads; ``Scene.from_toml(scene.to_toml()) == scene``
exactly, for the default and for random valid scenes; and every kind of bad
file raises one SunsetError whose message names the offending field.
"""

import copy
import dataclasses
import math
import re
import tomllib

from sunset.constants import MAX_DEGREES, MAX_PIXELS, MIN_SUN_RADIUS, MIN_WAVELENGTH, SIGMA_MIN
from importlib import resources

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from sunset.model.camera import Camera
from sunset.errors import SunsetError
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.scene import Scene, default_scene, load_named_scene
from sunset.model.sun import Sun
from sunset.model.waves import Sea, WaveTrain

finite = dict(allow_nan=False, allow_infinity=False)
DEFAULT_TEXT = (resources.files("sunset") / "scenes" / "carlas-island.toml").read_text(encoding="utf-8")


def default_data() -> dict:
    return tomllib.loads(DEFAULT_TEXT)


# -- the default scene ---------------------------------------------------------

def test_default_scene_loads():
    scene = Scene.default()
    data = default_data()
    assert scene.title == data["title"] == "Carla's Island"
    assert scene == default_scene() == load_named_scene("carlas-island")
    assert scene.camera == Camera(**data["camera"])
    assert scene.sun == Sun(**data["sun"])
    assert len(scene.sea.trains) == len(data["sea"]["trains"])
    assert [i.name for i in scene.islands] == [i["name"] for i in data["islands"]]
    for island, table in zip(scene.islands, data["islands"]):
        assert island.cliff == Paraboloid(**table["cliff"])
        assert island.beach == Paraboloid(**table["beach"])
        assert island.cosines == tuple(Cosine(**c) for c in table.get("cosines", []))


def test_default_scene_round_trips_exactly(tmp_path):
    scene = Scene.default()
    text = scene.to_toml()
    assert Scene.from_toml(text) == scene
    assert Scene.from_toml(text).to_toml() == text
    # The TOML is a faithful description: it parses to the same tables as the shipped file
    # (up to integers written as floats).
    assert tomllib.loads(text)["camera"] == default_data()["camera"]
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8")
    assert Scene.from_toml(path) == scene
    assert Scene.from_toml(str(path)) == scene


def test_still_and_with_size():
    scene = Scene.default()
    assert scene.still().sea.trains == ()
    assert scene.still().islands == scene.islands
    small = scene.with_size(40, 30)
    assert (small.camera.width, small.camera.height) == (40, 30)
    assert small.camera.s_min == scene.camera.s_min and small.sea == scene.sea


# -- random valid scenes ---------------------------------------------------------

def floats(lo, hi):
    return st.floats(lo, hi, **finite)


@st.composite
def cameras(draw):
    s_min = draw(floats(-2, 1))
    zy_min = draw(floats(-1, 0.2))
    width = draw(st.integers(1, 5000))
    height = draw(st.integers(1, min(5000, MAX_PIXELS // width)))      # the pixel budget of the camera
    return Camera(eye_height=draw(floats(1e-3, 1e3)), width=width,
                  height=height, s_min=s_min, s_max=s_min + draw(floats(1e-3, 3)),
                  zy_min=zy_min, zy_max=zy_min + draw(floats(1e-3, 2)), sigma=draw(floats(SIGMA_MIN, 10)))


@st.composite
def trains(draw):
    wavelength = draw(floats(MIN_WAVELENGTH, 1e3))
    return WaveTrain(amplitude=draw(floats(0, 4.99)) * wavelength / (2 * math.pi * 5), wavelength=wavelength,
                     direction=draw(floats(-MAX_DEGREES, MAX_DEGREES)), phase=draw(floats(-10, 10)),
                     stokes_order=draw(st.integers(1, 4)))


@st.composite
def paraboloids(draw):
    e, g = draw(floats(1e-6, 1.0)), draw(floats(1e-6, 1.0))
    return Paraboloid(height=draw(floats(-10, 500)), e=e,
                      f=draw(floats(-0.99, 0.99)) * 2 * math.sqrt(e * g), g=g)


#: A scene's text: any printable character of any script (sunset.model.scene.check_text).
scene_text = st.characters(codec=None, exclude_categories=("Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp", "Zs"),
                           include_characters=" ")


@st.composite
def islands(draw):
    cliff = draw(paraboloids())
    return Island(x=draw(floats(-1e4, 1e4)), y=draw(floats(1e-3, 1e5)), cliff=cliff,
                  beach=draw(paraboloids()), cliff_top=cliff.height - draw(floats(1e-3, 100)),
                  hill_factor=draw(floats(1e-3, 1.0)),
                  cosines=tuple(draw(st.lists(st.builds(Cosine, floats(0, 10), floats(-1, 1), floats(-1, 1)),
                                              max_size=3))),
                  name=draw(st.text(scene_text, max_size=12)))


@st.composite
def scenes(draw):
    camera = draw(cameras())
    isles = tuple(draw(st.lists(islands(), max_size=3)))
    assume(all(float(isl.height(0.0, 0.0)) < camera.eye_height for isl in isles))   # the eye is not underground
    return Scene(camera=camera,
                 sun=Sun(azimuth=draw(floats(-360, 360)), tilt=draw(floats(1e-3, 90)),
                         radius=draw(floats(MIN_SUN_RADIUS, 9.99))),
                 sea=Sea(tuple(draw(st.lists(trains(), max_size=4)))),
                 islands=isles,
                 title=draw(st.text(scene_text, max_size=30)))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(scenes())
def test_random_scenes_round_trip_exactly(scene):
    text = scene.to_toml()
    back = Scene.from_toml(text)
    assert back == scene
    # Exact, not merely equal: every float keeps every bit.
    assert back.to_dict() == scene.to_dict()
    assert back.to_toml() == text


def test_round_trip_keeps_awkward_strings_and_floats():
    scene = dataclasses.replace(
        Scene.default(), title='"quotes", \'single\', back\\slash, # = [x] """ é 漢字 🙂 \\n \\u0007',
        camera=dataclasses.replace(Scene.default().camera, eye_height=0.1 + 0.2, s_min=-0.1 - 0.2, s_max=1 / 3),
        sun=Sun(azimuth=5e-324))          # in range, but awkward: 0.30000000000000004, 1/3, a subnormal
    back = Scene.from_toml(scene.to_toml())
    assert back == scene
    assert math.copysign(1, Scene.from_toml(dataclasses.replace(
        scene, sun=Sun(azimuth=-0.0)).to_toml()).sun.azimuth) == -1
    for bad in ("tab\there", "new\nline", "cr\r", "bell\x07", "del\x7f", "\u202e"):   # not a scene's text
        with pytest.raises(SunsetError, match="^title must hold printable characters only"):
            dataclasses.replace(scene, title=bad)


# -- bad scene files ----------------------------------------------------------------

def load_modified(edit) -> Scene:
    data = copy.deepcopy(default_data())
    edit(data)
    return Scene.from_dict(data)


def error_of(edit) -> str:
    with pytest.raises(SunsetError) as info:
        load_modified(edit)
    return str(info.value)


def test_unknown_key_is_named():
    assert "'colour'" in error_of(lambda d: d.update(colour="red"))
    assert "'camera.zoom'" in error_of(lambda d: d["camera"].update(zoom=2.0))
    assert "'islands[1].cliff.k'" in error_of(lambda d: d["islands"][1]["cliff"].update(k=1.0))
    assert "'sea.trains[2].speed'" in error_of(lambda d: d["sea"]["trains"][2].update(speed=1.0))


@pytest.mark.parametrize("path", [
    ("camera", "eye_height"), ("camera", "width"), ("sun", "tilt"), ("camera",), ("sun",),
    ("islands", 0, "cliff_top"), ("islands", 2, "beach"), ("islands", 1, "cliff", "g"),
    ("sea", "trains", 0, "wavelength"), ("sea", "trains", 1, "amplitude"),
])
def test_missing_field_is_named(path):
    def drop(d):
        for key in path[:-1]:
            d = d[key]
        del d[path[-1]]
    where = path[0] + "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in path[1:])
    msg = error_of(drop)
    assert msg.startswith("missing field") and f"'{where}'" in msg


@pytest.mark.parametrize("where, value, words", [
    ("camera.width", "1020", "must be an integer"),
    ("camera.width", 1020.0, "must be an integer"),
    ("camera.height", True, "must be an integer"),
    ("camera.eye_height", "2", "must be a number"),
    ("camera.eye_height", False, "must be a number"),
    ("sun.radius", [0.75], "must be a number"),
    ("sea.trains[0].stokes_order", 2.0, "must be an integer"),
    ("islands[0].name", 7, "must be a string"),
    ("title", 1981, "must be a string"),
    ("islands[0].cliff", 3.0, "must be a table"),
    ("camera", 1, "must be a table"),
])
def test_wrong_type_is_named(where, value, words):
    assert error_of(lambda d: set_at(d, where, value)).startswith(f"{where} {words}")


def test_islands_must_be_an_array_of_tables():
    assert error_of(lambda d: d.update(islands={"x": 1.0})).startswith("islands must be an array of tables")


@pytest.mark.parametrize("where, value, words", [
    ("camera.width", 0, "must be >= 1"),
    ("camera.height", -3, "must be >= 1"),
    ("camera.sigma", 0.0, "must be positive"),
    ("sea.trains[1].wavelength", 0.0, "must be positive"),
    ("sea.trains[1].amplitude", -0.1, "must not be negative"),
    ("sun.radius", 0.0, "must be positive"),
    ("islands[1].cliff.e", -0.01, "must be positive"),
    ("islands[2].hill_factor", 0.0, "must be positive"),
])
def test_non_positive_sizes_are_named(where, value, words):
    assert error_of(lambda d: set_at(d, where, value)).startswith(f"{where} {words}")


def with_line(text: str, key: str, value: str) -> str:
    """``text`` with the one line ``key = ...`` set to ``key = value``."""
    pattern = rf"(?m)^{key} = .*$"
    assert len(re.findall(pattern, text)) == 1, key
    return re.sub(pattern, f"{key} = {value}", text)


@pytest.mark.parametrize("where", [
    "camera.eye_height", "camera.s_min", "camera.zy_max", "camera.sigma", "sun.azimuth", "sun.tilt",
    "sun.radius",
])
def test_nan_in_the_toml_text_is_named(where):
    # As a user would write it: TOML's own `nan` literal (the keys are unique in the file).
    text = with_line(DEFAULT_TEXT, where.split(".")[-1], "nan")
    with pytest.raises(SunsetError, match=rf"^{re.escape(where)} must be a finite number"):
        Scene.from_toml(text)


@pytest.mark.parametrize("where", [
    "camera.eye_height", "sea.trains[0].phase", "sea.trains[1].direction", "sea.trains[0].amplitude",
    "islands[0].x", "islands[0].y", "islands[1].cliff.f", "islands[2].beach.height", "islands[1].hill_factor",
    "islands[0].cosines[0].l",
])
def test_nan_is_named(where):
    assert error_of(lambda d: set_at(d, where, float("nan"))).startswith(f"{where} must be a finite number")


def test_island_behind_the_eye():
    for y in (0.0, -900.0):
        msg = error_of(lambda d: set_at(d, "islands[1].y", y))
        assert msg.startswith("islands[1].y must be positive") and "behind the eye" in msg


def test_eye_below_the_sea():
    for h in (0.0, -2.0):
        assert error_of(lambda d: set_at(d, "camera.eye_height", h)).startswith(
            "camera.eye_height must be positive")


def test_other_invalid_values_name_the_field():
    assert error_of(lambda d: set_at(d, "camera.s_max", -1.0)).startswith("camera.s_max must be greater")
    assert error_of(lambda d: set_at(d, "sun.tilt", 95.0)).startswith("sun.tilt must be in (0, 90]")
    assert error_of(lambda d: set_at(d, "islands[0].cliff_top", 500.0)).startswith("islands[0].cliff_top")
    assert error_of(lambda d: set_at(d, "islands[0].cliff.f", 1.0)).startswith("islands[0].cliff.f")
    assert error_of(lambda d: set_at(d, "sea.trains[0].stokes_order", 5)).startswith(
        "sea.trains[0].stokes_order must be in 1..4")


@pytest.mark.parametrize("text", [
    "title = 'unterminated\n[camera]\n",
    "[camera]\neye_height = 2.0\n[camera]\nwidth = 3\n",      # a table defined twice
    "[camera\neye_height = 2.0\n",
    "title = = 1\n",
])
def test_malformed_toml(text):
    with pytest.raises(SunsetError, match=r"malformed TOML"):
        Scene.from_toml(text)


def test_malformed_file_is_named(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("[camera\n", encoding="utf-8")
    with pytest.raises(SunsetError, match=rf"^{re.escape(str(path))}: malformed TOML"):
        Scene.from_toml(path)
    path.write_text(with_line(DEFAULT_TEXT, "tilt", "nan"), encoding="utf-8")
    with pytest.raises(SunsetError, match=rf"^{re.escape(str(path))}: sun.tilt must be a finite number"):
        Scene.from_toml(path)
    with pytest.raises(SunsetError, match="no such scene file"):
        Scene.from_toml(tmp_path / "missing.toml")
    with pytest.raises(SunsetError, match="no scene named"):
        load_named_scene("no-such-scene")


# -- helpers ----------------------------------------------------------------------

def split(where: str) -> list:
    parts = []
    for piece in where.split("."):
        name, *indices = piece.replace("]", "").split("[")
        parts.append(name)
        parts.extend(int(i) for i in indices)
    return parts


def set_at(data: dict, where: str, value) -> None:
    keys = split(where)
    for key in keys[:-1]:
        data = data[key]
    data[keys[-1]] = value


def test_an_eye_inside_an_island_is_refused():
    base = Scene.default()
    island = dataclasses.replace(base.islands[0], x=0.0, y=20.0)     # the west island moved onto the eye
    ground = float(island.height(0.0, 0.0))
    assert ground > base.camera.eye_height                          # independent check: the eye is under ground
    with pytest.raises(SunsetError, match=r"^islands\[0\] puts the eye inside it"):
        dataclasses.replace(base, islands=(island,) + base.islands[1:])
    text = base.to_toml().replace("x = -300.0", "x = 0.0", 1).replace("y = 850.0", "y = 20.0", 1)
    with pytest.raises(SunsetError, match=r"^islands\[0\] puts the eye inside it"):
        Scene.from_toml(text)
