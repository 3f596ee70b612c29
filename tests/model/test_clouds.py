"""The cloud layer (sunset/model/clouds.py): height functions, chords, validation, TOML, light."""

import math

import numpy as np
import pytest

from sunset.errors import SunsetError
from sunset.model.clouds import Billow, CloudCell, Clouds, cloud_radiance
from sunset.model.scene import Scene, load_named_scene
from sunset.model.sun import Sun

CELL = CloudCell(x=100.0, y=9000.0, a=2000.0, b=3000.0, top=400.0, bottom=150.0,
                 billows=(Billow(0.3, 0.002, 0.001),))
LAYER = Clouds(1500.0, (CELL, CloudCell(x=-3000.0, y=12000.0, a=1500.0, b=1500.0, top=200.0, bottom=300.0)))


def test_thickness_at_the_centre_and_outside_is_the_closed_form():
    T, B = LAYER.thickness(100.0, 9000.0)
    w = 1.0 + 0.3 * math.cos(0.002 * 100.0 + 0.001 * 9000.0)
    assert T == pytest.approx(400.0 * w, rel=1e-12) and B == pytest.approx(150.0 * w, rel=1e-12)
    T, B = LAYER.thickness(100.0 + 2000.0 * 1.0001, 9000.0)       # just outside the ellipse
    assert T == 0.0 and B == 0.0


def test_thickness_closes_to_zero_at_the_rim_as_a_square_root():
    eps = np.array([1e-2, 1e-4, 1e-6])
    x = 100.0 + 2000.0 * np.sqrt(1.0 - eps)                       # q = eps on the x axis through the centre
    T, _ = LAYER.cells[0].top * LAYER.cells[0].profile(x, 9000.0), None
    w = 1.0 + 0.3 * np.cos(0.002 * x + 9.0)
    np.testing.assert_allclose(T, 400.0 * np.sqrt(eps) * w, rtol=1e-6)


def test_overlapping_cells_make_one_segment_the_union():
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-5000, 3000, 4000), rng.uniform(6000, 14000, 4000)
    T, B = LAYER.thickness(x, y)
    per = [(c.top * c.profile(x, y), c.bottom * c.profile(x, y)) for c in LAYER.cells]
    np.testing.assert_array_equal(T, np.maximum(per[0][0], per[1][0]))
    np.testing.assert_array_equal(B, np.maximum(per[0][1], per[1][1]))
    z = rng.uniform(1000, 2100, x.size)
    member = np.zeros(x.size, bool)
    for t_, b_ in per:                                              # inside some cell's own segment
        member |= (t_ + b_ > 0) & (z >= 1500 - b_) & (z <= 1500 + t_)
    np.testing.assert_array_equal(LAYER.inside(x, y, z), member)


@pytest.mark.parametrize("s", [0.0, 0.01, -0.3, 0.25, 2.0])
def test_chord_against_a_dense_walk_along_the_scan_line(s):
    y = np.linspace(0.0, 20000.0, 2_000_001)
    inside = CELL.q(s * y, y) > 0
    y0, y1 = CELL.chord(np.array([s]))
    if not inside.any():
        assert np.isnan(y0[0]) and np.isnan(y1[0])
    else:
        assert y0[0] == pytest.approx(y[inside][0], abs=0.02) and y1[0] == pytest.approx(y[inside][-1], abs=0.02)


@pytest.mark.parametrize("kwargs, word", [
    (dict(level=0.0), "level"), (dict(level=-5.0), "level"), (dict(level=float("nan")), "level"),
    (dict(level=1e6), "level"), (dict(cells=()), "cells"), (dict(cells=(CELL,) * 65), "cells"),
    (dict(level=100.0), "bottom"),
])
def test_bad_layers(kwargs, word):
    args = dict(level=1500.0, cells=(CELL,))
    args.update(kwargs)
    with pytest.raises(SunsetError, match=word):
        Clouds(**args)


@pytest.mark.parametrize("kwargs, word", [
    (dict(a=0.0), "a"), (dict(b=-1.0), "b"), (dict(top=-1.0), "top"), (dict(top=0.0, bottom=0.0), "thickness"),
    (dict(top=5e-324), r"^top must be 0 or in \[1, 15000\] m"), (dict(bottom=0.5), r"^bottom must be 0 or in"),
    (dict(a=5e-324), r"^a must be in \[1, "), (dict(top=5e-324, bottom=0.0), "top must be 0 or"),  # issue 33
    (dict(billows=(Billow(0.6, 0.0, 0.0), Billow(0.5, 1.0, 0.0))), "billows"), (dict(x=float("inf")), "x"),
])
def test_bad_cells(kwargs, word):
    args = dict(x=0.0, y=9000.0, a=1000.0, b=1000.0, top=100.0, bottom=50.0)
    args.update(kwargs)
    with pytest.raises(SunsetError, match=word):
        CloudCell(**args)


def test_bad_billow():
    with pytest.raises(SunsetError, match="amplitude"):
        Billow(1.0, 0.0, 0.0)


def test_scene_files_with_and_without_clouds():
    cloudy = load_named_scene("carlas-island-clouds")
    plain = load_named_scene("carlas-island")
    assert cloudy.clouds is not None and plain.clouds is None
    assert Scene.from_toml(cloudy.to_toml()) == cloudy
    assert "clouds" not in plain.to_toml()                         # a scene without clouds writes as before
    # everything but the clouds is Carla's Island
    assert cloudy.camera == plain.camera and cloudy.sea == plain.sea and cloudy.islands == plain.islands


def test_scene_errors_name_the_cloud_field():
    text = load_named_scene("carlas-island-clouds").to_toml().replace("bottom = 160.0", "bottom = -160.0")
    with pytest.raises(SunsetError, match=r"clouds\.cells\[1\]\.bottom"):
        Scene.from_toml(text)
    with pytest.raises(SunsetError, match=r"unknown key 'clouds\.colour'"):
        Scene.from_toml(text.replace("[clouds]\n", "[clouds]\ncolour = 1.0\n"))


def test_the_eye_must_be_below_the_cloud_base():
    scene = load_named_scene("carlas-island-clouds")
    from dataclasses import replace
    with pytest.raises(SunsetError, match="cloud base"):
        replace(scene, camera=replace(scene.camera, eye_height=1400.0))


SUN = Sun(azimuth=0.0, tilt=40.0, radius=0.75)


@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_cloud_radiance_shapes_and_sign(shape):
    depth = np.full(shape, 50.0)
    L = cloud_radiance(depth, SUN.position(0.5), LAYER, SUN.delta)
    assert L.shape == shape + (41,) and np.all(L > 0) and np.all(np.isfinite(L))


def test_cloud_radiance_darkens_with_depth_and_follows_the_closed_form_of_the_attenuation():
    depth = np.array([-200.0, 0.0, 100.0, 300.0])
    p = SUN.position(1.0)
    L = cloud_radiance(depth, p, LAYER, SUN.delta).sum(axis=-1)
    assert L[0] >= L[1] > L[2] > L[3]
    # the difference between two depths below the level is the direct term's exponential alone,
    # up to the altitude's small change of the sun's transmittance
    L0 = cloud_radiance(np.array([0.0, 100.0, 200.0]), p, LAYER, SUN.delta).sum(axis=-1)
    ratio = (L0[1] - L0[2]) / (L0[0] - L0[1])
    assert ratio == pytest.approx(math.exp(-100.0 / 150.0), rel=0.02)


def test_clouds_are_still_lit_from_above_after_sunset_at_the_sea():
    """The sun sets later at altitude: just after sunset a high cloud's top still gets direct light."""
    high = Clouds(8000.0, (CloudCell(0.0, 20000.0, 5000.0, 5000.0, 500.0, 100.0),))
    p = SUN.position(-0.05)                                           # 3 minutes after sunset at the sea
    assert p[2] < 0
    low = cloud_radiance(np.array([7000.0]), p, high, SUN.delta).sum()    # 1 km up
    top = cloud_radiance(np.array([-300.0]), p, high, SUN.delta).sum()    # 8.3 km up
    assert top > 3.0 * low


def test_cloud_radiance_rejects_nan_depth():
    with pytest.raises(SunsetError, match="depth"):
        cloud_radiance(np.array([np.nan]), SUN.position(0.5), LAYER, SUN.delta)
