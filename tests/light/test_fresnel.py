"""Fresnel's law against its closed forms and against energy conservation (independent formulas)."""

import math

import numpy as np
import pytest

from sunset.constants import WATER_REFRACTIVE_INDEX as N
from sunset.light.fresnel import brewster_angle, fresnel, reflectance, refract


def angle_forms(i, n=N):
    """Fresnel's sine/tangent forms in the angles (Born & Wolf 1.5 (21a)), not the cosine forms the module uses."""
    t = math.asin(math.sin(i) / n)
    rs = (math.sin(i - t) / math.sin(i + t)) ** 2
    rp = (math.tan(i - t) / math.tan(i + t)) ** 2
    return rs, rp


def test_normal_incidence():
    rs, rp, r = fresnel(1.0)
    want = ((N - 1) / (N + 1)) ** 2
    assert rs == pytest.approx(want, rel=1e-12) and rp == pytest.approx(want, rel=1e-12)
    assert r == pytest.approx(0.02111, abs=1e-5)        # 2.1 % for n = 1.34


def test_brewster_angle():
    ib = brewster_angle()
    assert math.tan(ib) == pytest.approx(N)
    rs, rp, r = fresnel(math.cos(ib))
    assert rp == pytest.approx(0.0, abs=1e-15)
    assert rs == pytest.approx(((N * N - 1) / (N * N + 1)) ** 2, rel=1e-12)
    assert r == pytest.approx(rs / 2)


def test_grazing_incidence():
    assert reflectance(0.0) == pytest.approx(1.0)
    # approaching 90°: R → 1 monotonically
    c = np.array([1e-2, 1e-3, 1e-4, 1e-6])
    r = reflectance(c)
    assert np.all(np.diff(r) > 0) and 1 - r[-1] < 1e-5


@pytest.mark.parametrize("deg", [1, 10, 30, 45, 53.3, 60, 75, 85, 89.9])
def test_against_the_angle_forms(deg):
    i = math.radians(deg)
    rs, rp, _ = fresnel(math.cos(i))
    ws, wp = angle_forms(i)
    assert rs == pytest.approx(ws, rel=1e-10, abs=1e-15) and rp == pytest.approx(wp, rel=1e-9, abs=1e-15)


def test_reflected_plus_transmitted_is_one():
    """T from the transmitted amplitudes (t_s, t_p) and the beam's area change, independently of R."""
    ci = np.linspace(0.01, 1.0, 200)
    ct = np.sqrt(1 - (1 - ci**2) / N**2)
    ts = 2 * ci / (ci + N * ct)
    tp = 2 * ci / (N * ci + ct)
    factor = N * ct / ci
    rs, rp, r = fresnel(ci)
    np.testing.assert_allclose(rs + factor * ts**2, 1.0, rtol=1e-12)
    np.testing.assert_allclose(rp + factor * tp**2, 1.0, rtol=1e-12)
    np.testing.assert_allclose(r + 0.5 * factor * (ts**2 + tp**2), 1.0, rtol=1e-12)


@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_shapes(shape):
    c = np.full(shape, 0.5)
    assert np.shape(reflectance(c)) == shape


def test_matches_the_sky_models_fresnel():
    from sunset.model.sky import fresnel_reflectance

    c = np.linspace(0, 1, 101)
    np.testing.assert_allclose(reflectance(c), fresnel_reflectance(c), rtol=1e-14)


def test_refraction_obeys_snell():
    rng = np.random.default_rng(3)
    nrm = rng.normal(size=(500, 3)) * [0.3, 0.3, 1]
    nrm[:, 2] = np.abs(nrm[:, 2]) + 0.2
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    d = rng.normal(size=(500, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    d = np.where((np.sum(d * nrm, 1) > 0)[:, None], d - 2 * np.sum(d * nrm, 1)[:, None] * nrm, d)  # heading in
    ci = -np.sum(d * nrm, 1)
    t = refract(d, nrm, ci)
    np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0, rtol=1e-12)
    sin_i = np.linalg.norm(np.cross(d, nrm), axis=1)
    sin_t = np.linalg.norm(np.cross(t, nrm), axis=1)
    np.testing.assert_allclose(sin_i, N * sin_t, atol=1e-12)
    assert np.all(np.sum(t * nrm, 1) < 0)               # into the water
    # coplanar: t lies in the plane of d and N
    np.testing.assert_allclose(np.sum(np.cross(d, nrm) * t, 1), 0.0, atol=1e-12)
