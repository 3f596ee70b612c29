"""sunset.explore driven through its widgets' Python API.

Each control is moved as a slider would move it (its ``value``), and the
picture shown is compared with what the package's one-call API draws for the
settings the control states (``sunset.picture`` of the stated scene, or the
RGB back end's ``render_rgb``): computed here, not taken from the explorer.
The saved scene file is rendered by the command line its comment gives, and
must give the same bytes.
"""

import shlex
import subprocess
import sys
import threading
from dataclasses import replace

import numpy as np
import pytest
from PIL import Image

import sunset
from sunset.cli import main
from sunset.explorer.picture import Renderer
from sunset.explorer.settings import Start, scene_for
from sunset.light.output import to_uint8
from sunset.pipeline.rgb import render_rgb
from sunset.recorder.colour_tables import tables
from sunset.tape.codes import CODE_MAP

SIZE = (48, 40)


@pytest.fixture
def explorer():
    ex = sunset.explore("carlas-island", size=SIZE)
    assert ex.wait(120) and ex.error == ""
    yield ex
    ex.close()


def expected(scene, view):
    """The picture of ``scene`` at ``view``'s settings, drawn by the public API."""
    if view.shading == "rgb":
        return to_uint8(render_rgb(scene, view.t, view.hours, 1, view.reflections))
    return sunset.picture(scene, t=view.t, hours=view.hours, size=None, reflections=view.reflections, seed=view.seed)


def test_import_sunset_does_not_import_the_widgets():
    code = ("import sys, sunset; sunset.explore.__doc__; "
            "assert 'sunset.explorer.widget' not in sys.modules; import sunset.explorer.settings; "
            "bad = [m for m in ('ipywidgets', 'anywidget', 'traitlets') if m in sys.modules]; print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
    assert "explore" in sunset.__all__ and callable(sunset.explore)


def test_it_opens_on_carlas_island_at_512_squared():
    ex = sunset.explore()
    try:
        assert ex.wait(120) and ex.error == ""
        assert ex.picture.rgb.shape == (512, 512, 3)
        assert np.array_equal(ex.picture.rgb, sunset.picture("carlas-island", t=0.0, hours=0.35, size=(512, 512)))
        assert (ex.image.width, ex.image.height, ex.serial, ex.image.serial) == (512, 512, 1, 1)
        shown = np.frombuffer(ex.image.rgba, dtype=np.uint8).reshape(512, 512, 4)
        assert np.array_equal(shown[..., :3], ex.picture.rgb) and np.all(shown[..., 3] == 255)
    finally:
        ex.close()


# (control, value, what the scene or view must say afterwards)
CONTROLS = [
    ("hours", 2.5, lambda s, v: v.hours == 2.5),
    ("t", 1.75, lambda s, v: v.t == 1.75),
    ("azimuth", -6.0, lambda s, v: s.sun.azimuth == -6.0),
    ("trains[0].amplitude", 0.8, lambda s, v: s.sea.trains[0].amplitude == 0.8),
    ("trains[1].rung", 3, lambda s, v: s.sea.trains[1].wavelength == 40.0 / 9),
    ("trains[2].direction", 90.0, lambda s, v: s.sea.trains[2].direction == 90.0),
    ("eye_height", 9.0, lambda s, v: s.camera.eye_height == 9.0),
    ("heading", 12.0, lambda s, v: s.sun.azimuth == pytest.approx(1.1 - 12.0) and s.islands[1].x < 230.0),
    ("pitch", 2.0, lambda s, v: np.degrees(np.arctan((s.camera.zy_min + s.camera.zy_max) / 2)) == pytest.approx(2.0)),
    ("reflections", 0, lambda s, v: v.reflections == 0),
    ("shading", "rgb", lambda s, v: v.shading == "rgb"),
]


@pytest.mark.parametrize("name, value, says", CONTROLS, ids=[c[0] for c in CONTROLS])
def test_each_control_changes_what_it_states(explorer, name, value, says):
    before = explorer.picture
    explorer.controls[name].value = value
    assert explorer.wait(120) and explorer.error == ""
    pic = explorer.picture
    assert pic is not before and explorer.serial == 2
    assert says(pic.scene, pic.view)
    assert pic.scene == scene_for(explorer.start, pic.view)
    # every other control is where it was
    assert replace(pic.view, **{k: getattr(before.view, k) for k in ("hours", "t", "azimuth", "eye_height", "heading",
                                                                     "pitch", "reflections", "shading")}) \
        == replace(before.view, trains=pic.view.trains) or name.startswith("trains[")
    assert np.array_equal(pic.rgb, expected(pic.scene, pic.view))
    assert not np.array_equal(pic.rgb, before.rgb)


def saved_command(path):
    """The ``sunset render`` command of a saved scene's comment, as argv for sunset.cli.main."""
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("#   sunset render "):
            return shlex.split(line[len("#   sunset "):])
    raise AssertionError("no render command in the saved scene")


@pytest.mark.parametrize("shading", ["codes", "rgb"])
def test_saved_scene_renders_the_same_picture_from_the_command_line(explorer, tmp_path, monkeypatch, shading):
    c = explorer.controls
    c["hours"].value = -0.2
    c["t"].value = 3.21
    c["trains[1].rung"].value = 5
    c["trains[0].direction"].value = 230.0
    c["heading"].value = -8.5
    c["pitch"].value = -4.0
    c["reflections"].value = 1
    c["shading"].value = shading
    path = explorer.save_scene(tmp_path / "my explored.toml")
    pic = explorer.picture
    argv = saved_command(path)
    assert argv[:2] == ["render", "my explored.toml"]
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 0
    drawn = np.asarray(Image.open(tmp_path / "picture.png"))
    assert drawn.shape == pic.rgb.shape and np.array_equal(drawn, pic.rgb)
    scene = sunset.Scene.from_toml(path)
    assert scene == pic.scene and scene.camera.width == SIZE[0]
    if shading == "codes":
        assert np.array_equal(sunset.picture(path, t=3.21, hours=-0.2, size=None, reflections=1), pic.rgb)


def test_saved_scene_is_accepted_by_film_and_player(explorer, tmp_path, monkeypatch):
    explorer.controls["trains[2].amplitude"].value = 0.2
    path = explorer.save_scene(tmp_path / "s.toml")
    monkeypatch.chdir(tmp_path)
    assert main(["player", "s.toml", "-o", "p.html", "--frames", "2", "--size", "16x16", "--quiet"]) == 0
    assert main(["film", "s.toml", "-o", "f.mp4", "--frames", "2", "--size", "16x16", "--from-hours", "0.5",
                 "--to-hours", "0.4", "--jobs", "1", "--quiet"]) == 0
    assert (tmp_path / "p.html").stat().st_size > 0 and (tmp_path / "f.mp4").stat().st_size > 0


def test_a_refused_setting_shows_its_line_and_the_last_picture_stays(explorer):
    good, shown = explorer.picture, explorer.image.rgba
    explorer.controls["trains[3].amplitude"].value = 0.9          # too steep for a 2.5 m wave
    assert explorer.wait(120)
    line = "sea.trains[3].amplitude must be at most wavelength/2π = 0.3979 m (a first-harmonic slope k·a of 1), got 0.9"
    assert explorer.error == line
    assert line in explorer.status.value and "\n" not in explorer.status.value
    assert explorer.picture is good and explorer.image.rgba == shown and explorer.serial == 1
    explorer.controls["heading"].value = 90.0                     # the west island behind the eye
    assert explorer.wait(120)
    assert explorer.error.startswith("sea.trains[3].amplitude")   # the steep train is still refused first
    explorer.controls["trains[3].amplitude"].value = 0.02
    assert explorer.wait(120)
    assert explorer.error.startswith("heading: islands[0].y must be positive: the island is behind the eye")
    explorer.controls["heading"].value = 0.0
    assert explorer.wait(120) and explorer.error == "" and explorer.serial == 2
    assert "rendered in" in explorer.status.value


def test_a_setting_over_the_work_budget_is_refused_before_any_work():
    # a window 0.01 tall just below the horizon: each pitch step down multiplies the sea's samples per pixel
    scene = sunset.Scene.named("carlas-island")
    scene = replace(scene, camera=replace(scene.camera, zy_min=-0.305, zy_max=-0.295))
    ex = sunset.explore(scene, size=(32, 32))
    try:
        assert ex.wait(120) and ex.error == ""
        good = ex.picture
        ex.controls["pitch"].value = -30.0
        assert ex.wait(120)
        assert ex.error.startswith("camera: the picture window asks for 361 sea samples per pixel (at most 256)")
        assert "\n" not in ex.error
        assert ex.picture is good
    finally:
        ex.close()


def test_the_readout_says_what_the_code_under_the_pointer_means(explorer):
    pic = explorer.picture
    sky_row, sea_row = 2, SIZE[1] - 2
    for row in (sky_row, sea_row):
        explorer.image.pointer = [7, row]
        text = explorer.image.readout
        code = int(pic.codes[row, 7])
        group = next(r for r in CODE_MAP.ranges if r.start <= code < r.stop)
        assert text.startswith(f"pixel (7, {row}): code {code}, {group.name} (codes {group.start}–{group.stop - 1})")
        entry = tables(pic.scene.sun, pic.view.hours)[:, code]
        assert f"red {entry[0]}, green {entry[1]}, blue {entry[2]}" in text
        # away from the sun's disk, the colour drawn is the table's entry for the code (the film recorder's rule)
        assert tuple(int(v) for v in pic.rgb[row, 7]) == tuple(int(v) for v in entry)
        assert text == explorer.readout(7, row)
    assert explorer.readout(7, sky_row).splitlines()[1].startswith("R_z band")
    explorer.image.pointer = []
    assert explorer.image.readout == ""
    explorer.controls["shading"].value = "rgb"
    assert explorer.wait(120)
    assert "the RGB back end writes no codes" in explorer.readout(3, 3)
    with pytest.raises(sunset.SunsetError, match="col must"):
        explorer.readout(SIZE[0], 0)


def test_the_newest_setting_wins_and_stale_ones_are_never_rendered():
    start = Start.of("carlas-island", size=SIZE)
    real = Renderer(start)
    gate, holding = threading.Event(), threading.Event()
    calls = []

    def slow(view):
        calls.append(view.hours)
        if len(calls) == 2:              # the first move's render: held until the slider has moved on
            holding.set()
            assert gate.wait(60)
        return real(view)

    from sunset.explorer.widget import Explorer

    ex = Explorer(start, renderer=slow)
    try:
        assert ex.wait(120)
        hours = ex.controls["hours"]
        hours.value = 1.0
        assert holding.wait(60)
        for h in (1.25, 1.5, 1.75, 2.0):           # the slider passes four more values
            hours.value = h
        gate.set()
        assert ex.wait(120)
        assert calls == [0.35, 1.0, 2.0]
        assert ex.picture.view.hours == 2.0 and ex.serial == 2           # 1.0 was rendered, then dropped
        assert np.array_equal(ex.picture.rgb, sunset.picture("carlas-island", hours=2.0, size=SIZE))
    finally:
        ex.close()


def test_explore_checks_its_arguments():
    with pytest.raises(sunset.SunsetError, match="no scene named"):
        sunset.explore("atlantis")
    with pytest.raises(sunset.SunsetError, match="hours must be within"):
        sunset.explore(hours=13.0)
    with pytest.raises(sunset.SunsetError, match="shading must be one of"):
        sunset.explore(shading="oil")


def test_a_slider_echoing_its_first_value_on_its_grid_changes_nothing(explorer):
    """A slider's front end sends back min + k·step: −6.800000000000001 for the pitch −6.8 (−30 + 232 × 0.1)."""
    first = explorer.picture
    for name in ("pitch", "hours", "trains[0].direction", "azimuth"):
        c = explorer.controls[name]
        k = round((c.value - c.min) / c.step)
        echoed = c.min + k * c.step
        c.value = echoed
    assert explorer.controls["pitch"].value == -30.0 + 232 * 0.1 != -6.8
    assert explorer.wait(60) and explorer.serial == 1 and explorer.picture is first
    explorer.controls["pitch"].value = -3.0                 # moved, and back onto the grid near its first value
    assert explorer.wait(60) and explorer.serial == 2
    explorer.controls["pitch"].value = -30.0 + 232 * 0.1
    assert explorer.wait(60) and explorer.serial == 3
    assert explorer.picture.view.pitch == -6.8 and np.array_equal(explorer.picture.rgb, first.rgb)


def test_the_save_button_writes_the_file_named_in_its_box(explorer, tmp_path):
    explorer.controls["hours"].value = 1.5
    explorer.file.value = str(tmp_path / "button.toml")
    explorer.save_button.click()
    assert explorer.saved.value == f"saved {tmp_path / 'button.toml'}"
    assert sunset.Scene.from_toml(tmp_path / "button.toml") == explorer.picture.scene
    assert "--hours=1.5 " in (tmp_path / "button.toml").read_text(encoding="utf-8")
    explorer.file.value = str(tmp_path / "no such folder" / "x.toml")
    explorer.save_button.click()
    assert "no such folder" in explorer.saved.value and "\n" not in explorer.saved.value
    assert not (tmp_path / "no such folder").exists()


def test_what_the_renderer_keeps_between_views_gives_the_bytes_of_a_fresh_render():
    """The kept codes, islands' pass, still part of the cycle, frame and geometry, each reused, against sunset.picture."""
    start = Start.of("post-in-the-swell", size=SIZE)
    renderer = Renderer(start)
    v = start.view
    steps = [v, replace(v, t=0.4), replace(v, t=0.8), replace(v, t=1.2),            # the cycle's still part
             replace(v, t=1.2, azimuth=-5.0), replace(v, t=1.2, azimuth=-9.0),      # the frame, the sun moved
             replace(v, t=1.2, azimuth=-9.0, hours=2.0),                            # the codes, re-exposed
             replace(v, t=1.2, heading=4.0), replace(v, t=1.6, heading=4.0),
             replace(v, shading="rgb"), replace(v, shading="rgb", azimuth=3.0),     # the geometry, the sun moved
             replace(v, shading="rgb", azimuth=3.0, hours=1.0), replace(v, shading="rgb", t=0.9), replace(v, t=0.4)]
    for view in steps:
        pic = renderer(view)
        assert np.array_equal(pic.rgb, expected(scene_for(start, view), view)), view


@pytest.mark.parametrize("name, turns", [("carlas-island-in-the-wind", False), ("carlas-island-clouds", False),
                                         ("carlas-island", True)])
def test_a_scene_that_cannot_turn_has_its_heading_slider_disabled_and_says_why(name, turns):
    """A wind sea's tile (or a cloud layer's cells) lies along x and y: its explorer offers no heading, the
    slider's tooltip gives the reason, and a heading asked for anyway is refused in one line, the picture kept."""
    from sunset.explorer.settings import cannot_turn

    ex = sunset.explore(name, size=(24, 20))
    try:
        assert ex.wait(120) and ex.error == ""
        slider = ex.controls["heading"]
        assert slider.disabled is not turns
        why = cannot_turn(ex.start.scene)
        assert (why is None) is turns
        if turns:
            return
        assert slider.tooltip == why and ("wind sea" in why if "wind" in name else "clouds" in why)
        good = ex.picture
        slider.value = 5.0                        # as a program, not the disabled slider, would set it
        assert ex.wait(120)
        assert ex.error == f"heading: {why}; set heading to 0" and "\n" not in ex.status.value
        assert ex.picture is good
    finally:
        ex.close()
