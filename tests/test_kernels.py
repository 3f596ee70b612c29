"""The compiled kernels (the `*_numba` twins chosen by sunset/kernels.py) against the NumPy reference kernels.

The NumPy kernels are the reference (and are themselves tested against the
paper's scalar loop and the brute-force caster elsewhere). The compiled
kernels compute with other arithmetic (their own float32 cosine, loops in
another order), so they are held to the tolerances of sunset.kernels
(AGREE_*), measured in chapter 10: every geometry field within its
tolerance where both paths' rays meet the same surfaces, the codes
identical on at least AGREE_CODES of the pixels with every differing one
explained (tests/agree.py). Kernels without a transcendental function (the
scan conversion, the island piercing, the interval cut) compute the same
formula in the same IEEE operations and are compared for equality. Each
path on its own is byte-deterministic, for any number of threads.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from sunset import kernels
from sunset.vector import crests, heightfield as hf, heightfield_numba, island_samples, pierce, reflect_numba
from sunset.pipeline.frame import encode, render
from sunset.constants import SEA, SKY
from sunset.model.islands import Island, Paraboloid
from sunset.model.scene import as_scene, Scene, scene_names
from sunset.model.waves import Sea, WaveTrain
from sunset.pipeline.frame import island_pass, trace_direct, trace_reflections

from .agree import assert_codes_agree, assert_geometry_agrees
from .vector.test_crests_numba import CREST_DISTANCE_RTOL, CREST_GRAZING_SHARE

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


#: The sea's profile g = (elevation − h)·u on both paths, absolute, metres per metre: float32 roundings of
#: the elevation (a few 1e-7 of the largest amplitude) times u <= 0.5 (the tests' samples).
PROFILE_ATOL = 5e-7


@pytest.mark.parametrize("order", [1, 2, 4])
@pytest.mark.parametrize("t", [0.0, 1.3, 977.25])
def test_sea_profile_agrees_with_the_numpy_one(order, t):
    # Stokes orders 1 (no Horner loop), 2 (the default) and 4 (the longest), random scan lines
    rng = np.random.default_rng(order)
    sea = Sea([WaveTrain(0.5, 40.0, 260.0, 0.3, stokes_order=order), WaveTrain(0.12, 10.0, 235.0, 1.0),
               WaveTrain(0.0, 7.0, 10.0, 0.0)])
    s = rng.uniform(-0.4, 0.4, 7)
    u = np.sort(rng.uniform(1e-4, 0.5, 300))[::-1]
    want = hf.sea_profile.reference(sea, s, u, 2.0, t)
    got = hf.sea_profile.compiled()(sea, s, u, 2.0, t)
    assert got.dtype == want.dtype == np.float32 and got.shape == want.shape == (7, 300)
    err = np.abs(got.astype(float) - want)
    assert 0 < err.max() <= PROFILE_ATOL          # two arithmetic paths: close, not the same bits
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
def test_crest_hits_agree_with_the_numpy_ones(order):
    rng = np.random.default_rng(order)
    train = WaveTrain(0.5, 40.0, direction=rng.uniform(0, 360), phase=rng.uniform(0, 6), stokes_order=order)
    q, r = rays(rng, 5000)
    q[:, 2] = -2.0 + Sea((train,)).elevation(q[:, 0], q[:, 1], 1.3)
    cyl = crests.crest_cylinder(train, 1.3, q, r)
    t_in, _, meets = pierce.quadratic_interval(*crests.cylinder_coefficients(cyl, q, r))
    want = pierce.first_entry(t_in, meets)
    assert np.isfinite(want).sum() > 100
    got = reflect_numba.crest_hits(train, 1.3, q, r)
    hit = np.isfinite(want)
    np.testing.assert_array_equal(np.isfinite(got), hit)
    err = np.abs(got[hit] - want[hit]) / want[hit]
    assert np.count_nonzero(err > CREST_DISTANCE_RTOL) <= CREST_GRAZING_SHARE * err.size


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


def both_paths(scene, t, mode, sea_bounces=True, seed=4):
    """(frame, codes) on the NumPy path and on the compiled one."""
    out = []
    for compiled in (False, True):
        with kernels.use_compiled(compiled):
            frame = render(scene, t, mode, sea_bounces=sea_bounces)
            out.append((frame, encode(scene, frame, seed=seed)))
    return out


def assert_paths_agree(scene, t, mode, sea_bounces=True, seed=4, context=""):
    (ref, ref_codes), (got, got_codes) = both_paths(scene, t, mode, sea_bounces, seed)
    assert_geometry_agrees(ref, got, context)
    causes = assert_codes_agree(scene, ref, got, ref_codes, got_codes, seed, context)
    return ref, got, causes


@pytest.mark.parametrize("name", ["default", "still", "bare", "near"])
@pytest.mark.parametrize("mode", [0, 1, 2])
def test_frames_and_codes_agree_on_both_paths(name, mode):
    scene = small_scenes()[name]
    for t in (0.0, 1.7):
        ref, _, _ = assert_paths_agree(scene, t, mode, context=f"{name} t={t} mode {mode}")
        assert (ref.surface == SEA).any()


@pytest.mark.parametrize("name", sorted(scene_names()))
@pytest.mark.parametrize("mode", [0, 1, 2])
@pytest.mark.parametrize("sea_bounces", [False, True])
def test_every_packaged_scene_agrees_on_both_paths(name, mode, sea_bounces):
    scene = as_scene(name).with_size(256, 192)
    period = scene.sea.period or 8.0
    for t in (0.0, 0.37 * period):
        assert_paths_agree(scene, t, mode, sea_bounces, context=f"{name} t={t:.2f} mode {mode}")


@pytest.mark.parametrize("name", ["carlas-island", "storm-swell"])
def test_the_codes_agree_on_a_full_size_frame(name):
    # the contract's size: 1024², the mode of Figure 6; the geometry within its tolerances there too
    scene = as_scene(name).with_size(1024, 1024)
    ref, got, causes = assert_paths_agree(scene, 1.1, 2, sea_bounces=False, context=name)
    assert (ref.surface == SEA).mean() > 0.3


def test_the_agreement_checks_can_fail():
    # a frame one path got wrong: the hit points of a tenth of the sea moved along their rays by three times
    # the tolerance, and codes changed on a share of pixels one too many
    scene = small_scenes()["default"]
    (ref, ref_codes), (got, got_codes) = both_paths(scene, 0.0, 2)
    assert_geometry_agrees(ref, got)
    bad = render(scene, 0.0, 2)
    moved = np.zeros(bad.shape, bool)
    moved[::10] = bad.surface[::10] == SEA                # the sea pixels of every tenth row
    bad.point[moved] *= np.float32(1.0 + 3 * kernels.AGREE_POINT)
    with pytest.raises(AssertionError, match="point"):
        assert_geometry_agrees(ref, bad)
    wrong = ref_codes.copy()
    n = int(np.ceil((1 - kernels.AGREE_CODES) * wrong.size)) + 1
    flat = wrong.reshape(-1)
    flat[:n] = flat[:n] ^ 1
    with pytest.raises(AssertionError, match="identical"):
        assert_codes_agree(scene, ref, ref, ref_codes, wrong, 4)
    scene = Scene.default().with_size(128, 96)        # more than 10⁴ pixels: one code may differ
    (ref, ref_codes), _ = both_paths(scene, 0.0, 2)
    one = ref_codes.copy()
    one[0, 0] ^= 1                                    # same frames, another code: no known cause
    with pytest.raises(AssertionError, match="no known cause"):
        assert_codes_agree(scene, ref, ref, ref_codes, one, 4)


def test_a_larger_frame_agrees_on_both_paths():
    # more scan lines than one chunk, and islands of many samples per scan line
    scene = Scene.default().with_size(300, 260)
    assert_paths_agree(scene, 0.4, 2, context="300x260")


def test_write_back_into_a_non_contiguous_frame():
    scene = Scene.default().with_size(40, 30)
    with kernels.use_compiled(True):
        frame = trace_direct(scene, 0.0)
        frame.finish_direct()
        frame.ray = np.asfortranarray(frame.ray)  # reshape(-1) of this would copy
        trace_reflections(scene, frame, 1)
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
    from sunset.pipeline.frame import expose

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


#: NumPy's SIMD code for this processor switched off (AVX-512 and, in its X86_V3 target, AVX2 and FMA), as on an
#: older x86 processor: a frame must still be rendered by the compiled kernels. (This NumPy has no target named
#: AVX2 of its own: X86_V3 is the one that holds it.)
NO_NUMPY_SIMD = "AVX512_ICL AVX512_SPR X86_V4 X86_V3"

_PATH_PROBE = """
import json, time
from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
from sunset import kernels
from sunset.model.scene import Scene
from sunset.pipeline.frame import encode, render
from sunset.vector import direct_numba, heightfield_numba, island_samples_numba, reflect_numba, slopes_numba
from sunset.tape import codes_numba
scene = Scene.default().with_size(256, 192)
encode(scene, render(scene, 0.5, 2, sea_bounces=False), seed=0)
kernels_run = {name: len(fn.signatures) for name, fn in [
    ("sea columns", heightfield_numba._sea_columns), ("island strip", island_samples_numba._islands_strip),
    ("geometry", direct_numba._assemble), ("island normals", direct_numba._island_normals),
    ("sea normals", slopes_numba._normals), ("reflections", reflect_numba.trace_strip),
    ("codes", codes_numba._encode_pixels)]}
print(json.dumps({"numpy_simd": [n for n in __cpu_dispatch__ if __cpu_features__.get(n)],
                  "enabled": kernels.enabled(), "kernels": kernels_run}))
"""


@pytest.mark.parametrize("disabled", ["", NO_NUMPY_SIMD])
def test_the_compiled_path_runs_whatever_simd_numpy_picked(disabled):
    # each compiled kernel of a frame ran (Numba compiled or loaded it for a call) in a fresh process
    env = dict(os.environ, NPY_DISABLE_CPU_FEATURES=disabled)
    env.pop("SUNSET_COMPILED", None)
    out = subprocess.run([sys.executable, "-c", _PATH_PROBE], env=env, capture_output=True, text=True, check=True)
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["enabled"] is True
    assert all(n >= 1 for n in report["kernels"].values()), report["kernels"]
    if disabled:
        assert not any(t in report["numpy_simd"] for t in disabled.split()), report["numpy_simd"]
    # and with the compiled kernels off, none of them runs: the probe can tell
    env["SUNSET_COMPILED"] = "0"
    off = json.loads(subprocess.run([sys.executable, "-c", _PATH_PROBE], env=env, capture_output=True, text=True,
                                    check=True).stdout.strip().splitlines()[-1])
    assert off["enabled"] is False and not any(off["kernels"].values())


@pytest.mark.parametrize("compiled", [False, True])
def test_an_island_pass_computed_once_serves_every_time(compiled):
    from sunset.errors import SunsetError

    scene = Scene.default().with_size(120, 100)
    with kernels.use_compiled(compiled):
        islands = island_pass(scene)
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
