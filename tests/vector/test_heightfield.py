"""The σ-sampled height-field scan line and the direct-ray frame (sunset/vector/heightfield.py).

References: exact plane intersections, the exact ray–paraboloid quadratic,
finite differences of sunset.model.waves.Sea.elevation, the paper's scalar yp loop,
and the independent brute-force caster (sunset/vector/bruteforce.py).
"""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sunset.vector import heightfield as hf
from sunset.vector.bruteforce import trace_direct_bruteforce
from sunset.model.camera import Camera
from sunset.constants import PART_CLIFF, PART_NONE, SEA, SKY
from sunset.errors import SunsetError
from sunset.model.islands import Island, Paraboloid
from sunset.model.scene import Scene
from sunset.model.waves import Sea, WaveTrain
from sunset.pipeline.frame import trace_direct

finite = dict(allow_nan=False, allow_infinity=False)


@pytest.fixture(scope="module")
def small_default():
    return Scene.default().with_size(64, 64)


@pytest.fixture(scope="module")
def brute_default(small_default):
    return trace_direct_bruteforce(small_default, 0.0)


# -- the samples ---------------------------------------------------------------------

def test_samples_project_evenly_on_the_mean_plane():
    cam = Camera(eye_height=3.0, width=50, height=80, zy_min=-0.3, zy_max=0.1, sigma=0.25)
    samp = hf.sampling(cam, 0.4)
    y = samp.y()
    zeta = -cam.eye_height / y               # projection of (·, y, −h)
    dz = cam.pixel_pitch[1]
    # i = n … 1, each σ pixels apart, the farthest σ pixels below the horizon
    np.testing.assert_allclose(np.diff(zeta) / dz, cam.sigma, rtol=1e-9)
    assert zeta[-1] / dz == pytest.approx(-cam.sigma)
    # the nearest sample projects below the bottom pixel even on the highest crest
    zeta0 = cam.zy_min + 0.5 * dz
    assert (0.4 - cam.eye_height) / y[0] < zeta0
    assert (0.4 - cam.eye_height) / y[1] >= zeta0 - cam.sigma * dz * 1.01 * cam.eye_height / (cam.eye_height - 0.4)


@pytest.mark.parametrize("sigma", [2.0, 1.0, 0.25, 0.125])
def test_sample_count_scales_as_one_over_sigma(sigma):
    cam = Camera(width=10, height=200, sigma=sigma)
    n = hf.sampling(cam, 0.0).n
    # from the bottom pixel's centre up to the horizon, σ pixels apart
    pixels_below = -cam.zy_min / cam.pixel_pitch[1] - 0.5
    assert n == pytest.approx(pixels_below / sigma, abs=2)


def test_no_sea_samples_when_the_window_is_above_the_horizon():
    cam = Camera(width=10, height=20, zy_min=0.01, zy_max=0.2)
    assert hf.sampling(cam, 0.5).n == 0
    frame = trace_direct(Scene(camera=cam, sea=Sea((WaveTrain(0.3, 20.0),))), 0.0)
    assert np.all(frame.surface == SKY)


# -- the scan conversion: the paper's loop and the vectorized one ---------------------

def test_reference_loop_on_a_plane_is_exact():
    # g = −h u on the mean plane: linear in u, so interpolation in 1/y is exact
    h = 2.0
    u = np.arange(400, 0, -1) * 1e-4
    g = -h * u
    zeta = np.linspace(-0.039, -0.00025, 57)  # the farthest sample is at −0.0002
    yp = hf.scan_line_reference(1.0 / u, g, zeta)
    np.testing.assert_allclose(yp, h / -zeta, rtol=1e-12)


def test_reference_loop_by_hand():
    # near to far: g rises to 0.5 then falls; pixel centres at 0, 0.25, 0.75
    y = np.array([1.0, 2.0, 4.0])
    g = np.array([-1.0, 0.5, 0.2])
    yp = hf.scan_line_reference(y, g, [0.0, 0.25, 0.75])
    # pixel 0: between samples 0 and 1, f = 1/1.5 of the way in 1/y from 1 to 1/2
    assert yp[0] == pytest.approx(1.0 / (1.0 + (1.0 / 1.5) * (0.5 - 1.0)))
    assert yp[1] == pytest.approx(1.0 / (1.0 + (1.25 / 1.5) * (0.5 - 1.0)))
    assert yp[2] == np.inf  # no sample rises above 0.75


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_lines=st.integers(1, 5), n=st.integers(1, 60), K=st.integers(1, 40),
       pad=st.integers(0, 5))
def test_vectorized_scan_conversion_matches_the_loop(seed, n_lines, n, K, pad):
    rng = np.random.default_rng(seed)
    u = np.sort(rng.uniform(0.01, 1.0, (n_lines, n + pad)), axis=1)[:, ::-1].copy()
    g = np.cumsum(rng.normal(0, 0.3, (n_lines, n + pad)), axis=1) - 1.0
    if pad:
        g[:, n:] = -np.inf                      # missing samples at the far end
    dz = 0.1
    zeta0 = -1.0
    zeta = zeta0 + dz * np.arange(K)
    got = hf.scan_convert(u, g, zeta0, dz, K)
    for c in range(n_lines):
        ref = hf.scan_line_reference(1.0 / u[c, :n], g[c, :n], zeta)
        expect = np.where(np.isfinite(ref), 1.0 / np.where(np.isfinite(ref), ref, 1.0), 0.0)
        np.testing.assert_allclose(got[c], expect, rtol=1e-9, atol=1e-12)


def test_vectorized_scan_conversion_on_a_real_scan_line(small_default):
    scene = small_default
    cam = scene.camera
    samp = hf.sampling(cam, scene.sea.max_elevation)
    s = cam.s_centres()[[3, 30, 60]]
    u = samp.u()
    g = hf.sea_profile(scene.sea, s, u, cam.eye_height, 1.3)
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    got = hf.scan_convert(u, g, zeta0, dz, cam.height)
    zeta = zeta0 + dz * np.arange(cam.height)
    for c in range(3):
        ref = hf.scan_line_reference(1.0 / u, g[c].astype(float), zeta)
        hit = np.isfinite(ref)
        np.testing.assert_allclose(got[c][hit], 1.0 / ref[hit], rtol=1e-6)
        assert np.all(got[c][~hit] == 0)


# -- the sea along a scan line ------------------------------------------------------------

def test_sea_profile_matches_the_elevation(small_default):
    sea = small_default.sea
    s = np.array([-0.2, 0.0, 0.13])
    u = np.array([0.3, 0.05, 0.01, 0.002])
    t = 2.7
    g = hf.sea_profile(sea, s, u, 2.0, t)
    y = 1.0 / u
    expect = (sea.elevation(s[:, None] * y[None, :], y[None, :], t) - 2.0) * u[None, :]
    assert g.dtype == np.float32
    np.testing.assert_allclose(g, expect, rtol=2e-5, atol=1e-7)


def test_sea_profile_with_all_stokes_orders():
    sea = Sea.periodic(30.0, [0.8, 0.1, 0.04], [250.0, 200.0, 300.0], phases=[0.3, 1.0, 2.0], stokes_orders=[4, 3, 2])
    s = np.array([-0.1, 0.2])
    u = np.array([0.2, 0.02])
    g = hf.sea_profile(sea, s, u, 3.0, 0.9)
    y = 1.0 / u
    expect = (sea.elevation(s[:, None] * y, y, 0.9) - 3.0) * u
    np.testing.assert_allclose(g, expect, rtol=2e-5, atol=1e-7)


@pytest.mark.parametrize("orders", [[1, 1], [2, 1], [4, 3]])
def test_scanline_gradient_by_finite_differences(orders):
    sea = Sea.periodic(30.0, [0.8, 0.1], [250.0, 200.0], phases=[0.3, 1.0], stokes_orders=orders)
    s = np.array([-0.2, 0.0, 0.1, 0.25])
    y = np.array([5.0, 12.0, 40.0, 90.0])
    t = 1.1
    fx, fy = hf.sea_gradient_on_scanlines(sea, s, y, t)
    x = s * y
    e = 1e-4
    ex = (sea.elevation(x + e, y, t) - sea.elevation(x - e, y, t)) / (2 * e)
    ey = (sea.elevation(x, y + e, t) - sea.elevation(x, y - e, t)) / (2 * e)
    np.testing.assert_allclose(fx, ex, atol=2e-5)
    np.testing.assert_allclose(fy, ey, atol=2e-5)


# -- the frame ------------------------------------------------------------------------------

def test_still_water_is_the_exact_plane():
    cam = Camera(eye_height=2.5, width=40, height=60, s_min=-0.4, s_max=0.3, zy_min=-0.3, zy_max=0.1)
    frame = trace_direct(Scene(camera=cam), 0.0)
    D = cam.directions()
    sea = D[..., 2] < 0
    np.testing.assert_array_equal(frame.surface == SEA, sea)
    np.testing.assert_array_equal(frame.surface == SKY, ~sea)
    np.testing.assert_allclose(frame.distance[sea], cam.eye_height / -D[..., 2][sea], rtol=3e-7)
    np.testing.assert_allclose(frame.point[sea][:, 2], -cam.eye_height, rtol=3e-7)
    np.testing.assert_array_equal(frame.normal[sea], np.array([0, 0, 1], np.float32)[None].repeat(sea.sum(), 0))
    assert np.all(np.isinf(frame.distance[~sea])) and np.all(np.isnan(frame.point[~sea]))
    assert np.all(np.isnan(frame.normal[~sea]))


def test_frame_fields(small_default):
    frame = trace_direct(small_default, 0.4)
    H, W = 64, 64
    assert frame.shape == (H, W)
    assert frame.surface.dtype == np.int8 and frame.part.dtype == np.int8
    for name in ("direction", "distance", "point", "normal"):
        assert getattr(frame, name).dtype == np.float32, name
    assert frame.direction.shape == frame.point.shape == frame.normal.shape == (H, W, 3)
    np.testing.assert_allclose(frame.direction, small_default.camera.directions(), rtol=1e-6)
    hit = frame.surface != SKY
    # the point is on the ray at the distance
    np.testing.assert_allclose(frame.point[hit], frame.direction[hit] * frame.distance[hit][:, None], rtol=2e-6, atol=1e-4)
    np.testing.assert_allclose(np.linalg.norm(frame.normal[hit], axis=-1), 1.0, rtol=1e-5)
    assert np.all(frame.normal[hit][:, 2] > 0)
    assert np.all(frame.part[frame.surface <= SEA] == PART_NONE)
    assert np.all(frame.part[frame.surface > 0] > PART_NONE)
    assert set(np.unique(frame.surface)) == {SKY, SEA, 1, 2, 3}
    # row 0 is the top: the sky is up, the sea is down
    assert np.all(frame.surface[0] == SKY) and np.all(frame.surface[-1] == SEA)


def test_surfaces_agree_with_the_brute_force_caster(small_default, brute_default):
    frame = trace_direct(small_default, 0.0)
    agree = frame.surface == brute_default.surface
    # Disagreements can only come from rays that graze a crest or a summit
    # between two samples; at σ = 1/4 these are a few silhouette pixels.
    assert agree.mean() >= 0.995
    assert np.all(frame.part[agree] == brute_default.part[agree])


def test_island_hits_agree_with_the_brute_force_caster(small_default, brute_default):
    frame = trace_direct(small_default, 0.0)
    both = (frame.surface > 0) & (frame.surface == brute_default.surface)
    assert both.sum() > 50
    rel = np.abs(frame.distance[both] / brute_default.distance[both] - 1)
    assert np.median(rel) < 1e-4 and rel.max() < 0.02
    dot = np.sum(frame.normal[both] * brute_default.normal[both], -1)
    assert np.median(dot) > 0.9999


def test_sea_hits_agree_with_the_brute_force_caster_away_from_the_horizon(small_default, brute_default):
    frame = trace_direct(small_default, 0.0)
    cam = small_default.camera
    both = (frame.surface == SEA) & (brute_default.surface == SEA)
    # a pixel near the horizon spans hundreds of metres of sea: its hit
    # distance is ill-conditioned, so compare where a pixel spans < 1/8 of the
    # shortest wavelength... along y, i.e. rows with y_hit·(Δζ/|ζ|) small
    zeta = cam.zy_centres()[:, None] * np.ones((1, cam.width))
    footprint = cam.eye_height / np.abs(zeta) * (cam.pixel_pitch[1] / np.abs(zeta))
    near = both & (footprint < 2.5 / 8)
    assert near.sum() > 500
    rel = np.abs(frame.distance[near] / brute_default.distance[near] - 1)
    assert rel.max() < 1e-3
    assert np.median(np.abs(frame.distance[both] / brute_default.distance[both] - 1)) < 1e-3


def test_sea_normals_are_the_waves_gradient(small_default):
    scene = small_default
    frame = trace_direct(scene, 0.8)
    sea = frame.surface == SEA
    p = frame.point[sea].astype(float)
    e = 1e-4
    fx = (scene.sea.elevation(p[:, 0] + e, p[:, 1], 0.8) - scene.sea.elevation(p[:, 0] - e, p[:, 1], 0.8)) / (2 * e)
    fy = (scene.sea.elevation(p[:, 0], p[:, 1] + e, 0.8) - scene.sea.elevation(p[:, 0], p[:, 1] - e, 0.8)) / (2 * e)
    zb = 1 / np.sqrt(fx**2 + fy**2 + 1)
    expect = np.stack([-zb * fx, -zb * fy, zb], -1)
    np.testing.assert_allclose(frame.normal[sea], expect, atol=2e-4)


def test_island_normals_and_parts_at_the_hit_points(small_default):
    scene = small_default
    frame = trace_direct(scene, 0.0)
    for k, isl in enumerate(scene.islands, start=1):
        sel = frame.surface == k
        p = frame.point[sel].astype(float)
        np.testing.assert_allclose(frame.normal[sel], isl.normal(p[:, 0], p[:, 1]), atol=2e-3)
        assert np.mean(frame.part[sel] == isl.part(p[:, 0], p[:, 1])) > 0.97


def test_ray_meets_a_bare_paraboloid_where_the_quadratic_says():
    # one island without cosines or hills on still water: the ray x = s y, z = ζ y
    # meets P(x, y) − h = ζ y where A y² − (B − ζ) y + (C − height + h) = 0
    isl = Island(x=30.0, y=600.0, cliff=Paraboloid(60.0, 0.004, 0.001, 0.003), beach=Paraboloid(0.5, 0.01, 0.0, 0.01),
                 cliff_top=59.0, hill_factor=1.0)
    cam = Camera(eye_height=2.0, width=48, height=48, s_min=-0.15, s_max=0.25, zy_min=-0.05, zy_max=0.1, sigma=0.25)
    frame = trace_direct(Scene(camera=cam, islands=(isl,)), 0.0)
    s = cam.s_centres()[None, :] * np.ones((48, 1))
    z = cam.zy_centres()[:, None] * np.ones((1, 48))
    par, X, Y = isl.cliff, isl.x, isl.y
    A = par.e * s**2 + par.f * s + par.g
    B = 2 * par.e * s * X + par.f * (X + s * Y) + 2 * par.g * Y
    C = par.e * X**2 + par.f * X * Y + par.g * Y**2 - par.height + cam.eye_height
    disc = (B - z) ** 2 - 4 * A * C
    y_exact = np.where(disc > 0, ((B - z) - np.sqrt(np.abs(disc))) / (2 * A), np.nan)
    island = frame.surface == 1
    assert island.sum() > 100
    y_hit = frame.point[..., 1]
    rel = np.abs(y_hit[island] / y_exact[island] - 1)
    # rays grazing the top are ill-conditioned (a tangent ray), hence the looser maximum
    assert np.quantile(rel, 0.99) < 1e-3 and np.max(rel) < 5e-3 and np.median(rel) < 1e-4
    assert np.all(frame.part[island] == PART_CLIFF)
    # every ray the quadratic says meets the island above the water does so (up to grazing rays)
    meets = (disc > 0) & (y_exact * z > -cam.eye_height)
    assert np.mean(island == meets) > 0.99


def test_islands_pass_in_front_of_the_sea_and_behind_each_other():
    big = Island(x=0.0, y=900.0, cliff=Paraboloid(80.0, 0.004, 0.0, 0.004), beach=Paraboloid(1.0, 1e-4, 0, 1e-4),
                 cliff_top=60.0, hill_factor=0.5)
    near = Island(x=0.0, y=500.0, cliff=Paraboloid(20.0, 0.01, 0.0, 0.01), beach=Paraboloid(1.0, 1e-3, 0, 1e-3),
                  cliff_top=15.0, hill_factor=0.5)
    cam = Camera(eye_height=2.0, width=30, height=40, s_min=-0.2, s_max=0.2, zy_min=-0.05, zy_max=0.1)
    frame = trace_direct(Scene(camera=cam, islands=(big, near)), 0.0)
    col = 15
    column = frame.surface[:, col]
    assert (column == 1).any() and (column == 2).any() and (column == SEA).any()
    # the near island covers the far one's foot: from the bottom, sea, then island 2, then island 1 above it
    rows = {k: np.nonzero(column == k)[0] for k in (SEA, 1, 2)}
    assert rows[2].max() < rows[SEA].min() and rows[1].max() < rows[2].min()
    assert np.all(frame.distance[column == 2, col] < frame.distance[column == 1, col].min())


def test_periodic_in_time(small_default):
    scene = small_default
    T = scene.sea.period
    a = trace_direct(scene, 0.7)
    b = trace_direct(scene, 0.7 + T)
    assert np.mean(a.surface == b.surface) > 0.999
    both = (a.surface == SEA) & (b.surface == SEA)
    assert np.median(np.abs(a.distance[both] / b.distance[both] - 1)) < 1e-5


def test_deterministic(small_default):
    a = trace_direct(small_default, 1.5)
    b = trace_direct(small_default, 1.5)
    for name in ("surface", "part", "distance", "point", "normal"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name


def test_chunking_does_not_change_the_frame(small_default, monkeypatch):
    a = trace_direct(small_default, 0.0)
    import sunset.pipeline.frame as pipeline_frame

    monkeypatch.setattr(pipeline_frame, "SCANLINE_CHUNK_ELEMENTS", 3000)  # a few scan lines per chunk
    b = trace_direct(small_default, 0.0)
    for name in ("surface", "part", "distance", "normal"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name


def test_paper_sampling_of_islands_is_the_sea_lattice(small_default):
    info = {}
    trace_direct(small_default, 0.0, refine_islands=False, info=info)
    info_fine = {}
    trace_direct(small_default, 0.0, info=info_fine)
    assert info["island_samples"] < info_fine["island_samples"]
    assert info["sea_samples"] == info_fine["sea_samples"] == hf.sampling(
        small_default.camera, small_default.sea.max_elevation).n


def test_near_plane_clips_waves_taller_than_the_eye():
    cam = Camera(eye_height=0.5, width=16, height=16)
    sea = Sea((WaveTrain(0.6, 20.0, 270.0),))
    frame = trace_direct(Scene(camera=cam, sea=sea), 0.0)
    assert not np.isnan(frame.distance).any()
    assert (frame.surface == SEA).any()


@pytest.mark.parametrize("t", [float("nan"), float("inf")])
def test_bad_time(t, small_default):
    with pytest.raises(SunsetError, match="^t "):
        trace_direct(small_default, t)


def test_sigma_is_the_camera_parameter(small_default):
    coarse = replace(small_default, camera=replace(small_default.camera, sigma=2.0))
    i1, i2 = {}, {}
    trace_direct(coarse, 0.0, info=i1)
    trace_direct(small_default, 0.0, info=i2)
    # eight times as many samples (up to the rounding of the nearest one)
    assert i2["sea_samples"] == pytest.approx(8 * i1["sea_samples"], abs=8 * 2)
