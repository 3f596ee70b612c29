"""The wind sea's scan line (sunset/vector/windsea_scan.py and its Numba twin).

References: the tile's exact spectral sum (OceanTile.exact, a direct sum of
every component's complex exponential), the independent brute-force ray
caster (sunset/vector/bruteforce.py) marching the same interpolated surface,
and a one-component tile whose bound is known in closed form.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset.constants import SEA
from sunset.kernels import AGREE_POINT, use_compiled, use_threads
from sunset.model.ocean import OceanTile
from sunset.model.scene import Scene
from sunset.model.waves import Sea
from sunset.model.windsea import WindSea
from sunset.pipeline.frame import trace_direct
from sunset.vector.bruteforce import compare, trace_direct_bruteforce
from sunset.vector.heightfield import sampling
from sunset.vector.windsea_scan import wind_columns, wind_gradient_on_scanlines, wind_profile


def wind_scene(width=48, height=40, oversample=1, **wind):
    ws = WindSea(**{**dict(speed=7.0, direction=260.0, fetch=math.inf, seed=1, tile_points=64, tile_size=128.0,
                           cycle=64.0), **wind})
    base = Scene.default().with_size(width, height)
    scene = replace(base, sea=Sea(wind=ws), islands=(), camera=replace(base.camera, eye_height=5.0))
    if oversample > 1:
        object.__setattr__(ws, "tile", ws.make_tile(oversample))     # the cached tile, oversampled
    return scene


@pytest.fixture(scope="module")
def scene():
    return wind_scene()


def test_the_profile_is_the_tiles_interpolant_within_its_stated_error(scene):
    """g·y + h against the exact spectral sum at every sample: within the stated bound, rms as predicted."""
    sea, cam = scene.sea, scene.camera
    h = cam.eye_height
    tile = sea.wind.tile
    u = sampling(cam, sea.max_elevation).u()
    s = np.linspace(cam.s_min, cam.s_max, 9)
    g = wind_profile(sea, s, u, h, 5.0).astype(float)
    y = 1.0 / u
    exact = tile.exact(s[:, None] * y[None, :], np.broadcast_to(y, (s.size, y.size)), 5.0)[0]
    err = g / u[None, :] + h - exact
    stated = tile.interpolation_error()
    rounding = 1e-6 * h * np.max(y)                       # g is float32: |g|·2⁻²⁴ over u
    assert np.max(np.abs(err)) <= stated["max_z"] + rounding
    rms = math.sqrt(float(np.mean(err ** 2)))
    assert 0.5 < rms / stated["rms_z"] < 2.0, (rms, stated["rms_z"])
    # an oversampled grid (the same components) shrinks the error by about 16 (bilinear: second order)
    fine = sea.wind.make_tile(4)
    assert fine.interpolation_error()["rms_z"] < stated["rms_z"] / 10
    zf = fine.heights(s[:, None] * y[None, :], np.broadcast_to(y, (s.size, y.size)), 5.0)
    assert math.sqrt(float(np.mean((zf - exact) ** 2))) < rms / 10


def test_the_slopes_are_the_spectrums_gradient_within_its_stated_error(scene):
    tile = scene.sea.wind.tile
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-500, 500, 4000), rng.uniform(1, 900, 4000)
    s = x / y
    fx, fy = wind_gradient_on_scanlines(scene.sea, s, y, 7.0)
    _, ex, ey = tile.exact(s * y, y, 7.0)
    stated = tile.interpolation_error()
    for got, want, name in ((fx, ex, "rms_zx"), (fy, ey, "rms_zy")):
        rms = math.sqrt(float(np.mean((got - want) ** 2)))
        assert 0.5 < rms / stated[name] < 2.0, (name, rms, stated[name])
    # not the slope of the interpolated heights: that is constant along a cell's edge, this is not
    d = tile.spacing
    xs = np.linspace(0, d, 5)
    gx, _ = wind_gradient_on_scanlines(scene.sea, xs / 10.0, np.full(5, 10.0), 7.0)
    assert np.ptp(gx) > 0


def _scan_on_both_paths(scene) -> dict:
    """{compiled?: (tail, depth, surfaces)} of the scene's wind scan line at t = 3 s on each path."""
    sea, cam = scene.sea, scene.camera
    u = sampling(cam, sea.max_elevation).u()
    s = cam.s_centres()
    zeta = cam.zy_centres()[::-1]
    out = {}
    for on in (False, True):
        with use_compiled(on):
            bu, bs = np.zeros((s.size, cam.height)), np.zeros((s.size, cam.height), np.int8)
            tail = wind_columns(sea, s, u, cam.eye_height, 3.0, float(zeta[0]), cam.pixel_pitch[1], cam.height, bu, bs)
            out[on] = (tail, bu, bs)
    return out


def test_the_compiled_scan_line_agrees_with_the_reference(scene):
    out = _scan_on_both_paths(scene)
    assert out[True][0] == out[False][0]
    np.testing.assert_array_equal(out[True][2], out[False][2])
    assert (out[True][2] == SEA).mean() > 0.5
    np.testing.assert_allclose(out[True][1], out[False][1], rtol=AGREE_POINT, atol=0)


@pytest.mark.parametrize("compiled", [False, True])
def test_a_frame_of_a_wind_sea_is_the_same_bytes_on_any_number_of_threads(scene, compiled):
    frames = []
    for n in (1, 2):
        with use_compiled(compiled), use_threads(n):
            frames.append(trace_direct(scene, 2.0))
    for name in ("surface", "distance", "point", "normal"):
        assert getattr(frames[0], name).tobytes() == getattr(frames[1], name).tobytes(), name


@pytest.fixture(scope="module")
def brute(scene):
    return trace_direct_bruteforce(scene, 2.0)


def test_the_direct_rays_agree_with_the_brute_force_caster(scene, brute):
    """The σ-sampled scan line against marching every ray through the same interpolated surface."""
    frame = trace_direct(scene, 2.0)
    c = compare(frame, brute)
    # disagreements are rays that graze a crest between two samples near the horizon
    assert c["agree"] >= 0.99, c
    assert c["n_sea"] > 1000
    assert c["sea_median"] < 1e-4 and c["sea_normal_median"] < 0.1, c
    # where a pixel spans less than half the tile's grid spacing along y, the
    # scan line's samples (σ = 1/4 pixel apart) resolve every bilinear cell
    cam = scene.camera
    zeta = np.abs(cam.zy_centres())[:, None] * np.ones((1, cam.width))
    footprint = cam.eye_height / zeta * (cam.pixel_pitch[1] / zeta)
    near = (frame.surface == SEA) & (brute.surface == SEA) & (footprint < 0.5 * scene.sea.wind.tile.spacing)
    assert near.sum() > 300
    assert np.max(np.abs(frame.distance[near] / brute.distance[near] - 1)) < 2e-3


def test_every_time_bound_is_exact_for_one_component_and_bounds_a_cycle():
    n, size = 8, 16.0
    h0 = np.zeros((n, n), complex)
    h0[0, 1] = 0.3 - 0.4j                                  # one component, |h₀| = 0.5: z = 2·0.5 cos(…)
    tile = OceanTile(h0, size, 8.0)
    assert tile.bound_every_time == pytest.approx(1.0, rel=1e-12)
    assert 0.95 < max(tile.bound(t) for t in np.linspace(0, 8, 17)) <= 1.0 + 1e-12
    ws = WindSea(7.0, 30.0, math.inf, 4, 64, 128.0, 64.0)
    sea = Sea(wind=ws)
    grid_max = max(ws.tile.bound(t) for t in np.linspace(0, 64, 65))
    assert sea.max_elevation == ws.tile.bound_every_time
    assert grid_max <= sea.max_elevation < min(3 * grid_max, ws.tile.bound_all_times)
    assert ws.make_tile(2).bound_every_time >= ws.make_tile(2).bound(3.0)


@pytest.fixture(scope="module")
def choppy():
    return wind_scene(choppiness=0.8)


def test_the_compiled_choppy_scan_line_and_slopes_agree_with_the_reference(choppy):
    """λ > 0 on both paths: the same depth buffer (to AGREE_POINT) and the slopes to float32 roundings."""
    sea = choppy.sea
    out = _scan_on_both_paths(choppy)
    assert out[True][0] == out[False][0]
    np.testing.assert_array_equal(out[True][2], out[False][2])
    np.testing.assert_allclose(out[True][1], out[False][1], rtol=AGREE_POINT, atol=0)
    rng = np.random.default_rng(4)
    x, y = rng.uniform(-300, 300, 5000), rng.uniform(1, 600, 5000)
    with use_compiled(False):
        ref = wind_gradient_on_scanlines(sea, x / y, y, 3.0)
    with use_compiled(True):
        got = wind_gradient_on_scanlines(sea, x / y, y, 3.0)
    for a, b in zip(ref, got):
        np.testing.assert_allclose(b, a, rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("compiled", [False, True])
def test_a_choppy_frame_moves_the_sea_and_meets_the_displaced_surface(scene, choppy, compiled):
    """The choppy frame differs from λ = 0 on the sea, not above the horizon; its hits are the brute force's."""
    with use_compiled(compiled):
        flat, chop = trace_direct(scene, 2.0), trace_direct(choppy, 2.0)
    sea = (flat.surface == SEA) & (chop.surface == SEA)
    moved = np.abs(chop.distance[sea] / flat.distance[sea] - 1) > 1e-4
    assert moved.mean() > 0.5
    sky_rows = np.all(flat.surface != SEA, axis=1)
    assert sky_rows.any()
    np.testing.assert_array_equal(chop.surface[sky_rows], flat.surface[sky_rows])
    brute = trace_direct_bruteforce(choppy, 2.0)           # marches sea.elevation: the choppy map inverted
    c = compare(chop, brute)
    assert c["agree"] >= 0.99 and c["n_sea"] > 1000, c
    assert c["sea_median"] < 1e-4 and c["sea_normal_median"] < 0.1, c


@pytest.mark.parametrize("compiled", [False, True])
def test_a_wave_cycles_8bit_frame_of_a_wind_sea_has_the_tiles_normals(scene, compiled):
    """A wave cycle's frame (code_frame with its cycle pass: direct.sea_geometry and its twin) against render and encode.

    The compiled strip once took the trains' slopes of a wind sea (none: a flat mirror).
    """
    from sunset.pipeline.cycle import cycle_pass
    from sunset.pipeline.frame import code_frame, encode, render

    with use_compiled(compiled):
        still = cycle_pass(scene)
        codes = code_frame(scene, 2.0, 1, islands=still)
        ref = encode(scene, render(scene, 2.0, 1, sea_bounces=False), 0)
    assert np.mean(codes == ref) >= 0.99, np.mean(codes == ref)
