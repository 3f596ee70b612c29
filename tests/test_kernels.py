"""The compiled kernels (the `*_numba` twins chosen by sunset/kernels.py) against the NumPy vector kernels they replace.

The NumPy kernels are the reference (and are themselves tested against the
paper's scalar loop and the brute-force caster elsewhere); here every
compiled kernel must give the same numbers, bit for bit, and whole frames
and their codes must come out identical on both paths.
"""

import numpy as np
import pytest

from sunset import kernels
from sunset.vector import heightfield_numba
from sunset.vector import reflect_numba
from sunset.vector import heightfield as hf
from sunset.vector import direct
from sunset.vector import island_samples
from sunset.vector import pierce
from sunset.vector import reflect
from sunset.vector import crests
from sunset.tape.codes import encode
from sunset.constants import SEA, SKY
from sunset.model.islands import Island, Paraboloid
from sunset.vector.render import render
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain

FIELDS = ("direction", "surface", "part", "distance", "point", "normal", "bounces", "ray", "final_surface",
          "final_part", "final_normal")


def test_numba_is_there_and_the_switch_works():
    assert kernels.AVAILABLE
    with kernels.use_compiled(False) as on:
        assert not on and not kernels.enabled()
        with kernels.use_compiled(True) as on2:
            assert on2 and kernels.enabled()
        assert not kernels.enabled()


def random_profiles(rng, dtype):
    C, N, K = rng.integers(1, 7), rng.integers(1, 60), rng.integers(1, 40)
    g = np.cumsum(rng.normal(0, 0.3, (C, N)), axis=1).astype(dtype)
    counts = rng.integers(0, N + 1, C)
    valid = np.arange(N)[None, :] < counts[:, None]
    g[~valid] = -np.inf  # scan_convert's padding
    zeta0, dz = rng.normal(), rng.uniform(0.01, 0.3)
    return g, counts, valid, K, zeta0, dz


@pytest.mark.parametrize("seed", range(40))
def test_scan_columns_is_scan_convert(seed):
    rng = np.random.default_rng(seed)
    dtype = (np.float32, np.float64)[seed % 2]
    g, counts, valid, K, zeta0, dz = random_profiles(rng, dtype)
    N = g.shape[1]
    # u shared by all rows, and u per row
    u1 = np.sort(rng.random(N))[::-1].copy()
    want = hf.scan_convert(u1, g, zeta0, dz, K)
    got = heightfield_numba.scan_columns(u1, g, counts, zeta0, dz, K)
    np.testing.assert_array_equal(got, want)
    u2 = np.sort(rng.random(g.shape), axis=1)[:, ::-1].copy()
    want = hf.scan_convert(u2, g, zeta0, dz, K)
    np.testing.assert_array_equal(heightfield_numba.scan_columns(u2, g, counts, zeta0, dz, K), want)
    # the compressed layout: only the valid samples, row after row
    np.testing.assert_array_equal(heightfield_numba.scan_columns(u2[valid], g[valid], counts, zeta0, dz, K), want)


@pytest.mark.parametrize("seed", range(10))
def test_scan_merge_is_the_depth_buffer(seed):
    rng = np.random.default_rng(100 + seed)
    g, counts, valid, K, zeta0, dz = random_profiles(rng, np.float32)
    u = np.sort(rng.random(g.shape), axis=1)[:, ::-1].copy()
    best_u = np.where(rng.random((len(counts), K)) < 0.5, rng.random((len(counts), K)), 0.0)
    best_s = np.full(best_u.shape, SKY, np.int8)
    want_u, want_s = best_u.copy(), best_s.copy()
    hit = hf.scan_convert(u, g, zeta0, dz, K)
    nearer = hit > want_u
    want_u[nearer] = hit[nearer]
    want_s[nearer] = 3
    heightfield_numba.scan_merge(u[valid], g[valid], counts, zeta0, dz, K, best_u, best_s, 3)
    np.testing.assert_array_equal(best_u, want_u)
    np.testing.assert_array_equal(best_s, want_s)


@pytest.mark.parametrize("order", [1, 2, 4])
@pytest.mark.parametrize("t", [0.0, 1.3, 977.25])
def test_sea_profile_is_the_numpy_one_bit_for_bit(order, t):
    # Stokes orders 1 (no Horner loop), 2 (the default) and 4 (the longest), random scan lines
    rng = np.random.default_rng(order)
    sea = Sea([WaveTrain(0.5, 40.0, 260.0, 0.3, stokes_order=order), WaveTrain(0.12, 10.0, 235.0, 1.0),
               WaveTrain(0.0, 7.0, 10.0, 0.0)])
    s = rng.uniform(-0.4, 0.4, 7)
    u = np.sort(rng.uniform(1e-4, 0.5, 300))[::-1]
    want = hf.sea_profile.reference(sea, s, u, 2.0, t)
    got = hf.sea_profile.compiled()(sea, s, u, 2.0, t)
    assert got.dtype == want.dtype == np.float32 and got.shape == want.shape == (7, 300)
    np.testing.assert_array_equal(got.view(np.uint32), want.view(np.uint32))
    assert hf.sea_profile.compiled()(sea, s, u[:0], 2.0, t).shape == (7, 0)


def test_interval_expansion_is_the_numpy_one():
    scene = Scene.default().with_size(150, 120)
    cam = scene.camera
    d = scene.sea.max_elevation
    samp = hf.sampling(cam, d)
    s = cam.s_centres()
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    for isl in scene.islands:
        m0 = island_samples.probe_refinement(isl, s, samp, d)
        args = (isl, s, samp, d, cam.eye_height, m0, zeta0, dz, cam.height, cam.sigma, 4 * samp.n)
        with kernels.use_compiled(False):
            u_np, n_np = island_samples._island_samples_flat(*args)
        with kernels.use_compiled(True):
            u_c, n_c = island_samples._island_samples_flat(*args)
        np.testing.assert_array_equal(u_c, u_np)
        np.testing.assert_array_equal(n_c, n_np)


def rays(rng, n):
    q = np.column_stack([rng.uniform(-400, 600, n), rng.uniform(5, 2500, n), rng.uniform(-3, 1, n)])
    r = rng.normal(size=(n, 3))
    r[: n // 2, 2] = np.abs(r[: n // 2, 2]) * 0.2  # many low, upward rays, as reflections are
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    return q, r


def test_island_piercing_is_the_numpy_one():
    rng = np.random.default_rng(5)
    scene = Scene.default()
    q, r = rays(rng, 20000)
    # aim a share of the rays at the islands, some from inside the beach
    for k, isl in enumerate(scene.islands):
        sl = slice(3000 * k, 3000 * k + 2000)
        target = np.column_stack([isl.x + rng.normal(0, 60, 2000), isl.y + rng.normal(0, 60, 2000),
                                  rng.uniform(-2, 60, 2000)])
        d = target - q[sl]
        r[sl] = d / np.linalg.norm(d, axis=1, keepdims=True)
    t_np, w_np, p_np = pierce.pierce_islands(scene.islands, 2.0, q, r)
    t_c, w_c, p_c = reflect_numba.pierce_islands(scene.islands, 2.0, q, r)
    assert (w_np > 0).sum() > 1000  # the test sees hits of every part
    assert set(np.unique(p_np[w_np > 0])) == {1, 2, 3}
    np.testing.assert_array_equal(t_c, t_np)
    np.testing.assert_array_equal(w_c, w_np)
    np.testing.assert_array_equal(p_c, p_np)


@pytest.mark.parametrize("order", [1, 2, 4])
def test_crest_hits_are_the_numpy_ones(order):
    rng = np.random.default_rng(order)
    train = WaveTrain(0.5, 40.0, direction=rng.uniform(0, 360), phase=rng.uniform(0, 6), stokes_order=order)
    q, r = rays(rng, 5000)
    q[:, 2] = -2.0 + Sea((train,)).elevation(q[:, 0], q[:, 1], 1.3)
    cyl = crests.crest_cylinder(train, 1.3, q, r)
    t_in, _, meets = pierce.quadratic_interval(*crests.cylinder_coefficients(cyl, q, r))
    want = pierce.first_entry(t_in, meets)
    assert np.isfinite(want).sum() > 100
    np.testing.assert_array_equal(reflect_numba.crest_hits(train, 1.3, q, r), want)


def frames_equal(a, b):
    for name in FIELDS:
        x, y = getattr(a, name), getattr(b, name)
        np.testing.assert_array_equal(x, y, err_msg=name)


def small_scenes():
    default = Scene.default().with_size(96, 80)
    still = Scene(camera=default.camera, sun=default.sun, sea=Sea(()), islands=default.islands)
    bare = Scene(camera=default.camera, sun=default.sun, sea=default.sea, islands=())
    lone = Island(x=10.0, y=300.0, cliff=Paraboloid(40.0, 0.01, 0.0, 0.01), beach=Paraboloid(3.0, 1e-4, 0.0, 1e-4),
                  cliff_top=20.0)
    near = Scene(camera=default.camera, sun=default.sun, sea=default.sea, islands=(lone,))
    return {"default": default, "still": still, "bare": bare, "near": near}


@pytest.mark.parametrize("name", ["default", "still", "bare", "near"])
@pytest.mark.parametrize("mode", [0, 1, 2])
def test_frames_and_codes_are_the_same_on_both_paths(name, mode):
    scene = small_scenes()[name]
    for t in (0.0, 1.7):
        with kernels.use_compiled(False):
            ref = render(scene, t, mode)
            ref_codes = encode(scene, ref, seed=4)
        with kernels.use_compiled(True):
            got = render(scene, t, mode)
            got_codes = encode(scene, got, seed=4)
        frames_equal(got, ref)
        np.testing.assert_array_equal(got_codes, ref_codes)
        assert (ref.surface == SEA).any()


def test_a_larger_frame_is_the_same_on_both_paths():
    # more scan lines than one chunk, and islands of many samples per scan line
    scene = Scene.default().with_size(300, 260)
    with kernels.use_compiled(False):
        ref = render(scene, 0.4, 2)
    with kernels.use_compiled(True):
        got = render(scene, 0.4, 2)
    frames_equal(got, ref)


def test_write_back_into_a_non_contiguous_frame():
    scene = Scene.default().with_size(40, 30)
    with kernels.use_compiled(True):
        frame = direct.trace_direct(scene, 0.0)
        frame.finish_direct()
        frame.ray = np.asfortranarray(frame.ray)  # reshape(-1) of this would copy
        reflect.trace_reflections(scene, frame, 1)
    with kernels.use_compiled(False):
        ref = render(scene, 0.0, 1)
    frames_equal(frame, ref)


def test_codes_of_random_final_fields_are_the_same_on_both_paths():
    # hand-made final fields: every kind of pixel, normals along the sun's axis W, rays below the horizon
    from sunset.vector.frame import Frame

    rng = np.random.default_rng(12)
    scene = Scene.default().with_size(64, 48)
    sun = scene.sun
    H, W = 48, 64
    n = rng.normal(size=(H, W, 3))
    n[::7, ::5] = sun.W  # ρ undefined: N·U = N·V = 0
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    ray = rng.normal(size=(H, W, 3))
    ray[::3] += 8.0 * np.asarray(sun.U)  # many rays near the sun's circle: track and halo codes
    ray /= np.linalg.norm(ray, axis=-1, keepdims=True)
    surf = rng.choice(np.array([SKY, 1, 2, 3], np.int8), size=(H, W))
    part = np.where(surf >= 1, rng.integers(1, 4, size=(H, W)), 0).astype(np.int8)
    frame = Frame(t=0.0, reflections=2, direction=ray.astype(np.float32), surface=surf, part=part,
                  distance=np.ones((H, W), np.float32), point=np.zeros((H, W, 3), np.float32),
                  normal=n.astype(np.float32), bounces=rng.integers(0, 3, size=(H, W)).astype(np.uint8),
                  ray=ray.astype(np.float32), final_surface=surf, final_part=part, final_normal=n.astype(np.float32))
    with kernels.use_compiled(False):
        ref = encode(scene, frame, seed=9)
    got = encode(scene, frame, seed=9)
    np.testing.assert_array_equal(got, ref)
    from sunset.tape.codes import CODE_MAP

    assert CODE_MAP.track.contains(ref).any() and CODE_MAP.halo.contains(ref).any()
    # an unknown island part is the same error on both paths
    frame.final_part[0, 0] = 7
    frame.final_surface[0, 0] = 1
    for flag in (False, True):
        with kernels.use_compiled(flag), pytest.raises(Exception, match="final_part"):
            encode(scene, frame, seed=9)


# -- both cores inside one frame: strips on threads (kernels.run_strips) ---------------------------------

def test_strips_cut_the_range_into_contiguous_pieces():
    for n_threads in (1, 2, 3):
        with kernels.use_threads(n_threads):
            for n in (0, 1, 5, 97, 1024):
                for max_items in (None, 1, 7, 300):
                    parts = kernels.strips(n, max_items)
                    covered = [i for a, b in parts for i in range(a, b)]
                    assert covered == list(range(n))
                    if max_items:
                        assert all(b - a <= max_items for a, b in parts)
                    if n_threads == 1 and not max_items and n:
                        assert parts == [(0, n)]
            assert kernels.run_strips(lambda a, b: (a, b), kernels.strips(50)) == kernels.strips(50)


@pytest.mark.parametrize("compiled", [False, True])
def test_frames_codes_and_exposures_do_not_depend_on_the_threads(compiled):
    from sunset.recorder.dicomed import expose

    scenes = small_scenes()
    scenes["big"] = Scene.default().with_size(260, 230)
    for name, scene in scenes.items():
        results = []
        for n_threads in (1, 2, 3):
            with kernels.use_compiled(compiled), kernels.use_threads(n_threads):
                frame = render(scene, 1.1, 2)
                codes = encode(scene, frame, seed=9)
                results.append((frame, codes, expose(scene, codes, 0.3)))
        for frame, codes, rgb in results[1:]:
            frames_equal(frame, results[0][0])
            np.testing.assert_array_equal(codes, results[0][1])
            np.testing.assert_array_equal(rgb, results[0][2])


def test_the_dither_of_a_strip_is_its_piece_of_the_frames_stream():
    from sunset.tape.codes import dither

    H, W = 23, 31
    rng = np.random.default_rng(77)
    u, v = rng.random((H, W)), rng.random((H, W))
    np.testing.assert_array_equal(dither(77, 5 * W, (4, W)), u[5:9])
    np.testing.assert_array_equal(dither(77, (H + 11) * W, (12, W)), v[11:23])
    np.testing.assert_array_equal(dither(77, 0, (H, W)), u)


@pytest.mark.parametrize("compiled", [False, True])
def test_an_island_pass_computed_once_serves_every_time(compiled):
    from sunset.errors import SunsetError

    scene = Scene.default().with_size(120, 100)
    with kernels.use_compiled(compiled):
        islands = direct.island_pass(scene)
        before = (islands.u.copy(), islands.code.copy())
        for t in (0.0, 0.9, 2.3):
            frames_equal(render(scene, t, 2, islands=islands), render(scene, t, 2))
        # the pass is not changed by the frames that use it
        np.testing.assert_array_equal(islands.u, before[0])
        np.testing.assert_array_equal(islands.code, before[1])
        assert (islands.code > 0).any() and (islands.code == SKY).any()
        # another camera or other islands: refused
        with pytest.raises(SunsetError, match="another camera"):
            render(scene.with_size(121, 100), 0.0, 2, islands=islands)
        with pytest.raises(SunsetError, match="another camera"):
            render(small_scenes()["bare"].with_size(120, 100), 0.0, 2, islands=islands)
