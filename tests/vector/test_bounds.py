"""The bounding tests of the reflected rays (sunset.vector.pierce.island_candidates,
sunset.vector.crests.crest_candidates) skip only rays that miss, and skip most of those.

Each is checked against the quadratics themselves on every ray (the same
rays pierced without the test), on rays aimed at the surfaces, grazing them
and starting inside them; and a bound made too tight on purpose is caught.
"""

import math

import numpy as np
import pytest

from sunset.model.islands import Cosine, Island, Paraboloid
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain
from sunset.vector import crests, pierce

H = 2.0


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def islands(rng, n):
    out = list(Scene.default().islands)
    for _ in range(n):
        top = rng.uniform(20, 150)
        e, g = rng.uniform(5e-4, 8e-3, 2)
        f = rng.uniform(-0.95, 0.95) * 2 * math.sqrt(e * g)          # elongated ellipses too
        out.append(Island(x=rng.uniform(-300, 300), y=rng.uniform(300, 2000), cliff=Paraboloid(top, e, f, g),
                          beach=Paraboloid(rng.uniform(1, 8), e / rng.uniform(20, 150), 0.0, g / rng.uniform(20, 150)),
                          cliff_top=top * rng.uniform(0.2, 0.9), hill_factor=rng.uniform(0.1, 1.0),
                          cosines=(Cosine(2.0, 0.1, 0.05),)))
    return out


def island_rays(rng, island, n):
    """Rays from the sea aimed at the island (some grazing its top, some from under its beach) and at random."""
    ang = rng.uniform(0, 2 * math.pi, n)
    rad = math.sqrt(island.beach.height / island.beach.min_curvature) * rng.uniform(0.3, 4.0, n)
    q = np.column_stack([island.x + rad * np.cos(ang), island.y + rad * np.sin(ang), rng.uniform(-H - 3, -H + 2, n)])
    aim = np.column_stack([island.x + rng.normal(0, 80, n), island.y + rng.normal(0, 80, n),
                           rng.uniform(-H, island.smooth_height * 1.2, n) - H])
    r = unit(aim - q)
    k = n // 4
    r[:k] = unit(rng.normal(size=(k, 3)) * [1.0, 1.0, 0.3])      # anywhere, up or down
    r[k:k + 5] = [0.0, 0.0, 1.0]                                  # vertical
    # grazing: rays through a point of the smooth surface, along its tangent plane (± a hair)
    g = slice(k + 5, 2 * k)
    m = g.stop - g.start
    px = island.x + rng.normal(0, 60, m)
    py = island.y + rng.normal(0, 60, m)
    z = np.maximum(island.beach.value(px - island.x, py - island.y),
                   np.minimum(island.cliff.value(px - island.x, py - island.y),
                              island.cliff_top + island.hill_factor * (island.cliff.value(px - island.x, py - island.y)
                                                                        - island.cliff_top)))
    gx, gy = island.cliff.gradient(px - island.x, py - island.y)
    beach = island.beach.value(px - island.x, py - island.y) >= z - 1e-12
    bx, by = island.beach.gradient(px - island.x, py - island.y)
    gx, gy = np.where(beach, bx, gx), np.where(beach, by, gy)
    nrm = unit(np.column_stack([-gx, -gy, np.ones(m)]))
    tan = unit(np.cross(nrm, rng.normal(size=(m, 3))))
    tan[:, 2] += rng.choice([-1e-9, 0.0, 1e-9], m)
    back = rng.uniform(50, 800, m)
    q[g] = np.column_stack([px, py, z - H]) - back[:, None] * tan
    r[g] = tan
    return q, r


def hits_outside(candidates, rng, isles, n=3000):
    """Rays that hit an island although ``candidates`` set them aside, and how many rays it kept and hit."""
    missed = kept = hit = 0
    for isl in isles:
        q, r = island_rays(rng, isl, n)
        t, _ = pierce.pierce_island(isl, H, q, r)
        cand = candidates(isl, H, q, r)
        missed += int(np.sum(np.isfinite(t) & ~cand))
        kept += int(cand.sum())
        hit += int(np.isfinite(t).sum())
    return missed, kept, hit


def test_the_island_test_skips_only_misses():
    rng = np.random.default_rng(7)
    missed, kept, hit = hits_outside(pierce.island_candidates, rng, islands(rng, 25))
    assert missed == 0
    assert hit > 5000                       # the rays do hit, grazing ones included
    assert kept < 2.5 * hit                 # and most misses are set aside


def test_an_island_test_too_tight_is_caught(monkeypatch):
    """The check above sees a bound that undercuts the paraboloids (λ the largest eigenvalue, no grace)."""
    def too_tight(top, e, f, g, scale=1.0):
        big = 0.5 * (e + g + math.hypot(e - g, f)) * scale
        return big, big, top, 0.0
    monkeypatch.setattr(pierce, "_bounding_paraboloid", too_tight)
    rng = np.random.default_rng(7)
    missed, _, _ = hits_outside(pierce.island_candidates, rng, islands(rng, 25))
    assert missed > 0


def test_the_island_bounds_are_below_the_smallest_eigenvalue():
    for isl in islands(np.random.default_rng(3), 40):
        (lam_b, lo_b, hi_b, grace_b), (lam_u, lo_u, hi_u, grace_u) = pierce.island_bounds(isl, H)
        assert 0 < lam_b < isl.beach.min_curvature and 0 < lam_u < isl.hill_factor * isl.cliff.min_curvature
        assert lo_b < lam_b and hi_b > isl.beach.height - H and grace_b >= pierce.BOUND_GRACE
    # a form too thin to bound keeps every ray
    lam, lo, hi, grace = pierce._bounding_paraboloid(10.0, 1.0, 2.0, 1.0)   # f² = 4eg: λ = 0
    assert (lam, lo, hi, grace) == (0.0, 0.0, math.inf, 0.0)


def crest_rays(rng, sea, t, n):
    """Origins on the sea, rays every way: many low and rising, some grazing, some heading down."""
    q = np.column_stack([rng.uniform(-200, 200, n), rng.uniform(5, 2000, n), np.zeros(n)])
    q[:, 2] = -H + sea.elevation(q[:, 0], q[:, 1], t)
    r = rng.normal(size=(n, 3))
    r[: n // 2, 2] = np.abs(r[: n // 2, 2]) * rng.choice([0.01, 0.05, 0.3], n // 2)
    r[n // 2: n // 2 + n // 10, 2] = -np.abs(r[n // 2: n // 2 + n // 10, 2]) * 0.1
    return q, unit(r)


def crest_hits(train, t, q, r):
    cyl = crests.crest_cylinder(train, t, q, r)
    return np.isfinite(pierce.first_entry(*pierce.quadratic_interval(*crests.cylinder_coefficients(cyl, q, r))[::2]))


SEAS = {
    "order 1": Sea((WaveTrain(0.4, 30.0, direction=80.0, phase=0.3, stokes_order=1),)),
    "order 2": Sea((WaveTrain(0.5, 40.0, direction=95.0, phase=1.1, stokes_order=2),)),
    "order 4, steep": Sea((WaveTrain(1.6, 35.0, direction=100.0, phase=0.0, stokes_order=4),)),
    "default": Scene.default().sea,
}


@pytest.mark.parametrize("name", list(SEAS))
@pytest.mark.parametrize("t", [0.0, 2.3, 4000.5])
def test_the_crest_test_skips_only_misses(name, t):
    sea = SEAS[name]
    train = crests.largest_train(sea)
    q, r = crest_rays(np.random.default_rng(len(name)), sea, t, 40000)
    hit = crest_hits(train, t, q, r)
    cand = crests.crest_candidates(train, t, q, r)
    assert np.sum(hit & ~cand) == 0
    assert hit.sum() > 2000 and cand.sum() < 1.6 * hit.sum()


def test_a_crest_test_too_tight_is_caught(monkeypatch):
    """The check above sees a bound on the crest's height that is too low (the quadratic term alone)."""
    monkeypatch.setattr(crests, "CREST_GRACE", 0.0)
    monkeypatch.setattr(crests, "crest_rise", lambda amps, psi: 0.45 * np.minimum(psi, 2 * np.pi - psi) ** 2
                        * float(np.sum(amps)))
    sea = SEAS["order 4, steep"]
    train = crests.largest_train(sea)
    q, r = crest_rays(np.random.default_rng(1), sea, 2.3, 40000)
    assert np.sum(crest_hits(train, 2.3, q, r) & ~crests.crest_candidates(train, 2.3, q, r)) > 0


def test_the_crest_rise_bounds_the_crest_height():
    rng = np.random.default_rng(4)
    psi = np.concatenate([rng.uniform(0, 2 * np.pi, 100000), [0.0, np.pi, 2 * np.pi - 1e-15]])
    amps = np.array([0.5, 0.2, 0.05, 0.01])
    exact = sum(a * (1 - np.cos(n * psi)) for n, a in enumerate(amps, start=1))
    bound = crests.crest_rise(amps, psi)
    assert np.all(bound >= exact - 1e-15)              # (1 − cos of n·ψ near 2π is rounding)
    assert np.mean(bound - exact) < 0.25 * np.mean(exact)      # and it is not far above
    one = crests.crest_rise(amps[:1], psi)
    assert np.all(one <= 0.5 * (1 - np.cos(psi)) * (1 + 0.11) + 1e-15)   # one harmonic: within 11 %
