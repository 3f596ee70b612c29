"""Tests for sunset.figures.fig3: one scan line, checked by brute force along the rays.

Hidden points are checked by walking the straight segment from the eye to
each point and asking the sea (Sea.elevation, not the scan line's g) whether
it rises above the segment anywhere nearer; the samples' g against
f/y from Sea.elevation; every pixel's hit against the ray it belongs to.
"""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from sunset import Scene
from sunset.errors import SunsetError
from sunset.figures import make_figures
from sunset.figures.fig3 import figure3, scan_line

SCENE = Scene.default()


@pytest.fixture(scope="module")
def line():
    return scan_line(SCENE, n=1500)


def test_hidden_points_by_brute_force(line):
    sea, h = SCENE.sea, line.h
    rng = np.random.default_rng(3)
    picks = rng.choice(len(line.y), 150, replace=False)
    for i in picks:
        y, f = line.y[i], line.f[i]
        # the segment from the eye (0, 0) to (y, f), sampled at every dense point nearer than y
        near = line.y[: i]
        if near.size == 0:
            continue
        sea_z = sea.elevation(0.0 * near, near, 0.0) - h
        seg_z = f * near / y
        blocked = bool(np.any(sea_z > seg_z + 1e-9))
        assert blocked == bool(line.hidden[i]), (y, f)


def test_samples_follow_the_paper_and_the_sea(line):
    u = 1.0 / line.y_samples
    du = np.diff(u)
    np.testing.assert_allclose(du, du[0], rtol=1e-9)          # evenly spaced in 1/y, near to far
    assert du[0] < 0
    f = SCENE.sea.elevation(0.0 * line.y_samples, line.y_samples, 0.0) - line.h
    np.testing.assert_allclose(line.g_samples, f / line.y_samples, atol=2e-6)


def test_every_pixel_hit_lies_on_its_ray_at_a_visible_point(line):
    pitch = line.zeta[1] - line.zeta[0]
    hits = np.isfinite(line.yp)
    assert hits.sum() >= len(line.zeta) - 1
    y = line.yp[hits]
    f = SCENE.sea.elevation(0.0 * y, y, 0.0) - line.h
    # the sea at the hit projects onto the pixel's centre (to interpolation error)
    assert np.max(np.abs(f / y - line.zeta[hits])) < 0.5 * pitch
    # and the hit is not behind a nearer crest (beyond half a pixel)
    run = np.interp(y, line.y, line.running_max)
    assert np.all(f / y >= run - 0.5 * pitch)


def test_some_troughs_are_hidden(line):
    runs = line.hidden_runs()
    assert 0.05 < line.hidden_fraction < 0.95 and len(runs) >= 2
    assert all(a <= b for a, b in runs)


@pytest.mark.parametrize("kwargs, message", [
    (dict(y_near=10.0, y_far=5.0), "y_near < y_far"),
    (dict(pixels=1), "pixels"),
    (dict(sigma=0.0), "sigma"),
    (dict(t=float("nan")), "t must be"),
])
def test_scan_line_bad_input(kwargs, message):
    with pytest.raises(SunsetError, match=message):
        scan_line(SCENE, **kwargs)


def test_figure3_written_and_deterministic(tmp_path):
    a = figure3(tmp_path / "a.png", dpi=50)
    b = figure3(tmp_path / "b.png", dpi=50)
    assert a.read_bytes() == b.read_bytes()
    with Image.open(a) as im:
        assert im.format == "PNG" and im.width > im.height > 0


def test_figure3_from_the_registry(tmp_path):
    files = make_figures(tmp_path, only="3", scene=Scene.default().with_size(32, 32), log=lambda m: None)
    assert files == [tmp_path / "fig3.png"] and files[0].stat().st_size > 0
