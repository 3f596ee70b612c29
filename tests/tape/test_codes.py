"""The 8-bit code map and the coding of a frame (sunset/tape/codes.py).

Frames here are built by hand (only the final fields that ``encode`` reads),
so every expected code follows from the geometry put in, not from the
renderer.
"""

import math

import numpy as np
import pytest

from sunset.model.camera import Camera
from sunset.pipeline.frame import encode
from sunset.tape.codes import CODE_MAP, CodeMap, CodeRange, dither, elevation_index, island_code_rho, island_offsets, rho, rho_hat, sky_code_z, sky_index, sun_plane_angle, track_code_elevations, track_elevation_max
from sunset.constants import HALO_FACTOR, N_CODES, PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from sunset.errors import SunsetError
from sunset.vector.frame import Frame
from sunset.model.scene import Scene
from sunset.model.sun import Sun

SUNS = [Sun(), Sun(azimuth=2.0, tilt=50.0, radius=0.75), Sun(azimuth=-35.0, tilt=20.0, radius=2.0),
        Sun(azimuth=60.0, tilt=90.0, radius=0.3)]


def random_unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def make_frame(shape, surface, part=None, normal=None, ray=None, bounces=None):
    """A Frame with only the final fields filled (the rest NaN/placeholder)."""
    h, w = shape
    nan3 = np.full((h, w, 3), np.nan, np.float32)
    surface = np.broadcast_to(np.asarray(surface, np.int8), shape).copy()
    part = np.zeros(shape, np.int8) if part is None else np.broadcast_to(np.asarray(part, np.int8), shape).copy()
    normal = nan3 if normal is None else np.broadcast_to(np.asarray(normal, np.float32), (h, w, 3)).copy()
    ray = np.broadcast_to(np.asarray(ray if ray is not None else [0, 1, 0], np.float32), (h, w, 3)).copy()
    bounces = np.zeros(shape, np.uint8) if bounces is None else np.broadcast_to(
        np.asarray(bounces, np.uint8), shape).copy()
    return Frame(t=0.0, reflections=2, direction=ray.copy(), surface=surface, part=part,
                 distance=np.zeros(shape, np.float32), point=nan3, normal=normal, bounces=bounces, ray=ray,
                 final_surface=surface.copy(), final_part=part.copy(), final_normal=normal)


def scene_of(shape, sun=None):
    h, w = shape
    return Scene(camera=Camera(width=w, height=h), sun=sun or Sun(azimuth=2.0, tilt=50.0, radius=0.75))


# --------------------------------------------------------------------------- the map
def test_code_map_covers_every_code_exactly_once():
    hits = np.zeros(N_CODES, int)
    for r in CODE_MAP.ranges:
        for c in range(r.start, r.stop):
            hits[c] += 1
    assert np.all(hits == 1)
    assert sum(r.size for r in CODE_MAP.ranges) == 256
    assert {r.name for r in CODE_MAP.ranges} == {"hill", "cliff", "beach", "sky", "track", "halo"}


def test_group_and_masks_agree_with_the_ranges():
    codes = np.arange(256, dtype=np.uint8)
    groups = CODE_MAP.group(codes)
    for i, r in enumerate(CODE_MAP.ranges):
        assert np.all(groups[r.start:r.stop] == i)
        assert np.array_equal(r.contains(codes), (codes >= r.start) & (codes < r.stop))
        assert np.array_equal(r.codes(), codes[r.start:r.stop])
    sky_like = CODE_MAP.sky.contains(codes) | CODE_MAP.track.contains(codes) | CODE_MAP.halo.contains(codes)
    assert np.array_equal(CODE_MAP.reaches_sky(codes), sky_like)
    assert CODE_MAP.group(np.zeros((2, 3, 1), np.uint8)).shape == (2, 3, 1)
    assert [row[0] for row in CODE_MAP.table()] == [r.name for r in CODE_MAP.ranges]


def test_overlapping_or_short_maps_are_refused():
    r = [CodeRange("a", 0, 100, ""), CodeRange("b", 100, 100, ""), CodeRange("c", 200, 20, ""),
         CodeRange("d", 220, 10, ""), CodeRange("e", 230, 10, "")]
    with pytest.raises(ValueError):
        CodeMap(*r, CodeRange("f", 239, 17, ""))          # overlaps e
    with pytest.raises(ValueError):
        CodeMap(*r, CodeRange("f", 240, 10, ""))          # stops short of 255


# --------------------------------------------------------------------------- ρ(N)
def normals_and_suns(sun, seed, count=20000):
    """Random unit normals, random hours θ in [−π/2, π/2] and the sun's P(θ) for each."""
    rng = np.random.default_rng(seed)
    n = random_unit(rng, count)
    theta = rng.uniform(-math.pi / 2, math.pi / 2, size=count)
    p = np.cos(theta)[:, None] * sun.U + np.sin(theta)[:, None] * sun.V
    return n, theta, p


@pytest.mark.parametrize("sun", SUNS)
def test_rho_decides_light_on_the_half_the_paper_considered(sun):
    n, theta, p = normals_and_suns(sun, seed=1)
    lit = np.sum(n * p, axis=1)
    keep = (n @ sun.V > 1e-6) & (np.abs(lit) > 1e-9)
    assert np.array_equal((lit > 0)[keep], (rho(n, sun) < np.sin(theta))[keep])


@pytest.mark.parametrize("sun", SUNS)
def test_printed_rho_fails_where_n_dot_v_is_negative_and_the_turned_rule_holds(sun):
    n, theta, p = normals_and_suns(sun, seed=2)
    lit = np.sum(n * p, axis=1) > 0
    neg = n @ sun.V < -1e-6
    printed = rho(n, sun) < np.sin(theta)
    assert np.mean(printed[neg] != lit[neg]) > 0.2          # the printed rule is wrong on this half
    turned = np.sin(theta) < -rho(n, sun)
    clear = neg & (np.abs(np.sum(n * p, axis=1)) > 1e-9)
    assert np.array_equal(turned[clear], lit[clear])


@pytest.mark.parametrize("sun", SUNS)
def test_rho_hat_shadow_band(sun):
    """Shadow exactly when sin θ <= ρ̂ <= 2 + sin θ, for every normal and θ in [−π/2, π/2]."""
    n, theta, p = normals_and_suns(sun, seed=3)
    dot = np.sum(n * p, axis=1)
    rh = rho_hat(n, sun)
    assert np.all((rh >= -1) & (rh < 3))
    clear = np.abs(dot) > 1e-9
    shadow = (np.sin(theta) <= rh) & (rh <= 2 + np.sin(theta))
    assert np.array_equal(shadow[clear], (dot <= 0)[clear])


@pytest.mark.parametrize("sun", SUNS)
def test_rho_hat_is_monotone_in_the_sun_plane_angle_and_inverts(sun):
    rng = np.random.default_rng(4)
    n = random_unit(rng, 5000)
    psi = np.mod(np.arctan2(n @ sun.V, n @ sun.U), 2 * math.pi)
    rh = rho_hat(n, sun)
    order = np.argsort(psi)
    assert np.all(np.diff(rh[order]) >= -1e-12)
    np.testing.assert_allclose(sun_plane_angle(rh), psi, atol=1e-6)
    # ρ̂ is −cos ψ on the first half turn and 2 + cos ψ on the second
    expect = np.where(psi <= math.pi, -np.cos(psi), 2 + np.cos(psi))
    np.testing.assert_allclose(rh, expect, atol=1e-12)


@pytest.mark.parametrize("shape", [(3,), (6, 3), (2, 3, 3), (2, 3, 1, 3)])
def test_rho_shapes(shape):
    rng = np.random.default_rng(5)
    n = rng.normal(size=shape)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    sun = SUNS[1]
    assert np.shape(rho(n, sun)) == shape[:-1]
    assert np.shape(rho_hat(n, sun)) == shape[:-1]


def test_normals_along_w_are_never_lit():
    sun = SUNS[1]
    for w in (sun.W, -sun.W):
        rh = rho_hat(w, sun)
        psi = float(sun_plane_angle(rh))
        assert math.isfinite(psi)
        assert float(rho(w, sun)) == 1.0


# --------------------------------------------------------------------------- index functions
def test_dither_is_unbiased_and_splits_by_the_fraction():
    rng = np.random.default_rng(6)
    u = rng.random(200000)
    size = 40
    # ρ̂ chosen so that B(ρ̂ + 1) = 13.3: 30 % of the pixels go to offset 14
    rh = np.full(u.shape, 13.3 / (size / 4) - 1)
    off = island_offsets(rh, size, u)
    assert set(np.unique(off)) == {13, 14}
    assert abs(np.mean(off == 14) - 0.3) < 0.005
    assert abs(np.mean(off) - 13.3) < 0.005


def splitmix64(state: int, count: int) -> list[int]:
    """SplitMix64 (Steele, Lea and Flood 2014) in Python's integers: the first ``count`` outputs from ``state``."""
    mask, out = (1 << 64) - 1, []
    for _ in range(count):
        state = (state + 0x9E3779B97F4A7C15) & mask
        z = state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
        out.append(z ^ (z >> 31))
    return out


def test_the_dither_is_splitmix64():
    # SplitMix64's first output from state 0 is 0xE220A8397B1DCDAF (Vigna's splitmix64.c)
    assert splitmix64(0, 1) == [0xE220A8397B1DCDAF]
    for seed in (0, 5, 2**32 - 1):
        ref = [z >> 11 for z in splitmix64(seed, 2 * 60)]         # u, v of pixel 0, then of pixel 1, ...
        u, v = dither(seed, 0, (6, 10), 0), dither(seed, 0, (6, 10), 1)
        assert (u.ravel() * 2.0**53).astype(np.int64).tolist() == ref[0::2]
        assert (v.ravel() * 2.0**53).astype(np.int64).tolist() == ref[1::2]
        assert u.shape == (6, 10) and u.dtype == np.float64


def test_a_strips_dither_is_its_piece_of_the_frames():
    H, W = 23, 31
    for which in (0, 1):
        frame = dither(77, 0, (H, W), which)
        np.testing.assert_array_equal(dither(77, 5 * W, (4, W), which), frame[5:9])
        np.testing.assert_array_equal(dither(77, 11 * W + 3, (40,), which), frame.reshape(-1)[11 * W + 3:][:40])
    assert not np.array_equal(dither(77, 0, (H, W), 0), dither(78, 0, (H, W), 0))


def test_the_dither_is_uniform_and_uncorrelated():
    u = dither(3, 0, (1000, 1000), 0)
    v = dither(3, 0, (1000, 1000), 1)
    for x in (u, v):
        values = np.sort(x.ravel())
        ks = np.max(np.abs(values - (np.arange(values.size) + 0.5) / values.size))
        assert 0.0 <= values[0] and values[-1] < 1.0 and ks < 0.002    # 1.36/√n = 0.00136 at the 5 % level
    # neither u and v of a pixel nor neighbours along a row or a column are correlated
    for a, b in ((u, v), (u[:, 1:], u[:, :-1]), (u[1:], u[:-1])):
        assert abs(np.corrcoef(a.ravel(), b.ravel())[0, 1]) < 0.005


def test_island_offsets_wrap_around_the_turn():
    size = 40
    assert island_offsets(np.array([2.999999]), size, np.array([0.99])).tolist() == [0]
    assert island_offsets(np.array([-1.0]), size, np.array([0.0])).tolist() == [0]
    np.testing.assert_allclose(island_code_rho(size)[[0, 10, 20, 30]], [-1, 0, 1, 2])


def test_sky_index_follows_the_square_root_of_z():
    z = np.linspace(0, 1, 101)
    idx = sky_index(z, 56, np.zeros_like(z))
    np.testing.assert_array_equal(idx, np.minimum(np.floor(56 * np.sqrt(z)), 55))
    assert sky_index(np.array([-0.3]), 56, np.array([0.999])).tolist() == [0]
    zc = sky_code_z(56)
    assert np.all(np.diff(zc) > 0) and zc[0] > 0 and zc[-1] < 1


def test_elevation_index_and_its_centres():
    sun = SUNS[1]
    e_max = track_elevation_max(sun)
    assert math.isclose(e_max, math.radians(50.0) + HALO_FACTOR * math.radians(0.75))
    centres = track_code_elevations(64, sun)
    # a ray at each interior centre, with the middle dither value u = 1/2, goes to that index
    idx = elevation_index(np.sin(centres[1:-1]), 64, e_max, np.full(62, 0.5))
    np.testing.assert_array_equal(idx, np.arange(1, 63))


# --------------------------------------------------------------------------- encoding frames
def test_islands_code_by_part_and_rho_hat():
    sun = SUNS[1]
    rng = np.random.default_rng(7)
    # normals built from a chosen sun-plane angle ψ and an out-of-plane part
    psi = rng.uniform(0, 2 * math.pi, size=(30, 40))
    w = rng.uniform(-0.6, 0.6, size=psi.shape)
    r = np.sqrt(1 - w * w)
    n = (r * np.cos(psi))[..., None] * sun.U + (r * np.sin(psi))[..., None] * sun.V + w[..., None] * sun.W
    part = rng.choice([PART_BEACH, PART_CLIFF, PART_HILL], size=psi.shape)
    frame = make_frame(psi.shape, 1, part=part, normal=n)
    codes = encode(scene_of(psi.shape, sun), frame, seed=3)
    expect_rh = np.where(psi <= math.pi, -np.cos(psi), 2 + np.cos(psi))
    for p in (PART_BEACH, PART_CLIFF, PART_HILL):
        rg = CODE_MAP.for_part(p)
        sel = part == p
        assert np.all(rg.contains(codes[sel]))
        off = codes[sel].astype(int) - rg.start
        y = (rg.size / 4) * (expect_rh[sel] + 1)
        # the offset is ⌊y + u⌋ modulo the range: y or the next integer up
        d = np.mod(off - np.floor(y), rg.size)
        assert np.all((d == 0) | (d == 1))


def test_sky_track_and_halo():
    sun = SUNS[1]
    delta = sun.delta
    h, w = 8, 60
    # rays in the sun's plane at 10° elevation, then turned out of it by 0, 2δ and 5δ
    base = math.asin(math.sin(math.radians(10)) / math.sin(math.radians(50)))
    p = math.cos(base) * sun.U + math.sin(base) * sun.V
    side = np.cross(sun.W, p)
    rays = []
    for k in range(w):
        off = [0.0, 2.0 * delta, 5.0 * delta][k % 3]
        rays.append(math.cos(off) * p + math.sin(off) * sun.W)
    rays = np.broadcast_to(np.array(rays), (h, w, 3))
    assert np.allclose(np.cross(side, sun.W) @ sun.W, 0)
    frame = make_frame((h, w), SKY, ray=rays, bounces=1)
    codes = encode(scene_of((h, w), sun), frame, seed=0)
    col = np.arange(w) % 3
    assert np.all(CODE_MAP.track.contains(codes[:, col == 0]))
    assert np.all(CODE_MAP.halo.contains(codes[:, col == 1]))
    assert np.all(CODE_MAP.sky.contains(codes[:, col == 2]))
    # the same rays seen directly (no bounce) are plain sky
    direct = encode(scene_of((h, w), sun), make_frame((h, w), SKY, ray=rays, bounces=0), seed=0)
    assert np.all(CODE_MAP.sky.contains(direct))


def test_track_codes_rise_with_the_ray_and_sky_codes_with_z():
    sun = SUNS[1]
    n = 400
    phi = np.linspace(0.0, math.radians(70), n)
    rays = np.cos(phi)[:, None] * sun.U + np.sin(phi)[:, None] * sun.V
    frame = make_frame((1, n), SKY, ray=rays[None], bounces=1)
    codes = encode(scene_of((1, n), sun), frame, seed=0)[0].astype(int)
    assert np.all(CODE_MAP.track.contains(codes))
    # dithered by at most one step, the index follows n·e/e_max
    e = np.arcsin(rays[:, 2])
    y = e * CODE_MAP.track.size / track_elevation_max(sun)
    d = codes - CODE_MAP.track.start - np.floor(y)
    assert np.all((d == 0) | (d == 1) | ((codes == CODE_MAP.track.stop - 1) & (d <= 0)))
    z = np.linspace(0, 1, n)
    sky_rays = np.stack([np.zeros(n), np.sqrt(1 - z * z), z], -1)
    sc = encode(scene_of((1, n), sun), make_frame((1, n), SKY, ray=sky_rays[None]), seed=0)[0].astype(int)
    dz = sc - CODE_MAP.sky.start - np.floor(np.sqrt(z) * CODE_MAP.sky.size)
    assert np.all((dz == 0) | (dz == 1) | ((sc == CODE_MAP.sky.stop - 1) & (dz <= 0)))


def test_seed_reset_and_determinism():
    sun = SUNS[1]
    rng = np.random.default_rng(8)
    shape = (24, 32)
    n = random_unit(rng, shape[0] * shape[1]).reshape(shape + (3,))
    n[..., 2] = np.abs(n[..., 2])
    surface = np.where(rng.random(shape) < 0.5, 1, SKY)
    rays = random_unit(rng, shape[0] * shape[1]).reshape(shape + (3,))
    rays[..., 2] = np.abs(rays[..., 2])
    frame = make_frame(shape, surface, part=np.where(surface == 1, PART_HILL, 0), normal=n, ray=rays,
                       bounces=rng.integers(0, 2, shape))
    scene = scene_of(shape, sun)
    a = encode(scene, frame, seed=11)
    b = encode(scene, frame, seed=11)
    c = encode(scene, frame, seed=12)
    assert a.dtype == np.uint8 and a.shape == shape
    assert a.tobytes() == b.tobytes()
    assert not np.array_equal(a, c)


def test_bad_frames_and_seeds():
    scene = scene_of((4, 5))
    good = make_frame((4, 5), SKY)
    with pytest.raises(SunsetError, match="seed"):
        encode(scene, good, seed=-1)
    with pytest.raises(SunsetError, match="seed"):
        encode(scene, good, seed=1.5)
    with pytest.raises(SunsetError, match="shape"):
        encode(scene_of((5, 4)), good)
    sea = make_frame((4, 5), SEA)
    with pytest.raises(SunsetError, match="final_surface"):
        encode(scene, sea)
    untraced = make_frame((4, 5), SKY)
    untraced.ray = None
    with pytest.raises(SunsetError, match="frame.ray"):
        encode(scene, untraced)
    bad_part = make_frame((4, 5), 1, part=0, normal=[0, 0, 1])
    with pytest.raises(SunsetError, match="final_part"):
        encode(scene, bad_part)
