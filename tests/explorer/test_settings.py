"""What each of the explorer's controls changes in the scene (sunset.explorer.settings).

The turned scene is checked against the scene it came from by evaluating both:
an island's height, the sea's elevation and the sun's circle at a point p of
the old scene equal the new scene's at R p (R the turn), which the quadratic
forms, wave vectors and angles of the turned scene must reproduce.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

import sunset
from sunset.errors import SunsetError
from sunset.explorer.settings import Start, TrainControl, View, pitch_of, rung_of, scene_for, turned


@pytest.fixture(scope="module")
def start():
    return Start.of("carlas-island", size=(64, 48))


def with_train(view, i, **kw):
    trains = list(view.trains)
    trains[i] = replace(trains[i], **kw)
    return replace(view, trains=tuple(trains))


def test_the_controls_at_their_start_give_the_scene_itself(start):
    scene = sunset.Scene.named("carlas-island").with_size(64, 48)
    assert start.scene == scene
    assert scene_for(start, start.view) is start.scene
    v = start.view
    assert (v.hours, v.t, v.heading, v.reflections, v.shading, v.seed) == (0.35, 0.0, 0.0, 2, "codes", 0)
    assert v.azimuth == scene.sun.azimuth and v.eye_height == scene.camera.eye_height
    assert [tc.amplitude for tc in v.trains] == [tr.amplitude for tr in scene.sea.trains]
    assert [tc.direction for tc in v.trains] == [tr.direction for tr in scene.sea.trains]
    # Carla's Island's trains stand on the rungs 40/n² m, n = 1, 2, 3, 4
    assert start.fundamental == 40.0 and [tc.rung for tc in v.trains] == [1, 2, 3, 4]
    # the window's centre: ζ = (−0.42 + 0.18)/2 = −0.12, atan(−0.12) = −6.84°
    assert v.pitch == -6.8


def test_sun_azimuth(start):
    scene = scene_for(start, replace(start.view, azimuth=-7.5))
    assert scene.sun == replace(start.scene.sun, azimuth=-7.5)
    assert (scene.sea, scene.camera, scene.islands) == (start.scene.sea, start.scene.camera, start.scene.islands)
    # the setting sun's direction, 7.5° left of the view axis
    assert np.allclose(scene.sun.U, [math.sin(math.radians(-7.5)), math.cos(math.radians(-7.5)), 0.0])


def test_amplitude_and_direction_of_one_train(start):
    scene = scene_for(start, with_train(start.view, 1, amplitude=0.3, direction=180.0))
    trains, before = scene.sea.trains, start.scene.sea.trains
    assert trains[1] == replace(before[1], amplitude=0.3, direction=180.0)
    assert trains[0] == before[0] and trains[2:] == before[2:]
    # travelling toward −x: the crest at x = 0 is at x = −c t a little later (c = √(gλ/2π))
    c = math.sqrt(9.80665 * 10.0 / (2 * math.pi))
    only = sunset.Sea((trains[1],))
    assert only.elevation(-c * 0.7, 0.0, 0.7) == pytest.approx(0.3 * math.cos(before[1].phase), abs=1e-9)


@pytest.mark.parametrize("rung", [1, 3, 5, 7])
def test_a_rung_puts_the_train_on_the_ladder_and_keeps_the_cycle(start, rung):
    scene = scene_for(start, with_train(start.view, 1, rung=rung))
    assert scene.sea.trains[1].wavelength == 40.0 / rung**2
    # ω = √(g k) = rung · ω₁: the sea still repeats after T = √(2π λ₁ / g)
    assert scene.sea.period == pytest.approx(math.sqrt(2 * math.pi * 40.0 / 9.80665), rel=1e-12)


def test_a_train_off_the_ladder_keeps_its_wavelength_until_its_rung_moves():
    scene = sunset.Scene.named("carlas-island").with_size(32, 32)
    trains = list(scene.sea.trains)
    trains[2] = replace(trains[2], wavelength=5.0)             # between the rungs 40/9 and 40/4
    start = Start.of(replace(scene, sea=sunset.Sea(tuple(trains))), size=(32, 32))
    assert start.view.trains[2].rung == rung_of(5.0, 40.0) == 3
    same = scene_for(start, with_train(start.view, 2, amplitude=0.04))
    assert same.sea.trains[2].wavelength == 5.0
    moved = scene_for(start, with_train(start.view, 2, rung=4))
    assert moved.sea.trains[2].wavelength == 2.5


def test_eye_height(start):
    scene = scene_for(start, replace(start.view, eye_height=12.5))
    assert scene.camera == replace(start.scene.camera, eye_height=12.5)


@pytest.mark.parametrize("pitch", [-20.0, -3.3, 0.0, 10.0])
def test_pitch_slides_the_window_and_keeps_its_height(start, pitch):
    scene = scene_for(start, replace(start.view, pitch=pitch))
    cam, cam0 = scene.camera, start.scene.camera
    assert math.degrees(math.atan((cam.zy_min + cam.zy_max) / 2)) == pytest.approx(pitch, abs=1e-12)
    assert cam.zy_max - cam.zy_min == pytest.approx(cam0.zy_max - cam0.zy_min, rel=1e-12)
    assert (cam.s_min, cam.s_max, cam.width, cam.height) == (cam0.s_min, cam0.s_max, cam0.width, cam0.height)
    assert pitch_of(cam) == round(pitch, 1)


def rotation(heading):
    a = math.radians(heading)
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


@pytest.mark.parametrize("heading", [-20.0, 7.5, 25.0])
def test_heading_turns_the_world_the_other_way(start, heading):
    scene, before = scene_for(start, replace(start.view, heading=heading)), start.scene
    R = rotation(heading)
    rng = np.random.default_rng(1)
    for old, new in zip(before.islands, scene.islands):
        p = np.array([old.x, old.y])[:, None] + rng.uniform(-400, 400, (2, 500))
        q = R @ p
        assert np.allclose(new.height(q[0], q[1]), old.height(p[0], p[1]), rtol=0, atol=1e-9)
        assert np.array_equal(new.part(q[0], q[1]), old.part(p[0], p[1])) or \
            np.mean(new.part(q[0], q[1]) != old.part(p[0], p[1])) < 0.01      # creases, to rounding
        # the apex, seen from the eye, lies `heading` degrees further left
        bearing = math.degrees(math.atan2(old.x, old.y))
        assert math.degrees(math.atan2(new.x, new.y)) == pytest.approx(bearing - heading, abs=1e-9)
    p = rng.uniform(-200, 200, (2, 300))
    q = R @ p
    assert np.allclose(scene.sea.elevation(q[0], q[1], 1.3), before.sea.elevation(p[0], p[1], 1.3), atol=1e-9)
    R3 = np.eye(3)
    R3[:2, :2] = R
    for vec in ("U", "V", "W"):
        assert np.allclose(getattr(scene.sun, vec), R3 @ getattr(before.sun, vec), atol=1e-12)
    assert scene.camera == before.camera


def test_heading_turns_posts_and_is_refused_with_clouds():
    scene = sunset.Scene.named("post-in-the-swell")
    post, new = scene.posts[0], turned(scene, 30.0).posts[0]
    assert np.allclose([new.x, new.y], rotation(30.0) @ [post.x, post.y])
    assert (new.radius, new.top, new.depth) == (post.radius, post.top, post.depth)
    assert turned(scene, 0.0) is scene
    cloudy = sunset.Scene.named("carlas-island-clouds")
    with pytest.raises(SunsetError, match="^heading: a scene with clouds cannot turn"):
        turned(cloudy, 5.0)
    data = sunset.Scene.named("carlas-island").to_dict()
    data["sea"] = {"wind": {"speed": 7.0, "direction": 260.0, "fetch": float("inf"), "seed": 1, "tile_points": 64,
                            "tile_size": 128.0, "cycle": 64.0}}
    windy = sunset.Scene.from_dict(data)
    with pytest.raises(SunsetError, match="^heading: a scene with a wind sea cannot turn"):
        turned(windy, 5.0)
    # the other controls keep the wind sea
    start = Start.of(windy, size=(16, 16))
    assert start.view.trains == () and start.fundamental == 0.0
    assert scene_for(start, replace(start.view, eye_height=3.0)).sea == windy.sea


@pytest.mark.parametrize("change, message", [
    (dict(heading=90.0), "heading: islands[0].y must be positive: the island is behind the eye"),
    (dict(eye_height=0.0005), "camera.eye_height must be at least 0.001 m, got 0.0005"),
    (dict(pitch=85.0), "pitch must be in [-80, 80] degrees, got 85.0"),
    (dict(heading=200.0), "heading must be in [-180, 180] degrees, got 200.0"),
    (dict(azimuth=400.0), "sun.azimuth must be in [-360, 360] degrees, got 400.0"),
])
def test_refused_settings_name_the_field(start, change, message):
    with pytest.raises(SunsetError) as err:
        scene_for(start, replace(start.view, **change))
    assert str(err.value) == message or message.endswith("eye") and str(err.value).startswith(message + " (y = -")


def test_a_train_too_steep_for_its_rung_names_the_train(start):
    with pytest.raises(SunsetError, match=r"^sea\.trains\[3\]\.amplitude must be at most wavelength/2π = 0\.3979 m"):
        scene_for(start, with_train(start.view, 3, amplitude=0.9))
    with pytest.raises(SunsetError, match=r"^sea\.trains\[0\]\.amplitude must be at most wavelength/2π = 0\.3979 m .*got 0\.5$"):
        scene_for(start, with_train(start.view, 0, rung=4))       # 0.5 m on a 2.5 m wave


@pytest.mark.parametrize("kwargs, message", [
    (dict(reflections=3), "reflections"),
    (dict(shading="crayon"), "shading must be one of codes, rgb, got 'crayon'"),
    (dict(seed=-1), "seed"),
])
def test_a_view_checks_its_own_fields(start, kwargs, message):
    with pytest.raises(SunsetError, match=message.replace("(", r"\(")):
        replace(start.view, **kwargs)


def test_start_checks_its_arguments():
    with pytest.raises(SunsetError, match="hours must be within ±12"):
        Start.of("carlas-island", hours=13.0)
    with pytest.raises(SunsetError, match="t must be a finite number"):
        Start.of("carlas-island", t=float("nan"))
    with pytest.raises(SunsetError, match="size must be"):
        Start.of("carlas-island", size=512)
    with pytest.raises(SunsetError, match="no scene named"):
        Start.of("atlantis")
    assert TrainControl(0.1, 2, 90.0) == View(0.0, 0.0, 0.0, (TrainControl(0.1, 2, 90.0),), 2.0, 0.0, 0.0).trains[0]
