"""The sun's great circle (sunset/model/sun.py; paper, Figure 1).

The reference for the sun's elevation is the spherical-trigonometry sine rule
for a great circle inclined at ``tilt`` to the horizon and crossing it at U:
sin(elevation) = sin(tilt) · sin(θ). U, V and W are checked against
explicit component formulas and a hand-written cross product.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sunset.errors import SunsetError
from sunset.model.sun import Sun

finite = dict(allow_nan=False, allow_infinity=False)
SHAPES = [(), (6,), (2, 3), (2, 3, 1)]


@st.composite
def suns(draw):
    return Sun(azimuth=draw(st.floats(-360.0, 360.0, **finite)),
               tilt=draw(st.floats(0.5, 90.0, **finite)),
               radius=draw(st.floats(0.05, 5.0, **finite)))


def cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@settings(max_examples=80, deadline=None)
@given(suns())
def test_U_V_W_are_a_right_handed_orthonormal_frame(sun):
    U, V, W = sun.U, sun.V, sun.W
    B = np.stack([U, V, W])
    np.testing.assert_allclose(B @ B.T, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(W, cross(U, V), atol=1e-12)
    assert np.linalg.det(B) == pytest.approx(1.0)


@settings(max_examples=80, deadline=None)
@given(suns())
def test_U_on_the_horizon_at_the_azimuth_and_V_at_the_tilt(sun):
    a = math.radians(sun.azimuth)
    assert sun.U[2] == 0.0
    # The azimuth is measured from +y toward +x.
    np.testing.assert_allclose(sun.U, [math.sin(a), math.cos(a), 0.0], atol=1e-12)
    assert math.degrees(math.asin(sun.V[2])) == pytest.approx(sun.tilt)
    # V's horizontal part points 90° to the left of U (the sun climbs on the −x side
    # of U when it sets straight ahead): a positive z-component of U_h × V_h.
    if sun.tilt < 90:
        assert cross(sun.U, sun.V * [1, 1, 0])[2] > 0


@settings(max_examples=80, deadline=None)
@given(suns())
def test_position_at_sunset_noon_and_midnight(sun):
    np.testing.assert_allclose(sun.position(0.0), sun.U, atol=1e-12)
    np.testing.assert_allclose(sun.position(6.0), sun.V, atol=1e-12)   # θ = 90°: the highest
    np.testing.assert_allclose(sun.position(12.0), -sun.U, atol=1e-12)  # sunrise
    np.testing.assert_allclose(sun.position(-6.0), -sun.V, atol=1e-12)
    np.testing.assert_allclose(sun.position(24.0), sun.U, atol=1e-12)


def test_fifteen_degrees_per_hour():
    assert Sun.theta(1.0) == pytest.approx(math.radians(15.0))
    assert Sun.theta(-2.0) == pytest.approx(math.radians(-30.0))
    sun = Sun(azimuth=10.0, tilt=40.0)
    for hours in (0.25, 1.0, 3.0, 5.5):
        cos_angle = sun.position(hours) @ sun.U
        assert math.degrees(math.acos(cos_angle)) == pytest.approx(15.0 * hours)


@settings(max_examples=80, deadline=None)
@given(suns(), st.floats(-12.0, 12.0, **finite))
def test_elevation_by_spherical_trigonometry(sun, hours):
    theta = math.radians(15.0 * hours)
    expected = math.asin(math.sin(math.radians(sun.tilt)) * math.sin(theta))
    assert float(sun.elevation(hours)) == pytest.approx(expected, abs=1e-12)
    p = sun.position(hours)
    assert np.linalg.norm(p) == pytest.approx(1.0)
    assert abs(p @ sun.W) < 1e-12  # the sun stays on its great circle C


def test_a_sun_that_sets_straight_ahead():
    # Equinox at latitude 40° N, looking west: the sun climbs back up toward the south (left).
    sun = Sun(azimuth=0.0, tilt=50.0)
    p = sun.position(1.0)
    assert p[0] < 0 and p[1] > 0 and p[2] > 0
    assert math.degrees(float(sun.elevation(6.0))) == pytest.approx(50.0)


@pytest.mark.parametrize("shape", SHAPES)
def test_position_and_elevation_shapes(shape):
    sun = Sun(azimuth=5.0, tilt=30.0)
    hours = np.linspace(-3, 3, int(np.prod(shape))).reshape(shape)
    p = sun.position(hours)
    assert p.shape == shape + (3,)
    e = sun.elevation(hours)
    assert np.shape(e) == shape
    flat = np.ravel(hours)
    for i, h in enumerate(flat):
        np.testing.assert_allclose(p.reshape(-1, 3)[i], sun.position(float(h)))
        expected = math.asin(math.sin(math.radians(30.0)) * math.sin(math.radians(15.0 * h)))
        assert np.ravel(e)[i] == pytest.approx(expected, abs=1e-12)


def test_delta_is_the_radius_in_radians():
    assert Sun(radius=0.75).delta == pytest.approx(0.75 * math.pi / 180.0)


@pytest.mark.parametrize("field, value, words", [
    ("tilt", 0.0, r"in \(0, 90\]"),
    ("tilt", 90.5, r"in \(0, 90\]"),
    ("tilt", -10.0, r"in \(0, 90\]"),
    ("tilt", float("nan"), "finite"),
    ("azimuth", float("inf"), "finite"),
    ("azimuth", float("nan"), "finite"),
    ("radius", 0.0, "positive"),
    ("radius", -0.75, "positive"),
    ("radius", 10.0, "below 10"),
    ("radius", float("nan"), "finite"),
])
def test_bad_input_names_the_field(field, value, words):
    with pytest.raises(SunsetError, match=rf"^{field} .*{words}"):
        Sun(**{field: value})


@pytest.mark.parametrize("hours", [float("nan"), float("inf"), [0.0, float("nan")]])
def test_bad_hours(hours):
    with pytest.raises(SunsetError, match=r"^hours .*finite"):
        Sun().position(hours)
    with pytest.raises(SunsetError, match=r"^hours"):
        Sun().elevation(hours)


@pytest.mark.parametrize("hours", [0.0, 12.0, -12.0, np.zeros(6), np.full((2, 3), 11.9), np.full((2, 3, 1), -12.0)])
def test_require_hours_takes_scalars_and_arrays_within_half_a_day(hours):
    from sunset.model.sun import require_hours

    require_hours("hours", hours)          # no error


@pytest.mark.parametrize("hours", [12.000001, -13.0, 1e300, np.array([0.0, 0.5, 12.5]), np.full((2, 3, 1), -24.0),
                                   np.nan, np.array([0.0, np.inf])])
def test_require_hours_refuses_what_is_beyond_half_a_day_or_not_finite(hours):
    from sunset.model.sun import require_hours

    with pytest.raises(SunsetError, match="hours"):
        require_hours("hours", hours)


def test_the_tables_and_the_light_refuse_hours_beyond_half_a_day():
    from sunset.light.lighting import Lighting
    from sunset.recorder.colour_tables import tables

    sun = Sun()
    with pytest.raises(SunsetError, match="±12 hours"):
        tables(sun, 12.5)
    with pytest.raises(SunsetError, match="±12 hours"):
        Lighting.for_hour(sun, -100.0)
    assert tables(sun, -12.0).shape == (3, 256)
