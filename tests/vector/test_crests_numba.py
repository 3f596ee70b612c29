"""The compiled reflected rays (sunset.vector.crests_numba, reflect_numba) against the NumPy reference.

Float64 throughout, with the C library's sine and cosine on the compiled
path: the sea's and the islands' normals at a point agree to a few float64
roundings, the distances to the crest cylinder to 1e-9 but where a ray
grazes the cylinder (the quadratic's root is then as sensitive as its
discriminant is small), the reflected frames as tests/agree.py says; each
path gives the same bytes on any number of threads.
"""

from dataclasses import fields

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import SEA
from sunset.model.scene import Scene
from sunset.vector import crests, crests_numba, pierce, reflect, reflect_numba
from sunset.vector.frame import Frame
from sunset.pipeline.frame import encode
from sunset.pipeline.frame import trace_direct, trace_reflections

from ..agree import assert_codes_agree, assert_geometry_agrees
from .test_slopes_numba import same_bits, seas

#: Unit normals at a point, float64 on both paths: a few roundings of the sums of sines.
NORMAL64_ATOL = 1e-13
#: Distances to the crest cylinder, relative, on all but CREST_GRAZING_SHARE of the hits (measured: half of
#: them within 6e-15, 99 % within 6e-12; 0.23 % over 1e-9, rays that graze the cylinder).
CREST_DISTANCE_RTOL = 1e-9
CREST_GRAZING_SHARE = 0.005


def scene_with(name, size=(120, 90)):
    base = Scene.default().with_size(*size)
    return Scene(camera=base.camera, sun=base.sun, sea=seas()[name], islands=base.islands)


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4", "default"])
@pytest.mark.parametrize("t", [0.0, 2.9, 4000.5])
def test_the_sea_normal_at_a_point_agrees_with_numpys(name, t):
    sea = seas()[name]
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-300, 300, 3000), rng.uniform(2, 3000, 3000)
    want = sea.normal(x, y, t)
    waves, coef, count = crests_numba.sea_constants(sea, t)
    got = np.array([crests_numba.sea_normal(a, b, waves, coef, count) for a, b in zip(x, y)])
    np.testing.assert_allclose(got, want, rtol=0, atol=NORMAL64_ATOL)


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4"])
@pytest.mark.parametrize("t", [0.0, 7.25])
def test_crest_distances_agree_with_numpys(name, t):
    sea = seas()[name]
    train = crests.largest_train(sea)
    rng = np.random.default_rng(11)
    n = 8000
    q = np.column_stack([rng.uniform(-200, 200, n), rng.uniform(5, 2000, n), np.zeros(n)])
    q[:, 2] = -2.0 + sea.elevation(q[:, 0], q[:, 1], t)
    r = rng.normal(size=(n, 3))
    r[: n // 2, 2] = -np.abs(r[: n // 2, 2]) * 0.3        # many rays heading into the water
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    cand, (qc, rc) = pierce.gather(crests.crest_candidates(train, t, q, r), q, r)
    cyl = crests.crest_cylinder(train, t, qc, rc)
    want = np.full(n, np.inf)
    want[cand] = pierce.first_entry(*pierce.quadratic_interval(*crests.cylinder_coefficients(cyl, qc, rc))[::2])
    got = reflect_numba.crest_hits(train, t, q, r)
    assert np.isfinite(want).sum() > 200 and len(cand) < n       # hits, and rays the bounding test drops
    hit = np.isfinite(want)
    np.testing.assert_array_equal(np.isfinite(got), hit)
    err = np.abs(got[hit] - want[hit]) / want[hit]
    assert np.count_nonzero(err > CREST_DISTANCE_RTOL) <= CREST_GRAZING_SHARE * err.size


def frame_bits(frame):
    out = {}
    for f in fields(Frame):
        v = getattr(frame, f.name)
        out[f.name] = v.tobytes() if isinstance(v, np.ndarray) else v
    return out


def traced(scene, t, mode, sea_bounces):
    frame = trace_direct(scene, t)
    return trace_reflections(scene, frame, mode, sea_bounces)


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4", "default", "still"])
@pytest.mark.parametrize("mode", [0, 1, 2])
def test_reflected_frames_agree_with_numpys_and_not_with_the_threads(name, mode):
    scene = scene_with(name)
    for t in (0.0, 3.1):
        for sea_bounces in (True, False):
            with kernels.use_compiled(False):
                ref = traced(scene, t, mode, sea_bounces)
            runs = []
            for threads in (1, 2, 3):
                with kernels.use_threads(threads):
                    runs.append(traced(scene, t, mode, sea_bounces))
            assert all(frame_bits(got) == frame_bits(runs[0]) for got in runs[1:])
            got = runs[0]
            assert_geometry_agrees(ref, got, f"{name} t={t} mode {mode}")
            with kernels.use_compiled(False):
                codes_ref = encode(scene, ref, seed=2)
            assert_codes_agree(scene, ref, got, codes_ref, encode(scene, got, seed=2), 2, f"{name} t={t}")
            if mode == 2 and name != "still":
                assert (ref.bounces == 2).sum() > 20       # the second bounce is exercised
            if mode >= 1:
                assert (ref.final_surface[ref.surface == SEA] > 0).any()   # and the islands' hits


def test_the_strip_twin_agrees_with_the_reference_on_a_strip():
    scene = scene_with("order 4", (150, 120))
    frame = trace_direct(scene, 1.0).finish_direct(True)
    frame.reflections = 2
    a = frame.rows(30, 95)
    ref = Frame(**{f.name: (v.copy() if isinstance(v := getattr(frame, f.name), np.ndarray) else v)
                   for f in fields(Frame)})
    with kernels.use_compiled(False):
        reflect.trace_sea_rays.reference(scene, ref.rows(30, 95), 2)
    b = reflect.trace_sea_rays.compiled()(scene, a, 2)
    assert b is a
    assert_geometry_agrees(ref, frame)
    # the rows outside the strip are untouched
    for f in ("ray", "final_surface", "bounces"):
        assert getattr(frame, f)[:30].tobytes() == getattr(ref, f)[:30].tobytes()
        assert getattr(frame, f)[95:].tobytes() == getattr(ref, f)[95:].tobytes()


def test_the_phase_mod_two_pi_is_within_a_rounding_of_numpys():
    # x − ⌊x/2π⌋·2π, and Python's % where that falls outside [0, 2π): np.mod's value to a rounding of x
    rng = np.random.default_rng(2)
    two_pi = 2.0 * np.pi
    k = np.arange(-50000, 50000) * two_pi
    x = np.concatenate([rng.uniform(-1e3, 1e3, 200000), rng.uniform(-1e9, 1e9, 50000), k,
                        np.nextafter(k, np.inf), np.nextafter(k, -np.inf),
                        rng.integers(-10**6, 10**6, 100000) * two_pi + rng.normal(0, 1e-12, 100000),
                        [0.0, -0.0, 5e-324, -5e-324, 1e300, -1e300]])
    got = np.array([crests_numba.mod_two_pi(v) for v in x])
    want = np.mod(x, two_pi)
    assert ((got >= 0) & (got <= two_pi)).all()         # 2π itself where a tiny negative x rounds, as np.mod
    # the same angle: a result near 2π may be the other end of the turn
    diff = np.abs(got - want)
    diff = np.minimum(diff, two_pi - diff)
    assert (diff <= 2 * np.spacing(np.maximum(np.abs(x), two_pi))).all()
    assert np.isnan(crests_numba.mod_two_pi(np.nan)) and np.isnan(crests_numba.mod_two_pi(np.inf))


def test_the_island_normals_agree_with_numpys():
    """reflect_numba.island_normals (the loop's _island_normal) against pierce.island_normal, float64:
    every island of the default scene and one whose cosines have phases, on all three parts."""
    from dataclasses import replace

    from sunset.constants import PART_BEACH, PART_CLIFF, PART_HILL

    islands = list(Scene.default().islands)
    islands.append(replace(islands[0], cosines=tuple(replace(c, phase=0.7 * (i + 1))
                                                      for i, c in enumerate(islands[0].cosines))))
    rng = np.random.default_rng(5)
    n = 4000
    for k, isl in enumerate(islands, start=1):
        x = isl.x + rng.uniform(-400, 400, n)
        y = isl.y + rng.uniform(-400, 400, n)
        part = rng.choice(np.array([PART_BEACH, PART_CLIFF, PART_HILL], np.int8), n)
        want = pierce.island_normal(isl, x, y, part)
        got = reflect_numba.island_normals(islands, x, y, part, np.full(n, k))
        np.testing.assert_allclose(got, want, rtol=0, atol=NORMAL64_ATOL)
        # the parts differ (each branch is exercised): the beach's normal is not the cliff's
        at = np.array([PART_BEACH, PART_CLIFF, PART_HILL], np.int8)
        normals = [pierce.island_normal(isl, x[:1], y[:1], at[i:i + 1]) for i in range(3)]
        assert not np.array_equal(normals[0], normals[1]) and not np.array_equal(normals[1], normals[2])
    # the phases matter
    assert not np.array_equal(pierce.island_normal(islands[0], x, y, np.full(n, PART_CLIFF, np.int8)),
                              pierce.island_normal(islands[-1], x, y, np.full(n, PART_CLIFF, np.int8)))



def block_keep(train, t, q, r):
    """ψ and the crest test of crests_numba.crest_block, block by block of 512 rays (a ragged last one)."""
    crest, amps = crests_numba.crest_constants(train, t)
    n = len(q)
    psi, keep = np.empty(n), np.empty(n, bool)
    cols = [np.ascontiguousarray(a) for a in (*q.T, *r.T)]
    for a in range(0, n, 512):
        m = min(n, a + 512) - a
        p, k = np.empty(512), np.empty(512, bool)
        crests_numba.crest_block(m, *(c[a:a + m] for c in cols), crest, amps, p, k, np.empty((5, 512)))
        psi[a:a + m], keep[a:a + m] = p[:m], k[:m]
    return psi, keep


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4", "default"])
def test_the_block_crest_test_is_numpys(name):
    """crest_block: ψ is np.mod's to a rounding (where the quotient by 1/2π is wrong too), the test the reference's
    but at the turn of the phase."""
    sea = seas()[name]
    train = crests.largest_train(sea)
    rng = np.random.default_rng(8)
    n = 20000
    q = np.column_stack([rng.uniform(-300, 300, n), rng.uniform(5, 3000, n), np.zeros(n)])
    q[:, 2] = -2.0 + sea.elevation(q[:, 0], q[:, 1], 3.3)
    r = rng.normal(size=(n, 3))
    r[: n // 2, 2] = np.abs(r[: n // 2, 2]) * 0.1
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    # origins whose phase is (next to) a multiple of 2π: the quotient rounds across an integer
    l, m = train.wave_vector
    k = np.arange(-2000, 2000) * 2.0 * np.pi
    base = train.omega * 3.3 - train.phase
    q[:4000, 0] = 0.0
    q[:4000, 1] = (k + base) / m
    q[4000:8000, 1] = np.nextafter(q[:4000, 1], np.inf)
    q[4000:8000, 0] = 0.0
    psi, keep = block_keep(train, 3.3, q, r)
    theta = l * q[:, 0] + m * q[:, 1] - train.omega * 3.3 + train.phase
    diff = np.abs(psi - np.mod(theta, 2.0 * np.pi))
    assert (np.minimum(diff, 2.0 * np.pi - diff) <= 2 * np.spacing(np.maximum(np.abs(theta), 2.0 * np.pi))).all()
    want = crests.crest_candidates(train, 3.3, q, r)
    # the test is the reference's wherever ψ is not within a rounding of the turn 0 ≡ 2π; at the turn (the
    # origins built on a crest's top above) the two paths may put the crest ahead a wavelength apart
    psi_ref = np.mod(theta, 2.0 * np.pi)
    off_turn = np.minimum(psi_ref, 2.0 * np.pi - psi_ref) > 1e-9
    assert off_turn.sum() > 0.55 * n and not off_turn[:4000].any()
    np.testing.assert_array_equal(keep[off_turn], want[off_turn])
    assert 0 < want.sum() < n
    # and crest_phase, ray by ray, agrees
    crest, amps = crests_numba.crest_constants(train, 3.3)
    one = [crests_numba.crest_phase(*q[i], *r[i], crest, amps) for i in range(0, n, 37)]
    # (the same arithmetic as the block's: the same numbers, at the turn too)
    assert [b for b, _ in one] == list(keep[::37]) and same_bits(np.array([p for _, p in one]), psi[::37])


def test_the_island_test_is_numpys():
    """The compiled island bounding test (reflect_numba._is_candidate over the table) is pierce.island_candidates."""
    import numba

    @numba.njit
    def flags(q, r, table):
        out = np.empty((table.shape[0], q.shape[0]), np.bool_)
        for i in range(table.shape[0]):
            for j in range(q.shape[0]):
                h2 = r[j, 0] * r[j, 0] + r[j, 1] * r[j, 1]
                out[i, j] = reflect_numba._is_candidate(q[j, 0], q[j, 1], q[j, 2], r[j, 0], r[j, 1], r[j, 2], h2,
                                                        table[i])
        return out

    rng = np.random.default_rng(12)
    isl = Scene.default().islands
    n = 30000
    q = np.column_stack([rng.uniform(-600, 800, n), rng.uniform(0, 2500, n), rng.uniform(-4, 0, n)])
    aim = np.array([[i.x, i.y, 20.0] for i in isl])[rng.integers(0, len(isl), n)] + rng.normal(0, 150, (n, 3))
    r = (aim - q) / np.linalg.norm(aim - q, axis=1, keepdims=True)
    got = flags(q, r, reflect_numba.island_table(isl, 2.0))
    for i, island in enumerate(isl):
        want = pierce.island_candidates(island, 2.0, q, r)
        np.testing.assert_array_equal(got[i], want)
        assert 0 < want.sum() < n


@pytest.mark.parametrize("name", ["order 1", "order 4", "default"])
def test_the_sea_normals_of_a_block_are_the_point_by_point_ones(name):
    # the block form gathers the crest hits of a block of rays: the same bits as the scalar form
    sea = seas()[name]
    rng = np.random.default_rng(5)
    n = 700
    x, y = rng.uniform(-300, 300, n), rng.uniform(2, 3000, n)
    waves, coef, count = crests_numba.sea_constants(sea, 3.5)
    want = np.array([crests_numba.sea_normal(a, b, waves, coef, count) for a, b in zip(x, y)])
    out = np.full((3, n + 5), -7.0)
    crests_numba.sea_normals_into(n, x, y, waves, coef, count, np.empty((6, n + 5)), out[0], out[1], out[2])
    np.testing.assert_array_equal(out[:, :n].T, want)
    assert (out[:, n:] == -7.0).all()
    np.testing.assert_allclose(want, sea.normal(x, y, 3.5), rtol=0, atol=NORMAL64_ATOL)
