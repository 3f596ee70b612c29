"""Reflected rays (sunset/vector/pierce.py): reflection, piercing, crest cylinders, the frame.

Reference values come from independent computations: brute-force root finding
(dense stepping along each ray, then scipy's brentq) on the surfaces written
out here from their definitions, finite differences of the sea and island
surfaces, and the mirror geometry of still water.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from sunset.model.camera import Camera
from sunset.constants import PART_BEACH, PART_CLIFF, PART_HILL, PART_NONE, SEA, SKY
from sunset.errors import SunsetError
from sunset.vector.frame import Frame
from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.vector.crests import crest_curvature, crest_cylinder, cylinder_coefficients, largest_train, secondary_reflections
from sunset.vector.pierce import gather, island_normal, paraboloid_coefficients, pierce_island, pierce_islands, pierce_paraboloid, quadratic_interval, reflect, scatter
from sunset.pipeline.frame import trace_reflections
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain

RNG_SEED = 1981


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# ----------------------------------------------------------------------------- brute force
def first_crossing(inside, q, r, t_max, steps=20000):
    """First t in (0, t_max] where ``inside(points)`` (a signed function, >= 0 inside) goes
    from negative to non-negative, refined by brentq; +inf where it never does."""
    q = np.atleast_2d(q)
    r = np.atleast_2d(r)
    t_max = np.broadcast_to(np.asarray(t_max, dtype=float), (len(q),))
    out = np.full(len(q), np.inf)
    s = np.linspace(0.0, 1.0, steps + 1)
    for i in range(len(q)):  # a reference computation, not a hot path
        ts = s * t_max[i]
        pts = q[i] + ts[:, None] * r[i]
        val = inside(pts)
        up = np.flatnonzero((val[:-1] < 0) & (val[1:] >= 0))
        if len(up):
            j = up[0]
            g = lambda tt: float(inside((q[i] + tt * r[i])[None])[0])
            out[i] = ts[j + 1] if val[j + 1] == 0 else brentq(g, ts[j], ts[j + 1], xtol=1e-12, rtol=1e-13)
    return out


def para_height(pts, top, e, f, g, x0, y0):
    u = pts[..., 0] - x0
    v = pts[..., 1] - y0
    return top - e * u * u - f * u * v - g * v * v


def random_paraboloids(rng, n):
    e = rng.uniform(2e-4, 1e-2, n)
    g = rng.uniform(2e-4, 1e-2, n)
    f = rng.uniform(-0.95, 0.95, n) * 2 * np.sqrt(e * g)
    top = rng.uniform(3.0, 100.0, n)
    x0 = rng.uniform(-300, 300, n)
    y0 = rng.uniform(200, 1500, n)
    return top, e, f, g, x0, y0


def reach(q, r, top, e, f, g, x0, y0):
    """A distance beyond which a ray cannot be inside z <= P: past the footprint at the ray's lowest z."""
    lam = 0.5 * (e + g) - 0.5 * np.sqrt((e - g) ** 2 + f * f)  # smallest eigenvalue of the form
    zlow = np.minimum(q[:, 2], q[:, 2] + 5000 * np.minimum(r[:, 2], 0))
    radius = np.sqrt(np.maximum(top - zlow, 0) / lam)
    horiz = np.hypot(r[:, 0], r[:, 1])
    dist = np.hypot(q[:, 0] - x0, q[:, 1] - y0) + radius
    return np.where(horiz > 1e-6, dist / np.maximum(horiz, 1e-6) + 10, 5000.0)


# ----------------------------------------------------------------------------- reflection
@pytest.mark.parametrize("shape", [(3,), (6, 3), (2, 3, 3), (2, 3, 1, 3)])
def test_reflection_keeps_length_and_angle(shape):
    rng = np.random.default_rng(RNG_SEED)
    d = rng.normal(size=shape) * 2.5
    n = unit(rng.normal(size=shape))
    r = reflect(d, n)
    assert r.shape == shape
    np.testing.assert_allclose(np.linalg.norm(r, axis=-1), np.linalg.norm(d, axis=-1), rtol=1e-12)
    np.testing.assert_allclose(np.sum(r * n, axis=-1), -np.sum(d * n, axis=-1), atol=1e-12)
    # R − D is along N: the tangential part is unchanged
    np.testing.assert_allclose(np.cross(r - d, n), 0.0, atol=1e-12)


def test_reflection_in_still_water_is_a_mirror():
    d = unit(np.array([[0.1, 1.0, -0.2], [-0.3, 1.0, -0.05]]))
    r = reflect(d, np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(r, d * np.array([1, 1, -1]), atol=1e-15)


@pytest.mark.parametrize("d, n, name", [
    (np.zeros(2), np.zeros(3), "d"),
    (np.zeros(3), np.zeros((4, 2)), "n"),
    (np.array([np.nan, 0, 1]), np.array([0, 0, 1.0]), "d"),
    (np.array([0, 1, -1.0]), np.array([0, np.inf, 1.0]), "n"),
])
def test_reflection_bad_input(d, n, name):
    with pytest.raises(SunsetError, match=f"^{name} "):
        reflect(d, n)


# ----------------------------------------------------------------------------- the quadratic
def test_coefficients_reproduce_the_surface_along_the_ray():
    rng = np.random.default_rng(RNG_SEED)
    top, e, f, g, x0, y0 = random_paraboloids(rng, 50)
    q = np.column_stack([rng.uniform(-500, 500, 50), rng.uniform(0, 2000, 50), rng.uniform(-3, 1, 50)])
    r = unit(rng.normal(size=(50, 3)))
    a, b, c = paraboloid_coefficients(q, r, top, e, f, g, x0, y0)
    for t in (0.0, 1.3, 77.0, -20.0):
        s = q + t * r
        np.testing.assert_allclose(a * t * t + b * t + c, para_height(s, top, e, f, g, x0, y0) - s[:, 2],
                                   rtol=1e-9, atol=1e-8)


def test_piercing_random_rays_against_brute_force():
    rng = np.random.default_rng(RNG_SEED)
    n = 160
    top, e, f, g, x0, y0 = random_paraboloids(rng, n)
    # origins near the sea, some inside the footprint, directions aimed at the apex region or anywhere
    q = np.column_stack([x0 + rng.uniform(-400, 400, n), y0 + rng.uniform(-400, 400, n), rng.uniform(-4, 2, n)])
    aim = np.column_stack([x0 + rng.normal(0, 60, n), y0 + rng.normal(0, 60, n), rng.uniform(-10, 60, n)])
    r = unit(np.where(rng.uniform(size=(n, 1)) < 0.7, aim - q, rng.normal(size=(n, 3))))
    got = pierce_paraboloid(q, r, top, e, f, g, x0, y0)
    t_max = reach(q, r, top, e, f, g, x0, y0)
    for i in range(n):
        want = first_crossing(lambda p: para_height(p, top[i], e[i], f[i], g[i], x0[i], y0[i]) - p[:, 2],
                              q[i], r[i], t_max[i])[0]
        if math.isinf(want):
            assert math.isinf(got[i]), i
        else:
            assert got[i] == pytest.approx(want, rel=1e-9, abs=1e-7), i
    hits = np.isfinite(got)
    assert 0.2 < hits.mean() < 0.9  # both cases are exercised


def test_inside_origin_rays_never_enter():
    # an origin under the surface: the ray leaves the solid and cannot come back (a convex solid)
    rng = np.random.default_rng(7)
    n = 40
    top, e, f, g, x0, y0 = random_paraboloids(rng, n)
    q = np.column_stack([x0 + rng.uniform(-20, 20, n), y0 + rng.uniform(-20, 20, n), np.zeros(n)])
    q[:, 2] = para_height(q, top, e, f, g, x0, y0) - rng.uniform(0.1, 2.0, n)
    r = unit(rng.normal(size=(n, 3)))
    got = pierce_paraboloid(q, r, top, e, f, g, x0, y0)
    t_max = reach(q, r, top, e, f, g, x0, y0)
    for i in range(n):
        want = first_crossing(lambda p: para_height(p, top[i], e[i], f[i], g[i], x0[i], y0[i]) - p[:, 2],
                              q[i], r[i], t_max[i])[0]
        assert math.isinf(want) and math.isinf(got[i])


def tangent_rays(rng, n, lift):
    """Rays touching the paraboloid at a point S0, then moved up (lift > 0) or down by |lift|."""
    top, e, f, g, x0, y0 = random_paraboloids(rng, n)
    s0 = np.column_stack([x0 + rng.uniform(-60, 60, n), y0 + rng.uniform(-60, 60, n), np.zeros(n)])
    s0[:, 2] = para_height(s0, top, e, f, g, x0, y0)
    u, v = s0[:, 0] - x0, s0[:, 1] - y0
    grad = np.column_stack([-(2 * e * u + f * v), -(f * u + 2 * g * v), -np.ones(n)])  # ∇(P − z)
    r = unit(np.cross(grad, rng.normal(size=(n, 3))))  # tangent to the surface at s0
    t0 = rng.uniform(5, 200, n)
    q = s0 - t0[:, None] * r
    q[:, 2] += lift
    return q, r, t0, (top, e, f, g, x0, y0)


def test_tangent_ray_touches_at_the_tangent_point_or_misses():
    rng = np.random.default_rng(11)
    q, r, t0, par = tangent_rays(rng, 60, 0.0)
    got = pierce_paraboloid(q, r, *par)
    touched = np.isfinite(got)
    # rounding decides between a touch and a miss; a touch is at the tangent point
    np.testing.assert_allclose(got[touched], t0[touched], rtol=1e-3)
    a, b, c = paraboloid_coefficients(q, r, *par)
    assert np.all(np.abs(b * b - 4 * a * c) <= 1e-9 * np.maximum(b * b, 1.0))


@pytest.mark.parametrize("lift", [-1e-3, 1e-3])
def test_grazing_rays_against_brute_force(lift):
    rng = np.random.default_rng(12)
    q, r, t0, par = tangent_rays(rng, 40, lift)
    got = pierce_paraboloid(q, r, *par)
    top, e, f, g, x0, y0 = par
    for i in range(len(q)):
        want = first_crossing(lambda p: para_height(p, top[i], e[i], f[i], g[i], x0[i], y0[i]) - p[:, 2],
                              q[i], r[i], 2 * t0[i], steps=40000)[0]
        if lift > 0:
            assert math.isinf(want) and math.isinf(got[i])
        else:
            assert got[i] == pytest.approx(want, rel=1e-7), i
            assert got[i] < t0[i]  # a short chord around the old tangent point


def test_vertical_rays_are_linear():
    # R_x = R_y = 0 gives a = 0: down from above hits at Q_z − P, up never enters
    top, e, f, g, x0, y0 = 20.0, 0.004, 0.001, 0.003, 10.0, 500.0
    q = np.array([[30.0, 480.0, 50.0], [30.0, 480.0, 50.0], [30.0, 480.0, 0.0], [30.0, 480.0, 0.0]])
    r = np.array([[0, 0, -1.0], [0, 0, 1.0], [0, 0, 1.0], [0, 0, -1.0]])
    got = pierce_paraboloid(q, r, top, e, f, g, x0, y0)
    p = para_height(q[:1], top, e, f, g, x0, y0)[0]
    assert got[0] == pytest.approx(50.0 - p, rel=1e-12)
    assert np.all(np.isinf(got[1:]))  # going up; starting inside, going up or down


def test_quadratic_interval_linear_and_double_root_cases():
    t_in, t_out, meets = quadratic_interval([0.0, 0.0, 0.0, 0.0, -1.0], [2.0, -2.0, 0.0, 0.0, 0.0],
                                            [-4.0, 4.0, 1.0, -1.0, 0.0])
    assert list(meets) == [True, True, True, False, True]
    np.testing.assert_array_equal(t_in[:3], [2.0, -np.inf, -np.inf])
    np.testing.assert_array_equal(t_out[:3], [np.inf, 2.0, np.inf])
    assert t_in[4] == 0.0 and t_out[4] == 0.0


@pytest.mark.parametrize("shape", [(6,), (2, 3), (2, 3, 1)])
def test_piercing_shapes(shape):
    rng = np.random.default_rng(3)
    q = rng.normal(size=shape + (3,)) * 50 + np.array([0, 500, 0])
    r = unit(rng.normal(size=shape + (3,)))
    t = pierce_paraboloid(q, r, 10.0, 0.004, 0.0, 0.004, 0.0, 500.0)
    assert t.shape == shape
    assert np.all((t > 0) | np.isinf(t))


def test_piercing_bad_input():
    with pytest.raises(SunsetError, match="^q "):
        pierce_paraboloid(np.array([0.0, np.nan, 0.0]), np.array([0, 1.0, 0]), 1.0, 1e-3, 0.0, 1e-3, 0.0, 0.0)
    with pytest.raises(SunsetError, match="^r "):
        pierce_paraboloid(np.zeros(3), np.zeros(2), 1.0, 1e-3, 0.0, 1e-3, 0.0, 0.0)


# ----------------------------------------------------------------------------- islands
def random_island(rng, y=900.0, cosines=True):
    top = rng.uniform(30, 120)
    e, g = rng.uniform(1e-3, 6e-3, 2)
    f = rng.uniform(-0.8, 0.8) * 2 * math.sqrt(e * g)
    return Island(
        x=rng.uniform(-200, 200), y=y, cliff=Paraboloid(top, e, f, g),
        # a beach wider than the cliff's foot (beach e, g < cliff's × beach height / top) shows around it
        beach=Paraboloid(rng.uniform(1.0, 4.0), e / rng.uniform(40, 150), 0.0, g / rng.uniform(40, 150)),
        cliff_top=top * rng.uniform(0.25, 0.8), hill_factor=rng.uniform(0.2, 1.0),
        cosines=tuple(Cosine(rng.uniform(0, 4), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2))
                      for _ in range(2 if cosines else 0)))


def island_solid(island, h):
    """Signed 'inside' function of the island solid max(beach, min(cliff, hill)) − z, eye coordinates."""
    def f(p):
        pc = para_height(p, island.cliff.height, island.cliff.e, island.cliff.f, island.cliff.g, island.x, island.y)
        hill = island.cliff_top + island.hill_factor * (pc - island.cliff_top)
        pb = para_height(p, island.beach.height, island.beach.e, island.beach.f, island.beach.g, island.x, island.y)
        return np.maximum(pb, np.minimum(pc, hill)) - h - p[:, 2]
    return f


def island_part_at(island, p):
    """The part whose surface is on top at p (without cosines), from the definitions."""
    pc = para_height(p, island.cliff.height, island.cliff.e, island.cliff.f, island.cliff.g, island.x, island.y)
    hill = island.cliff_top + island.hill_factor * (pc - island.cliff_top)
    pb = para_height(p, island.beach.height, island.beach.e, island.beach.f, island.beach.g, island.x, island.y)
    return np.where(pb >= np.minimum(pc, hill), PART_BEACH, np.where(hill < pc, PART_HILL, PART_CLIFF))


def test_island_piercing_against_brute_force():
    rng = np.random.default_rng(RNG_SEED)
    h = 2.0
    checked = {PART_BEACH: 0, PART_CLIFF: 0, PART_HILL: 0, PART_NONE: 0}
    for _ in range(6):
        island = random_island(rng, y=rng.uniform(400, 1200))
        n = 50
        # origins on the sea plane around the island, some close to its foot
        ang = rng.uniform(0, 2 * math.pi, n)
        rad = np.sqrt(island.cliff.height / max(island.cliff.e, island.cliff.g)) * rng.uniform(0.9, 4.0, n)
        q = np.column_stack([island.x + rad * np.cos(ang), island.y + rad * np.sin(ang), rng.uniform(-h - 1, -h + 1, n)])
        aim = np.column_stack([island.x + rng.normal(0, 50, n), island.y + rng.normal(0, 50, n),
                               rng.uniform(-h, island.cliff.height, n) - h])
        r = unit(aim - q)
        t, part = pierce_island(island, h, q, r)
        want = first_crossing(island_solid(island, h), q, r, 3 * rad + 400, steps=30000)
        for i in range(n):
            if math.isinf(want[i]):
                assert math.isinf(t[i]) and part[i] == PART_NONE, i
            else:
                assert t[i] == pytest.approx(want[i], rel=1e-8, abs=1e-6), i
                p = q[i] + want[i] * r[i]
                assert part[i] == island_part_at(island, p[None])[0], i
            checked[int(part[i])] += 1
    assert all(v > 0 for v in checked.values()), checked


def test_island_piercing_from_inside_the_beach():
    # a sea point under the beach paraboloid (inside the solid): the ray leaves and sees no island
    island = Island(x=0.0, y=800.0, cliff=Paraboloid(60.0, 0.004, 0.0, 0.004),
                    beach=Paraboloid(3.0, 0.0003, 0.0, 0.0003), cliff_top=30.0)
    h = 2.0
    q = np.array([[0.0, 800.0 - 99.0, -h - 0.1]])  # inside the beach's footprint, below it
    assert island_solid(island, h)(q)[0] > 0
    r = unit(np.array([[0.0, 1.0, 0.3]]))
    t, part = pierce_island(island, h, q, r)
    assert math.isinf(t[0]) and part[0] == PART_NONE
    assert math.isinf(first_crossing(island_solid(island, h), q, r, 2000)[0])


def test_nearest_island_wins():
    h = 2.0
    near = Island(x=0.0, y=500.0, cliff=Paraboloid(40.0, 0.004, 0.0, 0.004), beach=Paraboloid(2.0, 4e-4, 0, 4e-4),
                  cliff_top=20.0)
    far = Island(x=0.0, y=1500.0, cliff=Paraboloid(200.0, 0.004, 0.0, 0.004), beach=Paraboloid(2.0, 4e-4, 0, 4e-4),
                 cliff_top=100.0)
    q = np.array([[0.0, 0.0, -h], [0.0, 0.0, -h], [400.0, 0.0, -h]])
    r = unit(np.array([[0.0, 1.0, 0.02], [0.0, 1.0, 0.06], [0.0, 1.0, 0.02]]))
    for order in ((near, far), (far, near)):
        t, which, part = pierce_islands(order, h, q, r)
        k_near = 1 + order.index(near)
        k_far = 1 + order.index(far)
        assert which[0] == k_near  # low ray: both in line, the near one first
        assert which[1] == k_far   # steeper ray clears the near island, meets the tall far one
        assert which[2] == SKY and math.isinf(t[2]) and part[2] == PART_NONE
        want = [first_crossing(island_solid(isl, h), q[i], r[i], 3000)[0] for i, isl in ((0, near), (1, far))]
        np.testing.assert_allclose(t[:2], want, rtol=1e-9)


def test_wrinkle_normal_matches_finite_differences():
    rng = np.random.default_rng(5)
    island = random_island(rng)
    x = island.x + rng.uniform(-80, 80, 30)
    y = island.y + rng.uniform(-80, 80, 30)
    part = rng.choice([PART_BEACH, PART_CLIFF, PART_HILL], 30)

    def surface(x, y, p):  # heights of each part, with the cosines on cliff and hill (eq. 4)
        pc = island.cliff.height - island.cliff.e * (x - island.x) ** 2 - island.cliff.f * (x - island.x) * (
            y - island.y) - island.cliff.g * (y - island.y) ** 2
        qq = pc + sum(c.amplitude * np.cos(c.l * x + c.m * y) for c in island.cosines)
        pb = island.beach.height - island.beach.e * (x - island.x) ** 2 - island.beach.g * (y - island.y) ** 2
        return np.where(p == PART_BEACH, pb, np.where(p == PART_HILL, island.hill_factor * qq, qq))

    eps = 1e-5
    gx = (surface(x + eps, y, part) - surface(x - eps, y, part)) / (2 * eps)
    gy = (surface(x, y + eps, part) - surface(x, y - eps, part)) / (2 * eps)
    want = unit(np.column_stack([-gx, -gy, np.ones_like(gx)]))
    got = island_normal(island, x, y, part)
    np.testing.assert_allclose(got, want, atol=1e-7)
    # shape (2, 3) -> (2, 3, 3)
    assert island_normal(island, x[:6].reshape(2, 3), y[:6].reshape(2, 3), part[:6].reshape(2, 3)).shape == (2, 3, 3)


# ----------------------------------------------------------------------------- crest cylinders
def cylinder_height(cyl, i, x, y):
    return para_height(np.stack([x, y], -1), cyl.top[i], cyl.e, cyl.f, cyl.g, cyl.x0[i], cyl.y0[i])


@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_crest_cylinder_is_tangent_to_the_crest_with_its_curvature(order):
    rng = np.random.default_rng(order)
    h = 2.0
    train = WaveTrain(0.6, 35.0, direction=rng.uniform(0, 360), phase=rng.uniform(0, 6), stokes_order=order)
    sea = Sea((train,))
    t = 3.7
    n = 25
    q = np.column_stack([rng.uniform(-50, 50, n), rng.uniform(5, 200, n), np.zeros(n)])
    q[:, 2] = -h + sea.elevation(q[:, 0], q[:, 1], t)
    r = unit(np.column_stack([rng.normal(size=n), rng.normal(size=n), rng.uniform(-0.3, 0.3, n)]))
    cyl = crest_cylinder(train, t, q, r)
    l, m = train.wave_vector
    k = train.k
    c_dir = np.array([l, m]) / k                      # across the crest
    along = np.array([-m, l]) / k                     # along the crest
    assert cyl.f ** 2 == pytest.approx(4 * cyl.e * cyl.g, rel=1e-12)
    for i in range(n):
        # the crest line the ray meets first: its crossing point, from the phase along the ray
        rate = l * r[i, 0] + m * r[i, 1]
        theta0 = l * q[i, 0] + m * q[i, 1] - train.omega * t + train.phase
        ts = np.linspace(0, 2 * math.pi / abs(rate), 20001)[1:]
        turns = np.floor((theta0 + rate * ts) / (2 * math.pi))
        j = np.flatnonzero(turns != np.floor(theta0 / (2 * math.pi)))[0]  # first crest crossed
        tc = brentq(lambda s: math.sin(0.5 * (theta0 + rate * s)), ts[j - 1] if j else 1e-12, ts[j])
        cx, cy = q[i, :2] + tc * r[i, :2]
        # foot of the cylinder is on that line
        assert np.dot(np.array([cyl.x0[i] - cx, cyl.y0[i] - cy]), c_dir) == pytest.approx(0, abs=1e-6)
        # tangent: same height as the wave at the crest, anywhere along the crest line
        for s in (-30.0, 0.0, 12.0):
            px, py = np.array([cx, cy]) + s * along
            assert cylinder_height(cyl, i, px, py) == pytest.approx(-h + sea.elevation(px, py, t), abs=1e-9)
        # zero slope and curvature −κ across the crest, as the wave's own second difference
        du = 0.05  # exact for the parabola; O((nk du)²) for the wave
        xs = cx + np.array([-du, 0, du]) * c_dir[0]
        ys = cy + np.array([-du, 0, du]) * c_dir[1]
        zc = cylinder_height(cyl, i, xs, ys)
        zw = -h + sea.elevation(xs, ys, t)
        assert (zc[2] - zc[0]) / (2 * du) == pytest.approx(0, abs=1e-9)
        assert (zc[2] - 2 * zc[1] + zc[0]) / du**2 == pytest.approx(-cyl.curvature, rel=1e-6)
        assert (zw[2] - 2 * zw[1] + zw[0]) / du**2 == pytest.approx(-cyl.curvature, rel=1e-3)


def test_crest_curvature_is_the_series_second_derivative():
    train = WaveTrain(0.5, 40.0, stokes_order=4)
    amps = train.harmonic_amplitudes()
    z = lambda x: sum(a * math.cos((n + 1) * train.k * x) for n, a in enumerate(amps))
    du = 1e-3
    assert crest_curvature(train) == pytest.approx(-(z(du) - 2 * z(0) + z(-du)) / du**2, rel=1e-5)


def test_cylinder_coefficients_agree_with_the_degenerate_paraboloid():
    rng = np.random.default_rng(9)
    train = WaveTrain(0.5, 40.0, direction=70.0, stokes_order=2)
    n = 200
    q = np.column_stack([rng.uniform(-50, 50, n), rng.uniform(5, 200, n), rng.uniform(-3, -1, n)])
    r = unit(rng.normal(size=(n, 3)))
    cyl = crest_cylinder(train, 0.0, q, r)
    got = cylinder_coefficients(cyl, q, r)
    want = paraboloid_coefficients(q, r, cyl.top, cyl.e, cyl.f, cyl.g, cyl.x0, cyl.y0)
    for gv, wv in zip(got, want):
        np.testing.assert_allclose(gv, wv, rtol=1e-9, atol=1e-9)


def sea_with_swell():
    return Sea((WaveTrain(0.12, 10.0, 120.0, 1.0), WaveTrain(0.5, 40.0, 80.0, 0.0, 2),
                WaveTrain(0.05, 40 / 9, 60.0, 2.0)))


def test_largest_train():
    sea = sea_with_swell()
    assert largest_train(sea) is sea.trains[1]
    assert largest_train(Sea(())) is None
    assert largest_train(Sea((WaveTrain(0.0, 10.0),))) is None


def test_secondary_reflections_from_the_crest():
    rng = np.random.default_rng(21)
    sea = sea_with_swell()
    h, t = 2.0, 1.25
    n = 3000
    q = np.column_stack([rng.uniform(-40, 40, n), rng.uniform(10, 300, n), np.zeros(n)])
    q[:, 2] = -h + sea.elevation(q[:, 0], q[:, 1], t)
    r = unit(np.column_stack([rng.normal(size=n), rng.uniform(0.2, 2, n), rng.uniform(-0.4, 0.4, n)]))
    train = largest_train(sea)
    # the origin is never inside its cylinder, so every ray heading down meets it
    a, b, c = cylinder_coefficients(crest_cylinder(train, t, q, r), q, r)
    assert np.all(c <= 1e-12)
    idx, point, ray2 = secondary_reflections(sea, t, q, r)
    hit = np.zeros(n, bool)
    hit[idx] = True
    assert np.all(hit[r[:, 2] < 0])
    assert 0 < hit[r[:, 2] > 0].sum() < (r[:, 2] > 0).sum()
    # the piercing point is on the cylinder, in front of the origin
    cyl = crest_cylinder(train, t, q[idx], r[idx])
    tt = np.einsum("ij,ij->i", point - q[idx], r[idx])
    assert np.all(tt > 0)
    np.testing.assert_allclose(point, q[idx] + tt[:, None] * r[idx], atol=1e-9)
    on = para_height(point, cyl.top, cyl.e, cyl.f, cyl.g, cyl.x0, cyl.y0) - point[:, 2]
    np.testing.assert_allclose(on, 0.0, atol=1e-8)
    # reflected off the true wave normal there (the normal from finite differences of the sea)
    eps = 1e-5
    fx = (sea.elevation(point[:, 0] + eps, point[:, 1], t) - sea.elevation(point[:, 0] - eps, point[:, 1], t)) / (2 * eps)
    fy = (sea.elevation(point[:, 0], point[:, 1] + eps, t) - sea.elevation(point[:, 0], point[:, 1] - eps, t)) / (2 * eps)
    nrm = unit(np.column_stack([-fx, -fy, np.ones_like(fx)]))
    want = r[idx] - 2 * np.sum(r[idx] * nrm, axis=1, keepdims=True) * nrm
    np.testing.assert_allclose(ray2, want, atol=1e-6)


def test_secondary_reflections_on_still_water_are_none():
    q = np.array([[0.0, 10.0, -2.0]])
    idx, point, ray2 = secondary_reflections(Sea(()), 0.0, q, np.array([[0.0, 1.0, -0.1]]))
    assert idx.shape == (0,) and point.shape == (0, 3) and ray2.shape == (0, 3)


# ----------------------------------------------------------------------------- gather and scatter
@pytest.mark.parametrize("shape", [(6,), (6, 3), (50, 3)])
def test_gather_then_scatter_is_the_identity(shape):
    rng = np.random.default_rng(2)
    arr = rng.normal(size=shape)
    other = rng.normal(size=shape[:1])
    mask = rng.uniform(size=shape[0]) < 0.4
    idx, (packed, packed_other) = gather(mask, arr, other)
    assert packed.shape == (mask.sum(),) + shape[1:]
    assert np.array_equal(packed, arr[mask]) and np.array_equal(packed_other, other[mask])
    back = scatter(idx, packed, np.full(shape, np.nan))
    assert np.array_equal(back[mask], arr[mask]) and np.all(np.isnan(back[~mask]))
    assert np.array_equal(scatter(idx, packed, arr.copy()), arr)


# ----------------------------------------------------------------------------- the frame
def still_frame(scene):
    """A direct-ray frame for still water computed here from the geometry (no height field):
    the ray meets the island (brute force) or the plane z = −h or the sky."""
    cam = scene.camera
    h = cam.eye_height
    d = cam.directions()
    H, W = d.shape[:2]
    dist = np.full((H, W), np.inf)
    surface = np.full((H, W), SKY, np.int8)
    down = d[..., 2] < 0
    with np.errstate(divide="ignore"):
        t_sea = np.where(down, -h / np.where(down, d[..., 2], -1.0), np.inf)
    dist = np.where(down, t_sea, dist)
    surface[down] = SEA
    flat = d.reshape(-1, 3)
    for k, island in enumerate(scene.islands, start=1):
        t_k = first_crossing(island_solid(island, h), np.zeros((len(flat), 3)), flat,
                             np.minimum(dist.ravel(), 6000.0), steps=4000).reshape(H, W)
        nearer = t_k < dist
        dist = np.where(nearer, t_k, dist)
        surface[nearer] = k
    point = np.where(np.isfinite(dist)[..., None], d * dist[..., None], np.nan)
    normal = np.where((surface == SEA)[..., None], np.array([0.0, 0.0, 1.0]), np.nan)
    normal[surface >= 1] = [0.0, 0.0, 1.0]  # not used by the reflections
    return Frame(t=0.0, reflections=1, direction=d.astype(np.float32), surface=surface,
                 part=np.zeros((H, W), np.int8), distance=dist.astype(np.float32),
                 point=point.astype(np.float32), normal=normal.astype(np.float32))


def small_still_scene(width=24, height=20):
    base = Scene.default()
    cam = Camera(eye_height=base.camera.eye_height, width=width, height=height,
                 s_min=-0.45, s_max=0.5, zy_min=-0.12, zy_max=0.08)
    return Scene(camera=cam, sun=base.sun, sea=Sea(()), islands=base.islands)


def test_still_water_is_a_mirror_of_the_islands():
    scene = small_still_scene()
    h = scene.camera.eye_height
    frame = trace_reflections(scene, still_frame(scene).finish_direct(), 1)
    sea = frame.surface == SEA
    assert np.all(frame.bounces[sea] == 1) and np.all(frame.bounces[~sea] == 0)
    # the reflected ray is the direct ray of a virtual eye at z = −2h, mirrored
    d = frame.direction[sea].astype(float)
    mirrored = d * np.array([1, 1, -1])
    np.testing.assert_allclose(frame.ray[sea], mirrored, atol=1e-6)
    virtual_eye = np.array([0.0, 0.0, -2 * h])
    start = h / mirrored[:, 2]  # where the virtual eye's ray crosses the sea plane
    want_k = np.full(len(d), SKY)
    want_part = np.zeros(len(d), int)
    want_t = np.full(len(d), np.inf)
    for k, island in enumerate(scene.islands, start=1):
        origin = virtual_eye + start[:, None] * mirrored
        tk = first_crossing(island_solid(island, h), origin, mirrored, 6000.0, steps=6000)
        nearer = tk < want_t
        want_t = np.where(nearer, tk, want_t)
        want_k = np.where(nearer, k, want_k)
        hitp = origin + np.where(np.isfinite(tk), tk, 0)[:, None] * mirrored
        want_part = np.where(nearer, island_part_at(island, hitp), want_part)
    np.testing.assert_array_equal(frame.final_surface[sea], want_k)
    np.testing.assert_array_equal(frame.final_part[sea], np.where(want_k > 0, want_part, PART_NONE))
    assert (want_k > 0).sum() >= 10 and (want_k == SKY).sum() >= 10  # islands and sky both reflected
    fn = frame.final_normal[sea]
    assert np.all(np.isnan(fn[want_k == SKY]))
    np.testing.assert_allclose(np.linalg.norm(fn[want_k > 0], axis=1), 1.0, atol=1e-5)
    # in still water, mode 2 finds no second reflection and changes nothing
    frame2 = trace_reflections(scene, still_frame(scene).finish_direct(), 2)
    for name in ("bounces", "ray", "final_surface", "final_part"):
        np.testing.assert_array_equal(getattr(frame2, name), getattr(frame, name))


def test_mode_0_goes_straight_to_the_sky():
    scene = small_still_scene(12, 10)
    frame = trace_reflections(scene, still_frame(scene).finish_direct(), 0)
    sea = frame.surface == SEA
    assert np.all(frame.final_surface[sea] == SKY) and np.all(frame.final_part[sea] == PART_NONE)
    assert np.all(frame.ray[sea][:, 2] >= 0) and np.all(np.isnan(frame.final_normal[sea]))
    # pixels that are not sea keep what finish_direct gave them
    direct = still_frame(scene).finish_direct()
    np.testing.assert_array_equal(frame.final_surface[~sea], direct.final_surface[~sea])
    np.testing.assert_array_equal(frame.ray[~sea], direct.ray[~sea])


def test_waves_frame_modes_1_and_2():
    # a synthetic wavy frame: direct rays meet the waves (brute force), then each mode
    cam = Camera(eye_height=2.0, width=16, height=12, s_min=-0.3, s_max=0.3, zy_min=-0.3, zy_max=-0.01)
    sea = sea_with_swell()
    scene = Scene(camera=cam, sea=sea, islands=Scene.default().islands)
    d = cam.directions()
    flat = d.reshape(-1, 3)
    depth = first_crossing(lambda p: -2.0 + sea.elevation(p[:, 0], p[:, 1], 0.0) - p[:, 2],
                           np.zeros((len(flat), 3)), flat, 2000.0, steps=20000)
    point = flat * depth[:, None]
    nrm = sea.normal(point[:, 0], point[:, 1], 0.0)
    shape = d.shape[:2]

    def frame():
        return Frame(t=0.0, reflections=2, direction=d.astype(np.float32), surface=np.zeros(shape, np.int8),
                     part=np.zeros(shape, np.int8), distance=depth.reshape(shape).astype(np.float32),
                     point=point.reshape(d.shape).astype(np.float32),
                     normal=nrm.reshape(d.shape).astype(np.float32)).finish_direct()

    f1 = trace_reflections(scene, frame(), 1)
    f2 = trace_reflections(scene, frame(), 2)
    assert np.all(f1.bounces == 1)
    assert set(np.unique(f2.bounces)) <= {1, 2}
    for f in (f1, f2):
        assert np.all(f.ray[..., 2] >= 0)
        np.testing.assert_allclose(np.linalg.norm(f.ray, axis=-1), 1.0, atol=1e-5)
        assert f.final_surface.dtype == np.int8 and f.final_part.dtype == np.int8
        assert f.ray.dtype == np.float32 and f.final_normal.dtype == np.float32
    once = f2.bounces == 1
    np.testing.assert_array_equal(f2.ray[once], f1.ray[once])  # rays that clear the crest: mode 1's
    # a first reflected ray heading down must meet the water again
    r1 = reflect(d.reshape(-1, 3), nrm).reshape(d.shape)
    assert np.all(f2.bounces[r1[..., 2] < 0] == 2)


@pytest.mark.parametrize("mode", [3, -1, 1.5, True, "1"])
def test_bad_reflection_mode(mode):
    scene = small_still_scene(4, 4)
    with pytest.raises(SunsetError, match="^reflections "):
        trace_reflections(scene, still_frame(scene).finish_direct(), mode)


def test_bounding_test_only_skips_misses():
    # pierce_islands culls rays by a bounding circle; every ray it skips must miss the island
    rng = np.random.default_rng(33)
    h = 2.0
    islands = [random_island(rng, y=rng.uniform(300, 1500)) for _ in range(3)]
    n = 4000
    q = np.column_stack([rng.uniform(-600, 600, n), rng.uniform(0, 1500, n), rng.uniform(-h - 0.7, -h + 0.7, n)])
    r = unit(np.column_stack([rng.normal(size=n), rng.uniform(-0.2, 1, n), rng.uniform(-0.05, 0.4, n)]))
    r[:5] = [0.0, 0.0, 1.0]  # vertical rays
    t, which, part = pierce_islands(islands, h, q, r)
    full = np.column_stack([pierce_island(isl, h, q, r)[0] for isl in islands])
    np.testing.assert_array_equal(t, full.min(axis=1))
    np.testing.assert_array_equal(which, np.where(np.isfinite(full.min(axis=1)), full.argmin(axis=1) + 1, SKY))
    assert 0.02 < np.isfinite(t).mean() < 0.9


# ----------------------------------------------------------------------------- the diagnostic figure
def test_reflection_modes_figure(tmp_path):
    from PIL import Image as PILImage

    from sunset.figures.reflections import reflection_modes

    a = reflection_modes(tmp_path / "a.png", size=(24, 16))
    b = reflection_modes(tmp_path / "b.png", size=(24, 16))
    assert a.read_bytes() == b.read_bytes()  # deterministic
    with PILImage.open(a) as img:
        assert img.size[0] > 100
    with pytest.raises(SunsetError, match="^width "):
        reflection_modes(tmp_path / "c.png", size=(0, 16))
    assert not (tmp_path / "c.png").exists()


def test_a_train_too_small_for_a_crest_curvature_counts_as_still_water():
    """Amplitude 1e-323 m: κ = Σ aₙ(nk)² underflows to 0, which would divide by zero in the crest test."""
    from dataclasses import replace

    from sunset import kernels
    from sunset.model.scene import Scene
    from sunset.model.waves import Sea, WaveTrain
    from sunset.vector.crests import largest_train
    from sunset.pipeline.frame import render

    tiny = Sea((WaveTrain(amplitude=1e-323, wavelength=40.0, direction=90.0),))   # k·a rounds to 0
    assert largest_train(tiny) is None
    scene = replace(Scene.default().with_size(24, 20), sea=tiny)
    for flag in (False, True):
        with kernels.use_compiled(flag):
            frame = render(scene, 0.0, 2)
        assert (frame.bounces <= 1).all()
