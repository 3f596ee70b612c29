"""The RGB back end: the frame's new fields, the mirror case by hand, no NaN, deferred shading."""

import math

import numpy as np
import pytest

import sunset
from sunset import kernels
from sunset.constants import SEA, SKY, WATER_REFRACTIVE_INDEX as N
from sunset.model.eye import spectrum_to_xyz as _spectrum_to_xyz
from sunset.model.sky import direct_irradiance, island_lighting, sky_radiance, spectral_data
from sunset.light import water
from sunset.light.geometry import Geometry
from sunset.light.lighting import Lighting
from sunset.light.render import frame_light, shade_display
from sunset.pipeline.rgb import render_rgb, trace_geometry
from sunset.light.shade import shade
from sunset.model.scene import Scene
from ..agree import assert_geometry_agrees


@pytest.fixture(scope="module")
def small():
    return Scene.default().with_size(48, 40)


def test_frame_records_each_bounce(small):
    f = sunset.render(small, 0.0, 2, sea_bounces=True)
    sea = f.surface == SEA
    inc, rays = f.incidence, f.sea_rays
    assert inc.dtype == np.float32 and inc.shape == f.shape + (2,) and rays.shape == f.shape + (2, 3)
    assert np.all(np.isfinite(inc[sea, 0])) and np.all(np.isnan(inc[~sea]))
    np.testing.assert_array_equal(np.isfinite(inc[..., 1]), f.bounces == 2)
    assert np.all(np.abs(inc[sea, 0]) <= 1)          # < 0 where a sampled hit sees a wave from behind
    # the first bounce: R₁ = D − 2(D·N)N and cos i = −D·N
    d, n = f.direction[sea].astype(float), f.normal[sea].astype(float)
    np.testing.assert_allclose(inc[sea, 0], -np.sum(d * n, 1), atol=1e-6)
    np.testing.assert_allclose(rays[sea, 0], d - 2 * np.sum(d * n, 1)[:, None] * n, atol=1e-6)
    # the final ray is the last bounce's, with |R_z|
    one = sea & (f.bounces == 1)
    last = np.where((f.bounces == 2)[..., None], rays[..., 1, :], rays[..., 0, :])
    np.testing.assert_allclose(f.ray[sea], np.abs(last[sea]) * [0, 0, 1] + last[sea] * [1, 1, 0], atol=1e-6)
    assert one.any() and (f.bounces == 2).any()


def test_the_new_fields_change_no_code(small):
    f = sunset.render(small, 0.0, 2, sea_bounces=True)
    codes = sunset.encode(small, f)
    f.incidence[:] = 0.123
    f.sea_rays[:] = np.nan
    np.testing.assert_array_equal(sunset.encode(small, f), codes)


def test_compiled_and_numpy_paths_record_the_same_bounces(small):
    # within the vector stage's tolerances (tests/agree.py): the same bounces, their rays and cosines close
    with kernels.use_compiled(False):
        a = sunset.render(small, 0.7, 2, sea_bounces=True)
    b = sunset.render(small, 0.7, 2, sea_bounces=True)
    np.testing.assert_array_equal(np.isnan(a.incidence), np.isnan(b.incidence))
    assert_geometry_agrees(a, b)


def angle_fresnel(i):
    t = math.asin(math.sin(i) / N)
    return 0.5 * ((math.sin(i - t) / math.sin(i + t)) ** 2 + (math.tan(i - t) / math.tan(i + t)) ** 2)


def test_still_sea_is_a_mirror_computed_by_hand():
    """A still sea pixel: F(i) L_sky(R) + (1 − F)/n² (water), every term computed here from the models."""
    scene = Scene.default().still().with_size(40, 40)
    hours = 1.2
    f = sunset.render(scene, 0.0, 1, sea_bounces=True)
    light = Lighting.for_hour(scene.sun, hours)
    xyz = shade(Geometry.from_frame(f), light)
    p = scene.sun.position(hours)
    sp = spectral_data()
    omega = water.single_scattering_albedo(sp.wavelengths)
    rows, cols = np.nonzero((f.surface == SEA) & (f.final_surface == SKY))
    checked = 0
    for r, c in list(zip(rows, cols))[:: max(1, len(rows) // 12)]:
        d = f.direction[r, c].astype(float)
        mirror = d * [1, 1, -1]
        if mirror @ p > math.cos(scene.sun.delta):
            continue
        i = math.acos(-d[2])
        big_f = angle_fresnel(i)
        sky = _spectrum_to_xyz(sky_radiance(mirror[None], p))[0]
        # the water: the eye's ray refracted by the flat sea, reversed
        sin_t = math.sin(i) / N
        horiz = d[:2] / np.linalg.norm(d[:2])
        u = np.array([-horiz[0] * sin_t, -horiz[1] * sin_t, math.sqrt(1 - sin_t**2)])
        mu_s = p[2]
        sin_ts = math.sqrt(1 - mu_s**2) / N
        ph = p[:2] / np.linalg.norm(p[:2])
        beam = np.array([-ph[0] * sin_ts, -ph[1] * sin_ts, -math.sqrt(1 - sin_ts**2)])
        cos_psi = beam @ u
        phase = (1 + 0.835 * cos_psi**2) / (4 * math.pi * (1 + 0.835 / 3))
        e_sun = _spectrum_to_xyz(omega * direct_irradiance(p, scene.sun.delta) * mu_s * (1 - angle_fresnel(math.acos(mu_s))))
        up_sun = e_sun * phase / (math.sqrt(1 - sin_ts**2) + u[2])
        diffuse = island_lighting(p, scene.sun.delta)[1]
        e_sky = _spectrum_to_xyz(omega * diffuse * (1 - water.diffuse_reflectance()))
        up_sky = e_sky / (4 * math.pi) / (water.diffuse_mean_cosine() + u[2])
        want = big_f * sky + (1 - big_f) / N**2 * (up_sun + up_sky)
        np.testing.assert_allclose(xyz[r, c], want, rtol=0.01)
        checked += 1
    assert checked >= 8


def test_sky_grid_against_the_model_per_direction():
    rng = np.random.default_rng(5)
    sun = Scene.default().sun
    for hours in (2.0, 0.3, 0.02):
        light = Lighting.for_hour(sun, hours)
        d = rng.normal(size=(300, 3))
        d[:, 2] = np.abs(d[:, 2]) * rng.choice([0.05, 1.0], 300)      # many near the horizon
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        want = _spectrum_to_xyz(sky_radiance(d, light.sun_dir))
        got = light.sky(d)
        rel = np.abs(got[:, 1] - want[:, 1]) / want[:, 1]
        # the worst: low in the Earth's shadow at twilight, a thousand times darker than near the sun
        assert np.percentile(rel, 95) < 0.025 and rel.max() < 0.08
        assert np.max(np.abs(got - want)) < 0.01 * want.max()


@pytest.mark.parametrize("seed", range(4))
def test_no_nan_over_random_scenes(seed):
    rng = np.random.default_rng(seed)
    base = Scene.default()
    sun = sunset.Sun(azimuth=float(rng.uniform(-60, 60)), tilt=float(rng.uniform(10, 90)),
                     radius=float(rng.uniform(0.2, 2.0)))
    cam = base.camera.with_size(int(rng.integers(8, 40)), int(rng.integers(8, 40)))
    scene = Scene(camera=cam, sun=sun, sea=base.sea if seed % 2 else base.sea.__class__(()), islands=base.islands)
    hours = float(rng.uniform(-0.5, 6.0))
    for refl in (0, 1, 2):
        img = render_rgb(scene, t=float(rng.uniform(0, 10)), hours=hours, samples=(1, 4)[seed % 2],
                         reflections=refl)
        assert img.shape == (cam.height, cam.width, 3)
        assert np.all(np.isfinite(img)) and img.min() >= 0 and img.max() <= 1


def test_deferred_shading_is_a_fresh_render(small):
    """One stored geometry shaded at two hours equals rendering afresh at each (the light of the frame: the hour's,
    and the ripples the waves throw on the islands' shores at that time and hour)."""
    g = trace_geometry(small, 0.4, 2)
    for hours in (3.0, 0.2):
        light = frame_light(small, 0.4, hours)
        assert light.extra_irradiance                      # the shores' light, on by default
        np.testing.assert_array_equal(shade_display(g, light), render_rgb(small, 0.4, hours))


def test_extra_layers_and_irradiance_are_applied(small):
    g = trace_geometry(small, 0.0, 2)
    light = Lighting.for_hour(small.sun, 1.0)
    base = shade(g, light)
    light.extra_sky.append(lambda d, xyz: xyz * 0.5)
    light.extra_irradiance.append(lambda pts, nrm, part: np.full(nrm.shape, 1e-3, nrm.dtype))
    other = shade(g, light)
    sky = (g.final_kind == SKY).reshape(g.shape)
    isl = (g.final_kind > 0).reshape(g.shape)
    direct_sky = sky & (g.throughput.reshape(g.shape) == 1)
    np.testing.assert_allclose(other[direct_sky], 0.5 * base[direct_sky], rtol=1e-6)
    assert np.all(other[isl] > base[isl])


@pytest.mark.parametrize("name", ["carlas-island-clouds"])
def test_scenes_with_clouds_and_posts_shade_without_nan(name):
    from sunset.model.scene import load_named_scene

    scene = load_named_scene(name).with_size(40, 36)
    img = render_rgb(scene, 0.0, 0.3, samples=1)
    assert np.all(np.isfinite(img)) and img.min() >= 0 and img.max() <= 1
    assert np.all(img.max(axis=-1) > 0)                 # no pixel left unshaded (black)


def test_posts_are_shaded_as_wood():
    from dataclasses import replace

    from sunset.constants import POST
    from sunset.model.posts import Post
    from sunset.model.scene import load_named_scene

    scene = replace(load_named_scene("carlas-island").with_size(72, 64),
                    posts=(Post(x=-1.5, y=14.0, radius=0.25, top=2.5, depth=3.0),))
    frame = sunset.render(scene, 0.3, 2, sea_bounces=True)
    post = frame.final_surface == POST
    assert post.any()
    g = Geometry.from_frame(frame)
    assert np.all(g.final_kind.reshape(frame.shape)[post] == 2)
    xyz = shade(g, Lighting.for_hour(scene.sun, 1.0))
    assert np.all(np.isfinite(xyz)) and np.all(xyz[post].sum(axis=-1) > 0)
