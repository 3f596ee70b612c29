"""The colour-table player (sunset/recorder/player.py): its data, its composition, its file, its command."""

import base64
import io
import json
import math
import re

import numpy as np
import pytest
from PIL import Image

from sunset import expose, Scene
from sunset.cli import main
from sunset.errors import SunsetError
from sunset.recorder.colour_tables import sun_colour, tables
from sunset.recorder.dicomed import sun_coverage
from sunset.pipeline.film import player_data, render_cycle, write_player
from sunset.recorder.player import (HTML_SUFFIXES, PLAYER_FORMAT, code_meanings, compose, data_tables,
                                    decode_codes, encode_thresholds, hours_grid, nearest_hour,
                                    player_fragment, player_html, player_size, quantise, read_player_data,
                                    sun_geometry, _DATA_ID)
from sunset.tape.codes import CODE_MAP
from sunset.model.waves import Sea, WaveTrain

SIZE = (48, 40)


def srgb_byte(x: float) -> int:
    """The sRGB encoding of IEC 61966-2-1 in plain Python floats, rounded half to even and clipped."""
    x = min(max(x, 0.0), 1.0)
    e = 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055
    return min(max(round(e * 255.0), 0), 255)


def sun_scene(size=SIZE):
    """The default scene with its window moved so that the sun sets in the middle of the picture."""
    base = Scene.default()
    sun = base.sun
    p = sun.position(0.05)
    s = p[0] / p[1]
    cam = base.camera
    from dataclasses import replace

    camera = replace(cam, width=size[0], height=size[1], s_min=s - 0.04, s_max=s + 0.04, zy_min=-0.05, zy_max=0.03)
    return replace(base, camera=camera)


@pytest.fixture(scope="module")
def scene():
    return sun_scene()


@pytest.fixture(scope="module")
def tape(scene):
    return render_cycle(scene, 3, reflections=2, seed=5, progress=False, workers=1)


@pytest.fixture(scope="module")
def grid():
    return hours_grid(0.3, -0.1, 0.05)


@pytest.fixture(scope="module")
def data(tape, grid):
    return player_data(tape, grid, start_hours=0.12)


# --------------------------------------------------------------------------- the grid of hours
@pytest.mark.parametrize("a, b, step", [(1.5, -0.25, 0.025), (0.3, -0.1, 0.05), (-0.25, 1.5, 0.1),
                                        (2.0, 1.99, 0.025), (0.0, 1.0, 0.3), (1.0, 0.0, 0.25)])
def test_hours_grid_includes_both_ends_with_the_fewest_points(a, b, step):
    g = hours_grid(a, b, step)
    assert g[0] == a and g[-1] == b                      # exactly, both ends
    d = np.diff(g)
    assert np.all(np.sign(d) == np.sign(b - a))
    np.testing.assert_allclose(d, d[0], rtol=1e-9)      # evenly spaced
    assert np.all(np.abs(d) <= step * (1 + 1e-9))
    # one point fewer would need a larger step
    assert abs(b - a) / (len(g) - 2) > step if len(g) > 2 else True


def test_hours_grid_one_point_and_bad_values():
    assert hours_grid(0.4, 0.4).tolist() == [0.4]
    assert len(hours_grid(1.5, -0.25)) == 71             # 1.75 h in steps of 1.5 minutes
    for bad in (math.nan, math.inf):
        with pytest.raises(SunsetError, match="from_hours"):
            hours_grid(bad, 0.0)
        with pytest.raises(SunsetError, match="to_hours"):
            hours_grid(0.0, bad)
    with pytest.raises(SunsetError, match="step"):
        hours_grid(0.0, 1.0, 0.0)


def test_nearest_hour_is_the_first_of_the_closest():
    g = [1.0, 0.5, 0.0, -0.5]
    rng = np.random.default_rng(0)
    for h in rng.uniform(-1.5, 2.0, 200):
        d = [abs(x - h) for x in g]
        assert nearest_hour(g, h) == d.index(min(d))
    assert nearest_hour(g, 0.25) == 1                    # a tie goes to the first
    assert nearest_hour(g, 9.0) == 0 and nearest_hour(g, -9.0) == 3


def test_player_size_keeps_the_aspect():
    assert player_size(Scene.default()) == (510, 512)
    assert player_size(Scene.default().with_size(800, 400), 100) == (100, 50)
    assert player_size(Scene.default().with_size(3, 1000), 10) == (1, 10)


# --------------------------------------------------------------------------- exact rounding by lookups
def test_encode_thresholds_reproduce_the_rounding_exactly():
    t = encode_thresholds()
    assert t.shape == (255,) and np.all(np.diff(t) > 0) and t[0] > 0 and t[-1] <= 1.0
    rng = np.random.default_rng(1)
    x = np.concatenate([rng.random(100_000), rng.random(1000) * 1e-3, t, np.nextafter(t, 0), np.nextafter(t, 2),
                        [0.0, 1.0, -0.5, 1.5, 5e-324]])
    np.testing.assert_array_equal(quantise(x), np.searchsorted(t, x, side="right"))
    # each threshold is where the byte steps up, to the last bit
    b = np.arange(1, 256)
    np.testing.assert_array_equal(quantise(t), b)
    np.testing.assert_array_equal(quantise(np.nextafter(t, 0)), b - 1)
    # and the byte is the sRGB encoding of IEC 61966-2-1, computed here in plain Python
    for v in x[::97]:
        assert int(np.searchsorted(t, v, side="right")) == srgb_byte(float(v))


# --------------------------------------------------------------------------- the sun on the picture
def test_sun_geometry_is_the_coverage_of_expose(scene, grid):
    n2 = 16 * 16
    seen_rim = False
    for h in grid:
        g = sun_geometry(scene, float(h))
        rows, cols, cov = sun_coverage(scene.camera, scene.sun, float(h))
        full = np.zeros((scene.camera.height, scene.camera.width))
        full[rows, cols] = cov
        if g is None:
            assert not np.any(full > 0)
            continue
        k = np.zeros(full.shape, np.int64)
        k[g["r0"]:g["r0"] + g["h"], g["c0"]:g["c0"] + g["w"]] = np.reshape(g["cover"], (g["h"], g["w"]))
        np.testing.assert_array_equal(k / n2, full)       # every pixel, inside the box and out
        assert g["h"] * g["w"] == len(g["cover"])
        # the box is the tightest: each of its edges has a covered pixel
        box = k[g["r0"]:g["r0"] + g["h"], g["c0"]:g["c0"] + g["w"]]
        assert box[0].any() and box[-1].any() and box[:, 0].any() and box[:, -1].any()
        np.testing.assert_array_equal(g["colour"], sun_colour(scene.sun, float(h)))
        seen_rim |= bool(np.any((box > 0) & (box < n2)))
    assert seen_rim


def test_no_sun_geometry_when_the_sun_is_out_of_the_picture(scene):
    assert sun_geometry(scene, 3.0) is None               # high above the window
    assert sun_geometry(scene, -0.5) is None              # set


# --------------------------------------------------------------------------- the data
def test_player_data_holds_the_tape_tables_and_grid(tape, grid, data):
    assert data["format"] == PLAYER_FORMAT
    assert (data["width"], data["height"], data["frames"]) == (SIZE[0], SIZE[1], 3)
    np.testing.assert_array_equal(decode_codes(data), tape.codes)         # lossless
    for b64 in data["codes"]:
        with Image.open(io.BytesIO(base64.b64decode(b64))) as img:
            assert img.format == "PNG" and img.mode == "L"
    assert data["hours"] == [float(h) for h in grid]
    tabs = data_tables(data)
    for h, hours in enumerate(grid):
        np.testing.assert_array_equal(tabs[h], tables(tape.scene.sun, float(hours)))
    # frame F is the sea at F T/N
    T = tape.scene.sea.period
    np.testing.assert_allclose(data["times"], np.arange(3) * T / 3, rtol=0, atol=1e-12)
    assert data["period"] == T
    assert data["start_hours"] == 0.12
    np.testing.assert_allclose(data["elevation"], np.degrees(tape.scene.sun.elevation(grid)))
    assert Scene.from_toml(data["scene"]) == tape.scene
    assert data["sky_start"] == CODE_MAP.sky.start


def test_player_data_is_the_same_over_two_processes(tape, grid, data):
    assert player_data(tape, grid, start_hours=0.12, workers=2) == data
    assert player_data(tape, grid, start_hours=0.12, workers=1) == data


def test_compose_is_expose_for_every_frame_and_hour(tape, grid, data):
    """The data is enough: table lookups plus the exported sun give sunset.expose's pixels exactly."""
    rim = 0
    for f in range(len(tape)):
        for h, hours in enumerate(grid):
            np.testing.assert_array_equal(compose(data, f, h), expose(tape.scene, tape.codes[f], float(hours)))
            s = data["sun"][h]
            if s is not None:
                k = np.reshape(s["cover"], (s["h"], s["w"]))
                box = tape.codes[f][s["r0"]:s["r0"] + s["h"], s["c0"]:s["c0"] + s["w"]]
                rim += int(np.count_nonzero((k > 0) & (k < 256) & (box >= CODE_MAP.sky.start)))
    assert rim > 0                      # the anti-aliased rim was on sky pixels, so the mix was exercised


def test_code_meanings_and_groups(scene, data):
    m = code_meanings(scene.sun)
    assert len(m) == 256 and all(m)
    for r in CODE_MAP.ranges:                           # within a group, every number says something else
        assert len(set(m[r.start:r.stop])) == r.size
    assert "ψ" in m[CODE_MAP.hill.start] and "above the horizon" in m[CODE_MAP.sky.start]
    assert "reflected ray" in m[CODE_MAP.track.start] and "3δ" in m[CODE_MAP.halo.start]
    groups = data["groups"]
    assert [g["first"] for g in groups] == [r.start for r in CODE_MAP.ranges]
    assert groups[0]["first"] == 0 and groups[-1]["last"] == 255
    assert all(a["last"] + 1 == b["first"] for a, b in zip(groups, groups[1:]))


def test_player_html_is_self_contained_and_round_trips(data):
    page = player_html(data)
    assert read_player_data(page) == data
    assert page.count('id="sunset-player"') == 1 and 'id="sunset-dump"' in page
    # the data cannot end its script element early
    body = page.split('id="sunset-player-data">', 1)[1].split("</script>", 1)[0]
    assert "</" not in body
    json.loads(body)
    # nothing fetched: outside the data, no URL with a scheme, no src or href attribute, no fetching call
    rest = page.replace(body, "")
    assert not re.search(r"https?:|ftp:|file:", rest)
    assert not re.search(r"\b(src|href|srcset|action)\s*=", rest)
    assert "import(" not in rest and "fetch(" not in rest and "XMLHttpRequest" not in rest
    assert player_html(data) == page                   # deterministic
    assert player_fragment(data) in page


def test_read_player_data_rejects_other_pages(data):
    with pytest.raises(SunsetError, match="no sunset player data"):
        read_player_data("<html></html>")
    other = player_html({**data, "format": "sunset-player/0"})
    with pytest.raises(SunsetError, match="format"):
        read_player_data(other)
    page = player_html(data)
    start = page.index(f'id="{_DATA_ID}">') + len(f'id="{_DATA_ID}">')
    for damaged, words in ((page[:start] + "{" + page[start:], "not JSON"),
                           (page[:start] + "9" * 5000 + page[page.index("</script>", start):], "not JSON"),
                           (page[:start] + "[1]" + page[page.index("</script>", start):], "JSON object")):
        with pytest.raises(SunsetError, match=words):          # one line, not json's or dict's own error
            read_player_data(damaged)


# --------------------------------------------------------------------------- the file and the command
def test_write_player_is_deterministic(tmp_path, scene):
    a, b = tmp_path / "a.html", tmp_path / "b.html"
    write_player(scene, a, frames=2, size=(24, 20), from_hours=0.2, to_hours=0.1, progress=False)
    write_player(scene, b, frames=2, size=(24, 20), from_hours=0.2, to_hours=0.1, progress=False)
    assert a.read_bytes() == b.read_bytes()
    d = read_player_data(a.read_text(encoding="utf-8"))
    assert (d["width"], d["height"], d["frames"]) == (24, 20, 2)
    assert d["hours"][0] == 0.2 and d["hours"][-1] == 0.1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.html", "b.html"]


@pytest.mark.parametrize("kwargs, words", [
    ({"path": "p.txt"}, "must end in .html"),
    ({"frames": 0}, "frames"),
    ({"from_hours": math.nan}, "from_hours"),
    ({"to_hours": math.inf}, "to_hours"),
    ({"reflections": 3}, "reflections"),
    ({"from_hours": 13.0}, "within ±12 hours"),
    ({"to_hours": -100.0}, "within ±12 hours"),
    ({"path": "missing/p.html"}, "does not exist"),
])
def test_write_player_bad_arguments_leave_no_file(tmp_path, monkeypatch, scene, kwargs, words):
    monkeypatch.chdir(tmp_path)
    args = {"path": "p.html", "frames": 2, "size": (8, 8), "progress": False, **kwargs}
    with pytest.raises(SunsetError, match=words):
        write_player(scene, **args)
    assert list(tmp_path.iterdir()) == []


def test_a_sea_that_never_repeats_fails_before_the_work(tmp_path, scene):
    from dataclasses import replace

    odd = replace(scene, sea=Sea((WaveTrain(0.3, 40.0), WaveTrain(0.1, 40.0 / math.pi))))
    with pytest.raises(SunsetError, match="never repeats"):
        write_player(odd, tmp_path / "p.html", frames=2, size=(8, 8), progress=False)
    assert list(tmp_path.iterdir()) == []


def test_an_interrupted_player_leaves_no_file(tmp_path, monkeypatch, scene):
    import sunset.pipeline.film as player

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(player, "player_html", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_player(scene, tmp_path / "p.html", frames=1, size=(8, 8), from_hours=0.1, to_hours=0.1,
                     progress=False)
    assert list(tmp_path.iterdir()) == []


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_player_writes_one_file_with_a_progress_bar(capsys, tmp_path, monkeypatch):
    import sys

    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)    # progress bars are for terminals only
    out = tmp_path / "carla.html"
    code, _, err = run(capsys, "player", "carlas-island", "-o", str(out), "--frames", "2", "--size", "16x12",
                       "--from-hours", "0.5", "--to-hours", "0.25")
    assert code == 0, err
    assert "colour tables" in err and "rendering" in err          # the progress bars
    d = read_player_data(out.read_text(encoding="utf-8"))
    assert (d["width"], d["height"], d["frames"]) == (16, 12, 2)
    assert d["hours"][0] == 0.5 and d["hours"][-1] == 0.25 and len(d["hours"]) == 11
    assert [p.name for p in tmp_path.iterdir()] == ["carla.html"]
    code, _, err = run(capsys, "player", "carlas-island", "-o", str(out), "--frames", "1", "--size", "8x8",
                       "--from-hours", "0.5", "--to-hours", "0.5", "--quiet")
    assert code == 0 and err == ""


@pytest.mark.parametrize("argv, words", [
    (["--frames", "0"], "positive"),
    (["--frames", "x"], "whole number"),
    (["--size", "0x5"], "positive"),
    (["--size", "big"], "WIDTHxHEIGHT"),
    (["--from-hours", "nan"], "finite"),
    (["--to-hours", "-inf"], "finite"),
    (["--from-hours", "soon"], "number"),
    (["-o", "carla.png"], "must end in .html"),
    (["-o", "nowhere/carla.html"], "does not exist"),
    (["--bogus"], "unrecognized"),
])
def test_cli_player_bad_arguments(capsys, tmp_path, monkeypatch, argv, words):
    monkeypatch.chdir(tmp_path)
    args = ["player", "carlas-island", "-o", "carla.html", "--frames", "1", "--size", "8x8"]
    for k in range(0, len(argv), 2):            # an option given again replaces the default above
        if argv[k] in args:
            i = args.index(argv[k])
            del args[i:i + 2]
    code, out, err = run(capsys, *args, *argv)
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("sunset: error:") and words in err, err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_cli_player_bad_scene(capsys, tmp_path):
    code, _, err = run(capsys, "player", str(tmp_path / "none.toml"), "-o", str(tmp_path / "p.html"))
    assert code == 2 and "no such scene file" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []
    code, _, err = run(capsys, "player", "carlas-island")
    assert code == 2 and "-o" in err


def test_a_cloudy_scene_plays_with_its_own_code_map():
    """Clouds change the code map; the player's data follows the scene and still composes to expose."""
    from dataclasses import replace

    from sunset.model.scene import load_named_scene
    from sunset.tape.codes import CLOUDY_CODE_MAP

    cloudy = load_named_scene("carlas-island-clouds")
    scene = replace(cloudy, camera=replace(cloudy.camera, width=48, height=40)).still()
    tape = render_cycle(scene, 1, reflections=1, seed=2, progress=False, workers=1)
    grid = hours_grid(0.4, 0.0, 0.2)
    data = player_data(tape, grid)
    assert data["sky_start"] == CLOUDY_CODE_MAP.sky.start
    assert [g["name"] for g in data["groups"]] == [r.name for r in CLOUDY_CODE_MAP.ranges]
    assert "cloud depth band" in data["meanings"][CLOUDY_CODE_MAP.cloud.start]
    assert np.any(CLOUDY_CODE_MAP.cloud.contains(tape.codes[0]))
    for h, hours in enumerate(grid):
        np.testing.assert_array_equal(compose(data, 0, h), expose(scene, tape.codes[0], float(hours)))
