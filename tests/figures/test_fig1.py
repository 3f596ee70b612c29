"""Tests for sunset.figures.fig1: Figure 1's geometry against an independent rotation, and the PNG.

P(θ) is checked against Rodrigues' formula for the rotation of U about W by
θ, written out here; the circle against its defining properties (unit,
in the plane normal to W, highest at V's elevation, crossing the horizon at ±U).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from sunset import Scene
from sunset.errors import SunsetError
from sunset.figures import make_figures
from sunset.figures.fig1 import circle_geometry, figure1
from sunset.model.sun import Sun


def rodrigues(v, axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    v = np.asarray(v, float)
    return (v * math.cos(angle) + np.cross(axis, v) * math.sin(angle)
            + axis * np.dot(axis, v) * (1 - math.cos(angle)))


@pytest.mark.parametrize("sun", [Sun(), Sun(azimuth=1.1, tilt=40.0), Sun(azimuth=-30.0, tilt=75.0, radius=0.27)])
@pytest.mark.parametrize("hours", [0.5, 2.0, 5.5])
def test_P_is_U_turned_about_W_by_theta(sun, hours):
    geo = circle_geometry(sun, hours)
    theta = hours * 2 * math.pi / 24
    assert geo.theta == pytest.approx(theta)
    np.testing.assert_allclose(geo.P, rodrigues(sun.U, sun.W, theta), atol=1e-12)
    assert geo.elevation == pytest.approx(math.asin(math.sin(math.radians(sun.tilt)) * math.sin(theta)))


@pytest.mark.parametrize("sun", [Sun(azimuth=1.1, tilt=40.0), Sun(azimuth=200.0, tilt=10.0)])
def test_circle_lies_on_the_sphere_in_the_plane_normal_to_W(sun):
    geo = circle_geometry(sun, 1.0, n=721)
    np.testing.assert_allclose(np.linalg.norm(geo.circle, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(geo.circle @ geo.W, 0.0, atol=1e-12)
    # highest at V, at the tilt; the horizon crossed at U (θ = 0) and −U (θ = π)
    assert math.degrees(math.asin(geo.circle[:, 2].max())) == pytest.approx(sun.tilt, abs=1e-6)
    assert math.degrees(geo.tilt) == pytest.approx(sun.tilt)
    np.testing.assert_allclose(geo.circle[0], sun.U, atol=1e-12)
    np.testing.assert_allclose(geo.circle[360], -sun.U, atol=1e-12)
    np.testing.assert_allclose(geo.horizon[:, 2], 0.0)


def test_circle_geometry_bad_input():
    with pytest.raises(SunsetError, match="hours"):
        circle_geometry(Sun(), float("nan"))
    with pytest.raises(SunsetError, match="n must be"):
        circle_geometry(Sun(), 1.0, n=3)


def test_figure1_written_deterministic_and_depends_on_the_sun(tmp_path):
    a = figure1(tmp_path / "a.png", dpi=50)
    b = figure1(tmp_path / "b.png", dpi=50)
    c = figure1(tmp_path / "c.png", sun=Sun(azimuth=10.0, tilt=60.0), dpi=50)
    assert a.read_bytes() == b.read_bytes() != c.read_bytes()
    with Image.open(a) as im:
        assert im.format == "PNG" and im.width > im.height > 0
        rgb = np.asarray(im.convert("RGB"))
    assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 50
    assert not list(tmp_path.glob(".*"))


@pytest.mark.parametrize("hours", [0.0, 6.0, -1.0, float("inf")])
def test_figure1_bad_hours(tmp_path, hours):
    with pytest.raises(SunsetError, match="hours"):
        figure1(tmp_path / "x.png", hours=hours)
    assert not (tmp_path / "x.png").exists()


def test_figure1_from_the_registry(tmp_path):
    files = make_figures(tmp_path, only="1", scene=Scene.default().with_size(32, 32), log=lambda m: None)
    assert files == [tmp_path / "fig1.png"] and files[0].stat().st_size > 0
