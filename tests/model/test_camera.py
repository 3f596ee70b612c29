"""The eye and the picture plane (sunset/model/camera.py).

Reference values come from independent constructions: pixel edges from
``np.linspace``, ray/plane intersections solved from the ray equation, angles
from dot products, and the horizon from a straight-line fit through the row
centres.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sunset.model.camera import Camera
from sunset.constants import MAX_EYE_HEIGHT, MAX_PIXELS, SIGMA_MAX, SIGMA_MIN
from sunset.errors import SunsetError

finite = dict(allow_nan=False, allow_infinity=False)
SHAPES = [(), (6,), (2, 3), (2, 3, 1)]


@st.composite
def cameras(draw):
    s_min = draw(st.floats(-2.0, 1.0, **finite))
    s_max = s_min + draw(st.floats(0.05, 2.0, **finite))
    zy_min = draw(st.floats(-1.0, 0.2, **finite))
    zy_max = zy_min + draw(st.floats(0.05, 1.0, **finite))
    return Camera(eye_height=draw(st.floats(0.1, 100.0, **finite)),
                  width=draw(st.integers(1, 40)), height=draw(st.integers(1, 40)),
                  s_min=s_min, s_max=s_max, zy_min=zy_min, zy_max=zy_max,
                  sigma=draw(st.floats(SIGMA_MIN, 4.0, **finite)))


def edges_centres(lo, hi, n):
    edges = np.linspace(lo, hi, n + 1)
    return 0.5 * (edges[:-1] + edges[1:])


@settings(max_examples=60, deadline=None)
@given(cameras())
def test_pixel_centres_are_midpoints_of_equal_cells(cam):
    np.testing.assert_allclose(cam.s_centres(), edges_centres(cam.s_min, cam.s_max, cam.width),
                               rtol=0, atol=1e-12)
    # Row 0 is the top of the picture: ζ decreases down the rows.
    np.testing.assert_allclose(cam.zy_centres(),
                               edges_centres(cam.zy_max, cam.zy_min, cam.height), rtol=0, atol=1e-12)
    ds, dz = cam.pixel_pitch
    assert ds == pytest.approx((cam.s_max - cam.s_min) / cam.width)
    assert dz == pytest.approx((cam.zy_max - cam.zy_min) / cam.height)


@settings(max_examples=60, deadline=None)
@given(cameras())
def test_directions_project_back_to_pixel_centres(cam):
    d = cam.directions()
    assert d.shape == (cam.height, cam.width, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, rtol=1e-12)
    assert np.all(d[..., 1] > 0)  # every ray looks forward
    s_ref = edges_centres(cam.s_min, cam.s_max, cam.width)
    z_ref = edges_centres(cam.zy_max, cam.zy_min, cam.height)
    np.testing.assert_allclose(d[..., 0] / d[..., 1], np.broadcast_to(s_ref, d.shape[:2]), atol=1e-12)
    np.testing.assert_allclose(d[..., 2] / d[..., 1], np.broadcast_to(z_ref[:, None], d.shape[:2]),
                               atol=1e-12)
    # And through project(): any point on the ray lands on its pixel centre.
    t = np.linspace(0.5, 50.0, cam.height * cam.width).reshape(cam.height, cam.width)
    p = d * t[..., None]
    s, zy = cam.project(p[..., 0], p[..., 1], p[..., 2])
    col, row = cam.to_pixel(s, zy)
    np.testing.assert_allclose(col, np.broadcast_to(np.arange(cam.width), col.shape), atol=1e-9)
    np.testing.assert_allclose(row, np.broadcast_to(np.arange(cam.height)[:, None], row.shape), atol=1e-9)


def test_directions_of_a_known_pixel():
    # 2 × 2 pixels over s ∈ [-1, 1], ζ ∈ [-1, 1]: centres at ±1/2.
    cam = Camera(eye_height=1.0, width=2, height=2, s_min=-1, s_max=1, zy_min=-1, zy_max=1)
    d = cam.directions()
    n = math.sqrt(0.25 + 1 + 0.25)
    np.testing.assert_allclose(d[0, 0], [-0.5 / n, 1 / n, 0.5 / n])   # top left
    np.testing.assert_allclose(d[1, 1], [0.5 / n, 1 / n, -0.5 / n])   # bottom right


@pytest.mark.parametrize("shape", SHAPES)
def test_project_is_elementwise(shape):
    rng = np.random.default_rng(1)
    x, y, z = rng.normal(size=shape), rng.uniform(0.5, 9, size=shape), rng.normal(size=shape)
    s, zy = Camera().project(x, y, z)
    assert np.shape(s) == shape and np.shape(zy) == shape
    # The ray from the eye through (x, y, z) crosses y = 1 at the parameter 1/y.
    np.testing.assert_allclose(s, x * (1.0 / y))
    np.testing.assert_allclose(zy, z * (1.0 / y))


@settings(max_examples=60, deadline=None)
@given(cameras())
def test_horizon_row_is_where_the_row_centres_cross_zero(cam):
    rows = np.arange(cam.height, dtype=float)
    z = edges_centres(cam.zy_max, cam.zy_min, cam.height)
    if cam.height == 1:
        slope = -(cam.zy_max - cam.zy_min)
    else:
        slope, _ = np.polyfit(rows, z, 1)
    expected = -z[0] / slope  # the straight line through the centres meets ζ = 0 here
    assert cam.horizon_row() == pytest.approx(expected, abs=1e-9)
    col, row = cam.to_pixel(0.0, 0.0)
    assert row == pytest.approx(expected, abs=1e-9)


@settings(max_examples=60, deadline=None)
@given(cameras())
def test_sea_y_is_the_ray_plane_intersection(cam):
    d = cam.directions()[:, 0, :]  # the first scan line; every scan line agrees in y
    y = cam.sea_y()
    assert y.shape == (cam.height,)
    below = d[:, 2] < 0
    # Solve t d_z = -h for the ray parameter t, then y = t d_y.
    t = -cam.eye_height / d[below, 2]
    np.testing.assert_allclose(y[below], t * d[below, 1], rtol=1e-12)
    assert np.all(np.isinf(y[~below]))
    for j in range(cam.width):
        dj = cam.directions()[below, j, :]
        np.testing.assert_allclose(-cam.eye_height / dj[:, 2] * dj[:, 1], y[below], rtol=1e-12)


def test_field_of_view_from_dot_products():
    cam = Camera(s_min=-0.7, s_max=0.4, zy_min=-0.35, zy_max=0.15)

    def angle(a, b):
        a, b = np.asarray(a, float), np.asarray(b, float)
        return math.degrees(math.acos(a @ b / np.linalg.norm(a) / np.linalg.norm(b)))

    horizontal, vertical = cam.field_of_view
    assert horizontal == pytest.approx(angle([-0.7, 1, 0], [0.4, 1, 0]))
    assert vertical == pytest.approx(angle([0, 1, -0.35], [0, 1, 0.15]))


def test_with_size_keeps_the_window():
    cam = Camera()
    small = cam.with_size(51, 33)
    assert (small.width, small.height) == (51, 33)
    assert (cam.width, cam.height) != (51, 33)  # the original is untouched (frozen)
    for name in ("eye_height", "s_min", "s_max", "zy_min", "zy_max", "sigma"):
        assert getattr(small, name) == getattr(cam, name)
    assert small.field_of_view == cam.field_of_view
    assert small.s_centres()[0] == pytest.approx(cam.s_min + (cam.s_max - cam.s_min) / 102)
    with pytest.raises(SunsetError, match=r"^width"):
        cam.with_size(0, 10)
    with pytest.raises(SunsetError, match=r"^height"):
        cam.with_size(10, 2.5)


@pytest.mark.parametrize("field, value, words", [
    ("eye_height", 0.0, "positive"),
    ("eye_height", -2.0, "positive"),
    ("eye_height", float("nan"), "finite"),
    ("width", 0, ">= 1"),
    ("width", 3.0, "integer"),
    ("height", True, "integer"),
    ("height", -5, ">= 1"),
    ("s_min", float("nan"), "finite"),
    ("s_max", -0.5, "greater"),
    ("zy_max", float("inf"), "finite"),
    ("zy_max", -0.35, "greater"),
    ("sigma", 0.0, "positive"),
    ("sigma", float("nan"), "finite"),
    ("sigma", 0.5 * SIGMA_MIN, "pixels"),
    ("sigma", 2 * SIGMA_MAX, "pixels"),
    ("eye_height", 2 * MAX_EYE_HEIGHT, "at most"),
])
def test_bad_input_names_the_field(field, value, words):
    with pytest.raises(SunsetError, match=rf"^{field} .*{words}"):
        Camera(**{field: value})


def test_too_many_pixels_is_refused_before_any_array_exists():
    side = int(MAX_PIXELS ** 0.5) + 1
    with pytest.raises(SunsetError, match=r"^width × height must be at most"):
        Camera(width=side, height=side)
    Camera(width=MAX_PIXELS // 1000, height=1000)       # exactly at the limit is allowed
