"""The compiled reflected rays (sunset.vector.crests_numba, reflect_numba) against the NumPy reference, bit for bit."""

from dataclasses import fields

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import SEA
from sunset.model.scene import Scene
from sunset.vector import crests, crests_numba, direct, pierce, reflect, reflect_numba
from sunset.vector.frame import Frame

from .test_slopes_numba import same_bits, seas


def scene_with(name, size=(120, 90)):
    base = Scene.default().with_size(*size)
    return Scene(camera=base.camera, sun=base.sun, sea=seas()[name], islands=base.islands)


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4", "default"])
@pytest.mark.parametrize("t", [0.0, 2.9, 4000.5])
def test_the_sea_normal_at_a_point_is_numpys(name, t):
    sea = seas()[name]
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-300, 300, 3000), rng.uniform(2, 3000, 3000)
    want = sea.normal(x, y, t)
    waves, coef, count = crests_numba.sea_constants(sea, t)
    got = np.array([crests_numba.sea_normal(a, b, waves, coef, count) for a, b in zip(x, y)])
    assert same_bits(got, want)


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4"])
@pytest.mark.parametrize("t", [0.0, 7.25])
def test_crest_distances_are_numpys(name, t):
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
    assert same_bits(got, want)


def frame_bits(frame):
    out = {}
    for f in fields(Frame):
        v = getattr(frame, f.name)
        out[f.name] = v.tobytes() if isinstance(v, np.ndarray) else v
    return out


def traced(scene, t, mode, sea_bounces):
    frame = direct.trace_direct(scene, t)
    return reflect.trace_reflections(scene, frame, mode, sea_bounces)


@pytest.mark.parametrize("name", ["order 1", "order 2", "order 4", "default", "still"])
@pytest.mark.parametrize("mode", [0, 1, 2])
@pytest.mark.parametrize("threads", [1, 2, 3])
def test_reflected_frames_are_numpys(name, mode, threads):
    scene = scene_with(name)
    for t in (0.0, 3.1):
        for sea_bounces in (True, False):
            with kernels.use_threads(threads):
                with kernels.use_compiled(False):
                    ref = traced(scene, t, mode, sea_bounces)
                got = traced(scene, t, mode, sea_bounces)
            want, have = frame_bits(ref), frame_bits(got)
            assert [k for k in want if want[k] != have[k]] == [], (t, sea_bounces)
            if mode == 2 and name != "still":
                assert (ref.bounces == 2).sum() > 20       # the second bounce is exercised
            if mode >= 1:
                assert (ref.final_surface[ref.surface == SEA] > 0).any()   # and the islands' hits


def test_the_strip_twin_is_the_reference_on_a_strip():
    scene = scene_with("order 4", (150, 120))
    frame = direct.trace_direct(scene, 1.0).finish_direct(True)
    frame.reflections = 2
    a, b = frame.rows(30, 95), None
    ref = Frame(**{f.name: (v.copy() if isinstance(v := getattr(frame, f.name), np.ndarray) else v)
                   for f in fields(Frame)})
    with kernels.use_compiled(False):
        reflect.trace_sea_rays.reference(scene, ref.rows(30, 95), 2)
    b = reflect.trace_sea_rays.compiled()(scene, a, 2)
    assert b is a
    assert frame_bits(frame) == frame_bits(ref)
    # a changed bit would be seen
    frame.ray[40, 3, 0] = np.nextafter(frame.ray[40, 3, 0], np.float32(9))
    assert frame_bits(frame) != frame_bits(ref)


def test_the_phase_mod_two_pi_is_numpys():
    # one fused multiply-add where the quotient is right, fmod where it is not: np.mod's bits everywhere
    rng = np.random.default_rng(2)
    two_pi = 2.0 * np.pi
    k = np.arange(-50000, 50000) * two_pi
    x = np.concatenate([rng.uniform(-1e3, 1e3, 200000), rng.uniform(-1e9, 1e9, 50000), k,
                        np.nextafter(k, np.inf), np.nextafter(k, -np.inf),
                        rng.integers(-10**6, 10**6, 100000) * two_pi + rng.normal(0, 1e-12, 100000),
                        [0.0, -0.0, 5e-324, -5e-324, 1e300, -1e300, np.inf, -np.inf, np.nan]])
    got = np.array([crests_numba.mod_two_pi(v) for v in x])
    with np.errstate(invalid="ignore"):
        want = np.mod(x, two_pi)
    assert same_bits(got, want)
    # the fused path does differ from a plain multiply-and-subtract: the test could see a wrong rounding
    y = x[:200000]
    plain = y - np.floor(y / two_pi) * two_pi
    assert not same_bits(plain, want[:200000])


def test_the_island_normals_are_numpys():
    """reflect_numba.island_normals (the loop's _island_normal) is pierce.island_normal bit for bit:
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
        assert same_bits(got, want)
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
    """crest_block: ψ is np.mod's bit for bit (where the quotient by 1/2π is wrong too) and the test the reference's."""
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
    assert same_bits(psi, np.mod(theta, 2.0 * np.pi))
    want = crests.crest_candidates(train, 3.3, q, r)
    np.testing.assert_array_equal(keep, want)
    assert 0 < want.sum() < n
    # and crest_phase, ray by ray, agrees
    crest, amps = crests_numba.crest_constants(train, 3.3)
    one = [crests_numba.crest_phase(*q[i], *r[i], crest, amps) for i in range(0, n, 37)]
    assert [b for b, _ in one] == list(want[::37]) and same_bits(np.array([p for _, p in one]), psi[::37])


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
