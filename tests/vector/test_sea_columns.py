"""The sea's scan lines in one compiled pass (heightfield.sea_columns and its twin) against the NumPy reference.

The reference is :func:`sunset.vector.heightfield.sea_profile` followed by
:func:`sunset.vector.heightfield.sea_scan` on the NumPy path (whole-array
float32 phases, NumPy's ``np.cos``, Horner's rule, the vectorized scan
conversion). The twin computes each scan line's profile with its own
float32 cosine (:mod:`sunset.vector.sincos_numba`) and scan-converts it at
once; the depth buffer and the winning surfaces must agree as
tests/agree.py says, for the packaged scenes, Stokes orders 1 to 4, a still
sea, phases beyond the cosine's fast range, and on any number of threads
(where each path gives the same bytes).
"""

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import SEA, SKY
from sunset.errors import SunsetError
from sunset.model.scene import as_scene, Scene, scene_names
from sunset.model.waves import Sea, WaveTrain
from sunset.vector.sincos_numba import LIMIT
from sunset.vector import heightfield as hf, heightfield_numba
from sunset.pipeline.frame import render
from sunset.pipeline.frame import trace_direct

from ..agree import assert_depth_agrees, assert_geometry_agrees

pytestmark = pytest.mark.skipif(not kernels.AVAILABLE, reason="no Numba: no compiled kernels")

#: The sea's profile on both paths, absolute (metres per metre of 1/y): float32 roundings of an elevation of a
#: few metres, times u.
PROFILE_ATOL = 5e-7


def setup(scene, seed=0):
    """The sea's lattice, the scan lines and a depth buffer half filled with 'islands' (code 2)."""
    cam = scene.camera
    samp = hf.sampling(cam, scene.sea.max_elevation)
    dz = cam.pixel_pitch[1]
    rng = np.random.default_rng(seed)
    W, H = cam.width, cam.height
    u = samp.u()
    best_u = np.where(rng.random((W, H)) < 0.4, rng.random((W, H)) * u[0], 0.0)
    best_surf = np.where(best_u > 0, 2, SKY).astype(np.int8)
    return cam, u, cam.s_centres(), cam.zy_min + 0.5 * dz, dz, best_u, best_surf


def both(scene, t, seed=0):
    """(reference, twin) results: (tail pixels, best_u, best_surf)."""
    cam, u, s, zeta0, dz, best_u, best_surf = setup(scene, seed)
    args = (scene.sea, s, u, cam.eye_height, t, zeta0, dz, cam.height)
    out = []
    for fn in (hf.sea_columns.reference, hf.sea_columns.compiled()):
        bu, bs = best_u.copy(), best_surf.copy()
        with kernels.use_compiled(False):      # the reference's inner calls on the NumPy path too
            n = fn(*args, bu, bs)
        out.append((n, bu, bs))
    return out


def assert_same(ref, got):
    """Both paths' (tail pixels, best_u, best_surf) agree: the tail (a plane) within a pixel a scan line."""
    assert abs(got[0] - ref[0]) <= max(1, ref[1].shape[0] // 100)
    assert_depth_agrees(ref[1], ref[2], got[1], got[2])


@pytest.mark.parametrize("name", sorted(scene_names()))
@pytest.mark.parametrize("t", [0.0, 1.3, 977.25])
def test_the_twin_is_the_reference_on_the_packaged_scenes(name, t):
    scene = as_scene(name).with_size(90, 70)
    if scene.sea.wind is not None:         # the trains' kernels refuse a wind sea (not drawn flat): both paths
        cam, u, s, zeta0, dz, best_u, best_surf = setup(scene)
        bu, bs = best_u.copy(), best_surf.copy()
        profile = (scene.sea, s, u, cam.eye_height, t)
        for fn, args in ((hf.sea_profile.reference, profile), (hf.sea_profile.compiled(), profile),
                         (hf.sea_columns.reference, profile + (zeta0, dz, cam.height, bu, bs)),
                         (hf.sea_columns.compiled(), profile + (zeta0, dz, cam.height, bu, bs))):
            with pytest.raises(SunsetError, match="^sea: a wind sea has no trains"):
                fn(*args)
        np.testing.assert_array_equal(bu, best_u)              # nothing drawn
        np.testing.assert_array_equal(bs, best_surf)
        return
    ref, got = both(scene, t)
    assert_same(ref, got)
    if scene.camera.zy_min < 0:            # the sea is in view: it wins pixels, and some islands' stay
        assert (ref[2] == SEA).any() and (ref[2] == 2).any()


def sea_scene(trains, size=(70, 90)):
    default = Scene.default()
    return Scene(camera=default.camera, sun=default.sun, sea=Sea(tuple(trains)), islands=()).with_size(*size)


@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_every_stokes_order_and_a_train_at_rest(order):
    scene = sea_scene([WaveTrain(0.5, 40.0, 260.0, 0.3, stokes_order=order), WaveTrain(0.12, 10.0, 235.0, 1.0),
                       WaveTrain(0.0, 7.0, 10.0, 0.0), WaveTrain(0.2, 25.0, 95.0, 2.0, stokes_order=5 - order)])
    for t in (0.0, 4.5):
        ref, got = both(scene, t, seed=order)
        assert_same(ref, got)
        assert (ref[2] == SEA).any()


def test_a_still_sea_and_the_far_tail():
    # no trains: the profile is −h·u, the plane; every pixel below the horizon is sea, the tail included
    ref, got = both(sea_scene([], size=(40, 31)), 0.0)
    assert_same(ref, got)
    assert ref[0] == 40                      # one tail pixel on each scan line at this size


def test_phases_beyond_the_cosines_fast_range():
    # 2 cm waves: b·y passes LIMIT far out, where the twin calls the C library's cosf
    scene = sea_scene([WaveTrain(0.0005, 0.02, 80.0, 0.0), WaveTrain(0.3, 30.0, 200.0, 0.0)], size=(40, 400))
    cam = scene.camera
    u = hf.sampling(cam, scene.sea.max_elevation).u()
    b, c, *_ = heightfield_numba._sea_coefficients(scene.sea, cam.s_centres(), 2.0, cam.eye_height)
    phase = np.abs(b[:, :, None] * (1.0 / u).astype(np.float32)[None, None, :] + c[:, None, None])
    assert np.count_nonzero(phase > LIMIT) > 40              # the last samples of every scan line
    ref, got = both(scene, 2.0)
    assert_same(ref, got)


def test_the_profile_twin_agrees_with_the_reference():
    scene = as_scene("storm-swell").with_size(50, 60)
    cam = scene.camera
    u = hf.sampling(cam, scene.sea.max_elevation).u()
    s = cam.s_centres()
    want = hf.sea_profile.reference(scene.sea, s, u, cam.eye_height, 3.3)
    got = hf.sea_profile.compiled()(scene.sea, s, u, cam.eye_height, 3.3)
    assert np.abs(got.astype(float) - want).max() <= PROFILE_ATOL
    # still water is the plane −h·u on both paths, the same numbers
    np.testing.assert_array_equal(hf.sea_profile.compiled()(Sea(()), s, u, cam.eye_height, 0.0),
                                  hf.sea_profile.reference(Sea(()), s, u, cam.eye_height, 0.0))


def test_a_strided_depth_buffer():
    scene = as_scene("carlas-island").with_size(40, 30)
    cam, u, s, zeta0, dz, best_u, best_surf = setup(scene)
    ref_u, ref_s = best_u.copy(), best_surf.copy()
    with kernels.use_compiled(False):
        n_ref = hf.sea_columns(scene.sea, s, u, cam.eye_height, 0.5, zeta0, dz, cam.height, ref_u, ref_s)
    wide_u = np.zeros((best_u.shape[0], 2 * best_u.shape[1]))
    wide_s = np.zeros(wide_u.shape, np.int8)
    wide_u[:, ::2], wide_s[:, ::2] = best_u, best_surf
    n = hf.sea_columns.compiled()(scene.sea, s, u, cam.eye_height, 0.5, zeta0, dz, cam.height, wide_u[:, ::2],
                                  wide_s[:, ::2])
    got_u, got_s = best_u.copy(), best_surf.copy()
    assert n == hf.sea_columns.compiled()(scene.sea, s, u, cam.eye_height, 0.5, zeta0, dz, cam.height, got_u, got_s)
    assert abs(n - n_ref) <= 1
    np.testing.assert_array_equal(wide_u[:, ::2], got_u)          # strided or not: the same bytes
    np.testing.assert_array_equal(wide_s[:, ::2], got_s)
    assert_depth_agrees(ref_u, ref_s, got_u, got_s)


def test_the_sea_wins_exact_ties():
    scene = as_scene("carlas-island").with_size(60, 50)
    cam, u, s, zeta0, dz, _, _ = setup(scene)
    sea_u = np.zeros((cam.width, cam.height))
    sea_s = np.full(sea_u.shape, SKY, np.int8)
    with kernels.use_compiled(False):
        hf.sea_columns(scene.sea, s, u, cam.eye_height, 0.5, zeta0, dz, cam.height, sea_u, sea_s)
    with kernels.use_compiled(True):
        twin_u = np.zeros((cam.width, cam.height))
        twin_s = np.full(twin_u.shape, SKY, np.int8)
        hf.sea_columns(scene.sea, s, u, cam.eye_height, 0.5, zeta0, dz, cam.height, twin_u, twin_s)
    for fn, want_u, want_s in ((hf.sea_columns.reference, sea_u, sea_s),
                               (hf.sea_columns.compiled(), twin_u, twin_s)):
        # the path's own sea at a third of its pixels put in the buffer as island 2: the sea wins every tie
        tie = (want_u > 0) & (np.arange(want_u.size).reshape(want_u.shape) % 3 == 0)
        assert tie.sum() > 100
        best_u = np.where(tie, want_u, 0.0)
        best_surf = np.where(tie, 2, SKY).astype(np.int8)
        with kernels.use_compiled(fn is not hf.sea_columns.reference):
            fn(scene.sea, s, u, cam.eye_height, 0.5, zeta0, dz, cam.height, best_u, best_surf)
        np.testing.assert_array_equal(best_u, want_u)
        np.testing.assert_array_equal(best_surf, want_s)


@pytest.mark.parametrize("name", ["storm-swell", "archipelago-at-dusk"])
def test_the_direct_rays_do_not_depend_on_the_threads_and_agree_across_paths(name):
    scene = as_scene(name).with_size(130, 97)
    with kernels.use_compiled(False):
        ref = trace_direct(scene, 2.5)
    runs = []
    for n in (1, 2, 3):
        with kernels.use_compiled(True), kernels.use_threads(n):
            runs.append(trace_direct(scene, 2.5))
    for got in runs[1:]:
        for field in ("surface", "distance", "point", "normal", "direction"):
            np.testing.assert_array_equal(getattr(got, field).view(np.uint8), getattr(runs[0], field).view(np.uint8))
    ref.finish_direct(False)
    runs[0].finish_direct(False)
    assert_geometry_agrees(ref, runs[0], name)
    assert (ref.surface == SEA).any()


def test_a_whole_frame_on_two_threads():
    scene = as_scene("post-in-the-swell").with_size(120, 90)
    frames = []
    for n in (1, 2):
        with kernels.use_compiled(True), kernels.use_threads(n):
            frames.append(render(scene, 0.9, 2))
    for field, value in vars(frames[0]).items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(np.ascontiguousarray(getattr(frames[1], field)).view(np.uint8),
                                          np.ascontiguousarray(value).view(np.uint8))


@pytest.mark.parametrize("seed", range(30))
def test_the_branch_free_scan_line_is_scan_convert(seed):
    # random profiles, float32 and float64, rising and falling, with −∞ samples, pixels above and below them all
    rng = np.random.default_rng(300 + seed)
    dtype = (np.float32, np.float64)[seed % 2]
    N, K = int(rng.integers(1, 80)), int(rng.integers(1, 50))
    g = np.cumsum(rng.normal(0.05, 0.3, N)).astype(dtype)
    g[rng.random(N) < 0.1] = -np.inf
    if seed % 3 == 0:
        g[: N // 2] = g[N // 2]               # long flat runs: equal bins
    u = np.sort(rng.random(N))[::-1].copy()
    zeta0, dz = float(rng.normal()), float(rng.uniform(0.01, 0.3))
    want = hf.scan_convert(u, g[None, :], zeta0, dz, K)[0]
    got = np.empty(K)
    t = np.dtype(dtype).type
    heightfield_numba._scan_row_b(u, 0, g, 0, N, zeta0, dz, t(1.0 / dz), t(zeta0), t(K), t(0.0), K, got,
                                  np.empty(N, np.int32), np.empty(K + 1, np.int64))
    np.testing.assert_array_equal(got.view(np.uint64), want.view(np.uint64))


@pytest.mark.parametrize("order", [1, 2, 3])
def test_samples_in_any_order_and_phases_past_the_fast_range(order):
    # the twin's one-pass trains bound a scan line's phases by its first and last sample, which needs y sorted;
    # unsorted samples, and phases past LIMIT at either end, take the general path
    rng = np.random.default_rng(order)
    sea = Sea([WaveTrain(0.3, 30.0, 200.0, 0.4, stokes_order=order), WaveTrain(0.0005, 0.02, 80.0, 0.0),
               WaveTrain(0.1, 12.0, 140.0, 1.0, stokes_order=4 - order)])
    s = rng.uniform(-0.4, 0.4, 9)
    for u in (np.sort(rng.uniform(1e-5, 0.5, 400))[::-1], rng.uniform(1e-5, 0.5, 400),
              np.sort(rng.uniform(0.2, 0.5, 400))[::-1]):
        for t in (0.0, 3.7):
            want = hf.sea_profile.reference(sea, s, u, 2.0, t)
            got = hf.sea_profile.compiled()(sea, s, u, 2.0, t)
            assert np.abs(got.astype(float) - want).max() <= PROFILE_ATOL
            # the general path and the one-pass one are the same arithmetic: sorted samples give the same bytes
            order_ = np.argsort(1.0 / u)
            fast = hf.sea_profile.compiled()(sea, s, u[order_], 2.0, t)
            np.testing.assert_array_equal(fast, got[:, order_])
