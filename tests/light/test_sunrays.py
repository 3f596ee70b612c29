"""The sun's rays on the waves (sunset/light/sunrays.py): the sea's table of cosines, the light a point gets, the
crests' shadows against a brute-force march, and the compiled twins within their tolerances."""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.light.fresnel import reflectance
from sunset.light.sunrays import in_shadow, sea_table, sun_points, surface, visible
from sunset.model.scene import load_named_scene
from sunset.model.waves import Sea

SCENES = [("post-in-the-swell", 1.0), ("carlas-island", 0.35), ("storm-swell", 1.0)]


@pytest.fixture(scope="module", params=SCENES, ids=[s for s, _ in SCENES])
def case(request):
    name, hours = request.param
    return load_named_scene(name), hours


def test_the_table_is_the_seas_own_sum(case):
    scene, _ = case
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-300, 300, 5000), rng.uniform(0, 900, 5000)
    for t in (0.0, 1.7, -40.0):
        tab = sea_table(scene.sea, t)
        with kernels.use_compiled(False):
            eta, gx, gy = surface(tab.a, tab.kx, tab.ky, tab.c, x, y)
        scale = tab.top
        np.testing.assert_allclose(eta, scene.sea.elevation(x, y, t), rtol=0, atol=1e-12 * scale)
        fx, fy = scene.sea.gradient(x, y, t)
        np.testing.assert_allclose(gx, fx, rtol=0, atol=1e-11)
        np.testing.assert_allclose(gy, fy, rtol=0, atol=1e-11)
        assert tab.top == pytest.approx(scene.sea.max_elevation, rel=1e-12)


def _brute_lit(sea, t, q, omega, p, top, n=40000):
    """Lit if the sun ray from q stays above the water at n points up to the crests' height (and ω > 0)."""
    out = np.zeros(len(q), bool)
    for i in range(len(q)):
        if omega[i] <= 0:
            continue
        tau = np.linspace(0.0, (top - q[i, 2]) / p[2], n)[1:]
        pts = q[i][None, :] + tau[:, None] * p[None, :]
        g = pts[:, 2] - sea.elevation(pts[:, 0], pts[:, 1], t)
        out[i] = bool(np.all(g > 0))
    return out


def test_the_shadow_test_agrees_with_a_brute_force_march(case):
    scene, hours = case
    t = 0.9
    tab = sea_table(scene.sea, t)
    p = scene.sun.position(hours)
    rng = np.random.default_rng(2)
    x, y = rng.uniform(-50, 50, 400), rng.uniform(0, 100, 400)
    sp = sun_points(tab, x, y, p)
    want = _brute_lit(scene.sea, t, sp.q, sp.omega, p, tab.top)
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            got = visible(tab.a, tab.kx, tab.ky, tab.c, tab.top, x, y, sp.q[:, 2], sp.omega, p)
        assert np.array_equal(got, want)
    assert 0 < want.sum() < len(want)                  # both kinds met: low suns shadow some water


def test_still_water_gets_sin_e_everywhere_and_a_mirror_reflection():
    scene = replace(load_named_scene("carlas-island"), sea=Sea(()))
    p = scene.sun.position(1.0)
    tab = sea_table(scene.sea, 0.0)
    sp = sun_points(tab, np.linspace(-5, 5, 7), np.linspace(1, 9, 7), p)
    np.testing.assert_allclose(sp.omega, p[2], rtol=1e-15)
    np.testing.assert_allclose(sp.R, reflectance(p[2]), rtol=1e-15)
    np.testing.assert_allclose(sp.reflected, np.broadcast_to([-p[0], -p[1], p[2]], (7, 3)), atol=1e-15)
    cos_t = math.sqrt(1 - (1 - p[2] ** 2) / 1.34 ** 2)
    np.testing.assert_allclose(-sp.refracted[:, 2], cos_t, rtol=1e-14)
    assert not np.any(in_shadow(tab, sp.q[:, 0], sp.q[:, 1], sp.q[:, 2], sp.omega, p, np.ones(7, bool)))


def test_water_facing_away_from_the_sun_is_dark_without_a_march():
    scene, hours = load_named_scene("carlas-island"), 0.35
    tab = sea_table(scene.sea, 0.0)
    p = scene.sun.position(hours)
    rng = np.random.default_rng(4)
    x, y = rng.uniform(-50, 50, 3000), rng.uniform(0, 100, 3000)
    sp = sun_points(tab, x, y, p)
    away = sp.omega <= 0
    assert away.sum() > 100
    dark = in_shadow(tab, x, y, sp.q[:, 2], sp.omega, p, np.zeros(3000, bool))
    np.testing.assert_array_equal(dark, away)
    # the flux a facet gets per horizontal area is P·N/N_z, as the normal says
    np.testing.assert_allclose(sp.omega[~away], (sp.normal @ p)[~away] / sp.normal[~away, 2], rtol=0, atol=1e-14)


@pytest.mark.skipif(not kernels.AVAILABLE, reason="Numba is not installed")
def test_the_compiled_surface_agrees_and_is_the_same_bytes_on_any_number_of_threads(case):
    scene, _ = case
    tab = sea_table(scene.sea, 2.5)
    rng = np.random.default_rng(5)
    x, y = rng.uniform(-1e3, 1e3, 200_000), rng.uniform(0, 2e3, 200_000)
    want = surface.reference(tab.a, tab.kx, tab.ky, tab.c, x, y)
    runs = []
    for n in (1, 2, 3):
        with kernels.use_threads(n):
            runs.append(surface.compiled()(tab.a, tab.kx, tab.ky, tab.c, x, y))
    from sunset.light.sunrays_numba import SURFACE_ATOL
    for got, ref in zip(runs[0], want):
        np.testing.assert_allclose(got, ref, rtol=0, atol=SURFACE_ATOL * max(tab.top, 1.0))
    for other in runs[1:]:
        assert all(a.tobytes() == b.tobytes() for a, b in zip(other, runs[0]))
