"""Islands: paraboloids (eq. 3), cosine hills (eq. 4), parts, the bounding ellipse (sunset/model/islands.py).

Reference values come from independent computations: the quadratic form
written as a matrix product, central finite differences, eigenvalues from
numpy.linalg, and dense grids of points for the bounds.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sunset.constants import PART_BEACH, PART_CLIFF, PART_HILL
from sunset.errors import SunsetError
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.scene import Scene

finite = dict(allow_nan=False, allow_infinity=False)


def make_island(**kw):
    args = dict(x=-120.0, y=900.0, cliff=Paraboloid(110.0, 0.004, 0.0015, 0.003),
                beach=Paraboloid(3.0, 5e-5, 1e-5, 4e-5), cliff_top=45.0, hill_factor=0.3,
                cosines=(Cosine(4.0, 0.08, 0.05), Cosine(2.0, -0.11, 0.17)))
    args.update(kw)
    return Island(**args)


def quadratic_form(par, dx, dy):
    """height − [dx dy] M [dx dy]ᵀ with M = [[e, f/2], [f/2, g]] (eq. 3 as a matrix product)."""
    M = np.array([[par.e, par.f / 2], [par.f / 2, par.g]])
    v = np.stack([dx, dy], axis=-1)
    return par.height - np.einsum("...i,ij,...j->...", v, M, v)


def central(fun, x, y, hstep=1e-3):
    fx = (fun(x + hstep, y) - fun(x - hstep, y)) / (2 * hstep)
    fy = (fun(x, y + hstep) - fun(x, y - hstep)) / (2 * hstep)
    return fx, fy


# -- eq. 3 -------------------------------------------------------------------

def test_paraboloid_matches_the_matrix_form():
    par = Paraboloid(80.0, 0.003, -0.002, 0.005)
    rng = np.random.default_rng(1)
    dx, dy = rng.normal(0, 100, (2, 50))
    np.testing.assert_allclose(par.value(dx, dy), quadratic_form(par, dx, dy), rtol=1e-12, atol=1e-9)
    assert par.value(0.0, 0.0) == 80.0


def test_island_paraboloid_is_centred_on_the_apex():
    isl = make_island()
    assert isl.paraboloid(isl.x, isl.y, "cliff") == isl.cliff.height
    assert isl.paraboloid(isl.x, isl.y, "beach") == isl.beach.height
    x, y = isl.x + 30.0, isl.y - 20.0
    assert isl.paraboloid(x, y) == pytest.approx(quadratic_form(isl.cliff, 30.0, -20.0))


def test_paraboloid_gradient_by_finite_differences():
    par = Paraboloid(80.0, 0.003, -0.002, 0.005)
    dx, dy = np.array([12.0, -40.0, 0.0]), np.array([-7.0, 25.0, 60.0])
    gx, gy = par.gradient(dx, dy)
    fx, fy = central(par.value, dx, dy)
    np.testing.assert_allclose(gx, fx, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(gy, fy, rtol=1e-7, atol=1e-9)


def test_min_curvature_is_the_smallest_eigenvalue():
    par = Paraboloid(10.0, 0.003, -0.004, 0.005)
    M = np.array([[par.e, par.f / 2], [par.f / 2, par.g]])
    assert par.min_curvature == pytest.approx(np.linalg.eigvalsh(M).min(), rel=1e-12)


# -- eq. 4 and the composite surface ---------------------------------------------

def test_cliff_equation_adds_the_cosines():
    isl = make_island()
    x, y = np.array([-150.0, -100.0]), np.array([880.0, 950.0])
    expected = quadratic_form(isl.cliff, x - isl.x, y - isl.y)
    for c in isl.cosines:
        expected = expected + c.amplitude * np.cos(c.l * x + c.m * y)
    np.testing.assert_allclose(isl.cliff_equation(x, y), expected, rtol=1e-12)


def test_cliff_equation_gradient_by_finite_differences():
    isl = make_island()
    x, y = np.array([-150.0, -100.0, -60.0]), np.array([880.0, 950.0, 910.0])
    gx, gy = isl.cliff_equation_gradient(x, y)
    fx, fy = central(isl.cliff_equation, x, y)
    np.testing.assert_allclose(gx, fx, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(gy, fy, rtol=1e-6, atol=1e-8)


def piecewise_height(isl, x, y):
    """The island's height, written out case by case (independent of Island.surface)."""
    q = float(isl.cliff_equation(x, y))
    b = float(isl.paraboloid(x, y, "beach"))
    upper = q if q <= isl.cliff_top else isl.cliff_top + isl.hill_factor * (q - isl.cliff_top)
    if b >= upper:
        return b, PART_BEACH
    return upper, (PART_CLIFF if q <= isl.cliff_top else PART_HILL)


def test_surface_and_parts_case_by_case():
    isl = make_island()
    rng = np.random.default_rng(2)
    x = isl.x + rng.uniform(-300, 300, 400)
    y = isl.y + rng.uniform(-300, 300, 400)
    height, part = isl.surface(x, y, with_gradient=False)
    ref = [piecewise_height(isl, a, b) for a, b in zip(x, y)]
    np.testing.assert_allclose(height, [r[0] for r in ref], rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(part, [r[1] for r in ref])
    assert {PART_BEACH, PART_CLIFF, PART_HILL} <= set(np.unique(part))


def test_surface_is_continuous_at_the_cliff_top():
    # walk outward from the apex along +x: the height crosses the cliff top continuously
    isl = make_island(cosines=())
    r = math.sqrt((isl.cliff.height - isl.cliff_top) / isl.cliff.e)  # Q = cliff_top on this ray
    below = isl.height(isl.x + r + 1e-6, isl.y)
    above = isl.height(isl.x + r - 1e-6, isl.y)
    assert below == pytest.approx(isl.cliff_top, abs=1e-5)
    assert above == pytest.approx(isl.cliff_top, abs=1e-5)
    # the hill is flattened by the factor: at the apex it is c + φ(h − c)
    assert isl.height(isl.x, isl.y) == pytest.approx(isl.cliff_top + isl.hill_factor * (isl.cliff.height - isl.cliff_top))


@pytest.mark.parametrize("part", [PART_BEACH, PART_CLIFF, PART_HILL])
def test_gradient_by_finite_differences_in_each_part(part):
    isl = make_island()
    rng = np.random.default_rng(3)
    x = isl.x + rng.uniform(-300, 300, 4000)
    y = isl.y + rng.uniform(-300, 300, 4000)
    p = isl.part(x, y)
    # stay away from the creases, where the surface has a kink
    hstep = 1e-3
    same = np.ones_like(p, dtype=bool)
    for ddx, ddy in ((hstep, 0), (-hstep, 0), (0, hstep), (0, -hstep)):
        same &= isl.part(x + ddx, y + ddy) == p
    sel = (p == part) & same
    assert sel.sum() > 20
    gx, gy = isl.gradient(x[sel], y[sel])
    fx, fy = central(isl.height, x[sel], y[sel], hstep)
    np.testing.assert_allclose(gx, fx, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(gy, fy, rtol=1e-5, atol=1e-6)
    if part == PART_HILL:  # the chain rule through the hill factor
        qx, qy = isl.cliff_equation_gradient(x[sel], y[sel])
        np.testing.assert_allclose(gx, isl.hill_factor * qx, rtol=1e-12)


def test_normal_is_unit_and_perpendicular_to_the_surface():
    isl = make_island()
    rng = np.random.default_rng(4)
    x = isl.x + rng.uniform(-250, 250, 300)
    y = isl.y + rng.uniform(-250, 250, 300)
    n = isl.normal(x, y)
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, rtol=1e-12)
    assert np.all(n[..., 2] > 0)
    fx, fy = central(isl.height, x, y, 1e-4)
    p = isl.part(x, y)
    smooth = np.ones_like(p, dtype=bool)
    for ddx, ddy in ((1e-4, 0), (-1e-4, 0), (0, 1e-4), (0, -1e-4)):
        smooth &= isl.part(x + ddx, y + ddy) == p
    # tangents (1, 0, f_x) and (0, 1, f_y) are perpendicular to the normal
    t1 = np.stack([np.ones_like(fx), np.zeros_like(fx), fx], -1)
    t2 = np.stack([np.zeros_like(fy), np.ones_like(fy), fy], -1)
    assert np.abs(np.sum(n * t1, -1)[smooth]).max() < 1e-5
    assert np.abs(np.sum(n * t2, -1)[smooth]).max() < 1e-5


def test_max_height_bounds_the_surface():
    isl = make_island()
    x, y = np.meshgrid(np.linspace(isl.x - 200, isl.x + 200, 401), np.linspace(isl.y - 200, isl.y + 200, 401))
    assert isl.height(x, y).max() <= isl.max_height + 1e-9
    assert isl.max_perturbation == 6.0


# -- the bounding ellipse ------------------------------------------------------------

@pytest.mark.parametrize("d", [0.0, 0.7, 3.0])
def test_bounding_ellipses_contain_every_point_above_the_lowest_sea(d):
    isl = make_island()
    x, y = np.meshgrid(np.linspace(isl.x - 400, isl.x + 400, 801), np.linspace(isl.y - 400, isl.y + 400, 801))
    above = isl.height(x, y) > -d
    inside = isl.bound_contains(x, y, d)
    assert above.any()
    assert not np.any(above & ~inside)
    # and they are not wastefully large: the cliff ellipse is tight for the pure paraboloid
    assert inside.sum() < 1.6 * above.sum()


@pytest.mark.parametrize("d", [0.0, 0.7])
def test_chord_brackets_every_point_above_the_lowest_sea(d):
    isl = make_island()
    s = np.linspace(-0.45, 0.2, 131)
    y0, y1 = isl.chord(s, d)
    y = np.linspace(500.0, 1300.0, 8001)
    for si, a, b in zip(s, y0, y1):
        above = isl.height(si * y, y) > -d
        if not np.isfinite(a):
            assert not above.any()
            continue
        assert np.all((y[above] >= a - 1e-9) & (y[above] <= b + 1e-9))


def test_paraboloid_chord_ends_lie_on_the_ellipse():
    par = Paraboloid(60.0, 0.003, 0.001, 0.002)
    X, Y, level = 40.0, 700.0, -2.0
    s = np.array([-0.1, 0.0, 0.05, 0.1, 5.0])
    y0, y1 = par.chord(X, Y, level, s)
    hit = np.isfinite(y0)
    assert hit[:4].all() and not hit[4]
    for ends in (y0[hit], y1[hit]):
        np.testing.assert_allclose(par.value(s[hit] * ends - X, ends - Y), level, atol=1e-8)
    mid = 0.5 * (y0[hit] + y1[hit])
    assert np.all(par.value(s[hit] * mid - X, mid - Y) > level)
    assert np.all(y1[hit] > y0[hit])


@settings(max_examples=40, deadline=None)
@given(e=st.floats(1e-4, 1e-2, **finite), g=st.floats(1e-4, 1e-2, **finite), frac=st.floats(-0.95, 0.95, **finite),
       X=st.floats(-500, 500, **finite), Y=st.floats(50, 3000, **finite), s=st.floats(-1, 1, **finite))
def test_chord_roots_property(e, g, frac, X, Y, s):
    par = Paraboloid(50.0, e, frac * 2 * math.sqrt(e * g), g)
    y0, y1 = par.chord(X, Y, -1.0, s)
    if np.isfinite(y0):
        for yy in (float(y0), float(y1)):
            assert par.value(s * yy - X, yy - Y) == pytest.approx(-1.0, abs=1e-6 * max(1.0, abs(yy)) ** 2 * max(e, g) + 1e-6)


# -- shapes and dtypes ----------------------------------------------------------------

@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_shapes(shape):
    isl = make_island()
    rng = np.random.default_rng(5)
    x = isl.x + rng.uniform(-200, 200, shape)
    y = isl.y + rng.uniform(-200, 200, shape)
    h, p, gx, gy = isl.surface(x, y)
    assert np.shape(h) == shape and np.shape(p) == shape and np.shape(gx) == shape and np.shape(gy) == shape
    assert np.shape(isl.normal(x, y)) == shape + (3,)
    assert np.shape(isl.cliff_equation(x, y)) == shape
    assert np.asarray(p).dtype == np.int8
    # elementwise: each element equals the scalar evaluation
    flat = np.ravel(x), np.ravel(y)
    np.testing.assert_allclose(np.ravel(h), [isl.height(a, b) for a, b in zip(*flat)], rtol=1e-12)


def test_float32_in_float32_out():
    isl = make_island()
    x = np.array([-150.0, -100.0], dtype=np.float32)
    y = np.array([880.0, 950.0], dtype=np.float32)
    h, p, gx, gy = isl.surface(x, y)
    assert h.dtype == np.float32 and gx.dtype == np.float32 and gy.dtype == np.float32


def test_default_scene_islands_show_all_three_parts():
    scene = Scene.default()
    assert len(scene.islands) == 3
    for isl in scene.islands:
        x, y = np.meshgrid(np.linspace(isl.x - 350, isl.x + 350, 351), np.linspace(isl.y - 350, isl.y + 350, 351))
        h, p = isl.surface(x, y, with_gradient=False)
        dry = h > 0
        assert set(np.unique(p[dry])) == {PART_BEACH, PART_CLIFF, PART_HILL}, isl.name


# -- bad input ----------------------------------------------------------------------------

@pytest.mark.parametrize("kw, name", [
    (dict(e=-0.001), "e"), (dict(g=0.0), "g"), (dict(height=float("nan")), "height"),
    (dict(f=float("inf")), "f"), (dict(f=0.1), "f"),
])
def test_bad_paraboloid(kw, name):
    args = dict(height=50.0, e=0.003, f=0.0, g=0.003)
    args.update(kw)
    with pytest.raises(SunsetError, match=f"^{name} "):
        Paraboloid(**args)


@pytest.mark.parametrize("kw, name", [
    (dict(y=-10.0), "y"), (dict(x=float("nan")), "x"), (dict(hill_factor=1.5), "hill_factor"),
    (dict(hill_factor=0.0), "hill_factor"), (dict(cliff_top=200.0), "cliff_top"),
])
def test_bad_island(kw, name):
    with pytest.raises(SunsetError, match=f"^{name} "):
        make_island(**kw)


def test_bad_cosine_and_arguments():
    with pytest.raises(SunsetError, match="^amplitude "):
        Cosine(-1.0, 0.1, 0.1)
    with pytest.raises(SunsetError, match="^l "):
        Cosine(1.0, float("nan"), 0.1)
    isl = make_island()
    with pytest.raises(SunsetError, match="^which "):
        isl.paraboloid(0.0, 0.0, "hill")
    with pytest.raises(SunsetError, match="^sea_max_elevation "):
        isl.chord(0.0, -1.0)
    with pytest.raises(SunsetError, match="^sea_max_elevation "):
        isl.bound_levels(float("nan"))
