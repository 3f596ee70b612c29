"""Clouds in the vector stage (sunset/vector/clouds.py) against a brute-force ray march and closed forms."""

from dataclasses import replace

import numpy as np
import pytest

from sunset import kernels
from sunset.constants import CLOUD, SEA, SKY
from sunset.model.clouds import CloudCell, Clouds
from sunset.model.scene import load_named_scene
from sunset.model.waves import Sea
from sunset.pipeline.frame import encode, render
from sunset.tape.codes import CLOUDY_CODE_MAP, code_map
from sunset.vector.bruteforce import trace_clouds_bruteforce
from sunset.vector.clouds import cloud_scan

from ..agree import assert_codes_agree


@pytest.fixture(scope="module")
def cloudy():
    return load_named_scene("carlas-island-clouds").with_size(64, 48)


def scan_u(scene):
    return np.ascontiguousarray(cloud_scan(scene)[:, ::-1].T)


@pytest.fixture(scope="module")
def reference(cloudy):
    return trace_clouds_bruteforce(cloudy)


def test_scan_line_agrees_with_the_brute_force_march(cloudy, reference):
    u = scan_u(cloudy)
    sky_rows = cloudy.camera.zy_centres() > 0
    agree = (u > 0) == (reference > 0)
    assert agree[~sky_rows].all() and not (u[~sky_rows] > 0).any()   # no cloud below the horizon
    assert agree[sky_rows].mean() >= 0.99
    both = (u > 0) & (reference > 0)
    assert both.sum() > 200
    rel = np.abs(1 / u[both] - 1 / reference[both]) * reference[both]
    assert np.median(rel) < 5e-3          # 2.8e-3 measured at 64 × 48, σ = 1/4 (pixels are coarse here)


def test_the_error_falls_as_sigma_falls(cloudy, reference):
    med = []
    for sigma in (1.0, 0.25, 0.0625):
        u = scan_u(replace(cloudy, camera=replace(cloudy.camera, sigma=sigma)))
        both = (u > 0) & (reference > 0)
        med.append(np.median(np.abs(1 / u[both] - 1 / reference[both]) * reference[both]))
    assert med[0] > 2 * med[1] > 4 * med[2]


def test_a_flat_cloud_overhead_is_the_plane_of_its_base():
    """A very wide cell whose centre is far: near its middle the base is almost flat, z = Z − B."""
    cell = CloudCell(x=0.0, y=30000.0, a=1e6, b=1e6, top=10.0, bottom=100.0)
    scene = replace(load_named_scene("carlas-island").with_size(32, 40), clouds=Clouds(1000.0, (cell,)),
                    islands=())
    u = scan_u(scene)
    cam = scene.camera
    zeta = cam.zy_centres()[:, None] * np.ones((1, cam.width))
    up = zeta > 0
    assert (u[up] > 0).all()
    base = 1000.0 - 100.0 - cam.eye_height                           # B ≈ bottom·√q, q ≈ 1 near y = 30 km
    y = 1.0 / u[up]
    np.testing.assert_allclose(y * zeta[up], base, rtol=2e-3)


def test_render_puts_clouds_behind_islands_and_in_front_of_the_sky(cloudy):
    f = render(cloudy, 0.0, 2)
    cloud = f.surface == CLOUD
    assert cloud.any()
    assert np.all(np.isfinite(f.point[cloud])) and np.all(np.isnan(f.normal[cloud]))
    assert np.all(np.isfinite(f.cloud_depth[cloud]))
    plain = render(replace(cloudy, clouds=None), 0.0, 2)
    # clouds only ever replace sky or a farther island, never the sea
    assert np.all(plain.surface[cloud] != SEA)
    islands = plain.surface >= 1
    assert np.all(f.surface[islands & ~cloud] == plain.surface[islands & ~cloud])
    won = islands & cloud
    assert np.all(f.distance[won] < plain.distance[won])
    # depth is the mean level less the hit's height
    z = cloudy.camera.eye_height + f.point[cloud][:, 2]
    np.testing.assert_allclose(f.cloud_depth[cloud], cloudy.clouds.level - z, rtol=1e-5, atol=1e-2)


def test_reflected_rays_pierce_the_mean_level_in_closed_form():
    """Still water: the reflected ray of pixel (s, ζ < 0) is (s, 1, −ζ); it meets z = Z at y = (2h + Z − h)/|ζ|·…"""
    cell = CloudCell(x=0.0, y=40000.0, a=9000.0, b=20000.0, top=200.0, bottom=300.0)
    scene = replace(load_named_scene("carlas-island").with_size(40, 60), clouds=Clouds(1500.0, (cell,)),
                    islands=(), sea=Sea(()))
    f = render(scene, 0.0, 1)
    cam = scene.camera
    s = cam.s_centres()[None, :] * np.ones((cam.height, 1))
    zeta = cam.zy_centres()[:, None] * np.ones((1, cam.width))
    sea = zeta < 0
    h, Z = cam.eye_height, 1500.0
    # the ray reaches the sea at y = h/|ζ| and climbs back at slope |ζ|: z = Z at y = (h + Z − 0)/|ζ| − … from the eye
    y_cloud = (h + Z) / np.abs(zeta[sea])
    x_cloud = s[sea] * y_cloud
    T, B = scene.clouds.thickness(x_cloud, y_cloud)
    expect = T + B > 0
    got = f.final_surface[sea] == CLOUD
    assert got.sum() > 50 and (~got).sum() > 50
    assert np.mean(got == expect) > 0.995
    np.testing.assert_allclose(f.cloud_depth[sea][got & expect], B[got & expect], rtol=1e-3, atol=0.5)


def test_cloud_codes_and_both_kernel_paths(cloudy):
    with kernels.use_compiled(False):
        ref = render(cloudy, 0.4, 2)
        a = encode(cloudy, ref)
    with kernels.use_compiled(True):
        f = render(cloudy, 0.4, 2)
        b = encode(cloudy, f)
    assert_codes_agree(cloudy, ref, f, a, b, 0, "clouds")
    assert code_map(cloudy) is CLOUDY_CODE_MAP
    cloud = f.final_surface == CLOUD
    assert np.all(CLOUDY_CODE_MAP.cloud.contains(b[cloud])) and not np.any(CLOUDY_CODE_MAP.cloud.contains(b[~cloud]))
    # deeper clouds get higher codes (up to the dither)
    d = f.cloud_depth[cloud]
    c = b[cloud].astype(int)
    assert np.corrcoef(d, c)[0, 1] > 0.9
    assert np.all(f.final_surface != SEA) and set(np.unique(f.final_surface)) <= {CLOUD, SKY, 1, 2, 3}
