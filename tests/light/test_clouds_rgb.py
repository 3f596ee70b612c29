"""Clouds and ripples in the RGB back end (sunset/light: geometry, lighting, shade, ripples.ripple_source)."""

import numpy as np
import pytest

from sunset.constants import CLOUD, POST, SKY
from sunset.light.geometry import Geometry
from sunset.light.lighting import Lighting
from sunset.light.render import frame_light
from sunset.pipeline.rgb import trace_geometry
from sunset.light.ripples import ripple_source, texture_lookup
from sunset.light.shade import shade
from sunset.model.clouds import cloud_radiance
from sunset.model.eye import spectrum_to_xyz
from sunset.model.scene import load_named_scene
from sunset.pipeline.frame import render


@pytest.fixture(scope="module")
def cloudy():
    return load_named_scene("carlas-island-clouds").with_size(72, 64)


@pytest.fixture(scope="module")
def frame(cloudy):
    return render(cloudy, 0.0, 2, sea_bounces=True)


def test_geometry_keeps_the_depth_of_the_cloud_each_sky_ray_ends_on(frame):
    g = Geometry.from_frame(frame)
    final = frame.final_surface.reshape(-1)[g.sky_index]
    assert np.all(np.isin(final, [SKY, CLOUD]))
    np.testing.assert_array_equal(np.isfinite(g.sky_cloud), final == CLOUD)
    np.testing.assert_array_equal(g.sky_cloud[final == CLOUD],
                                  frame.cloud_depth.reshape(-1)[g.sky_index][final == CLOUD])
    assert (final == CLOUD).sum() > 50


def test_the_light_tabulates_the_cloud_radiance_of_the_model(cloudy):
    light = Lighting.for_scene(cloudy, 0.5)
    d = np.array([-200.0, 13.0, 95.5])
    want = spectrum_to_xyz(cloud_radiance(d, light.sun_dir, cloudy.clouds, light.delta))
    np.testing.assert_allclose(light.cloud(d), want, rtol=0.01)
    assert Lighting.for_scene(load_named_scene("carlas-island"), 0.5).cloud_xyz is None


def test_a_cloud_pixel_is_the_clouds_light_and_hides_the_sun(cloudy, frame):
    g = Geometry.from_frame(frame)
    light = Lighting.for_scene(cloudy, 0.28)                # the sun behind a cloud at this hour
    xyz = shade(g, light).reshape(-1, 3)
    direct = (frame.surface.reshape(-1) == CLOUD)
    np.testing.assert_allclose(xyz[direct], light.cloud(frame.cloud_depth.reshape(-1)[direct]), rtol=1e-6)
    # without the clouds in the light the same pixels see the sky (and where the sun is, the sun)
    plain = shade(g, Lighting.for_hour(cloudy.sun, 0.28)).reshape(-1, 3)
    assert not np.allclose(plain[direct], xyz[direct])
    not_cloud = ~np.isin(frame.final_surface.reshape(-1), [CLOUD])
    np.testing.assert_array_equal(plain[not_cloud], xyz[not_cloud])


def test_the_ripples_add_the_texture_times_the_direct_light_on_wood_only_on_the_post():
    scene = load_named_scene("post-in-the-swell").with_size(96, 96)
    g = trace_geometry(scene, 0.0, 2)
    base = Lighting.for_scene(scene, 1.0)
    bare = shade(g, base).reshape(-1, 3)
    light = frame_light(scene, 0.0, 1.0)
    lit = shade(g, light).reshape(-1, 3)
    source = light.extra_irradiance[0]
    post = scene.posts[0]
    points = g.island_point + np.array([0.0, 0.0, scene.camera.eye_height])
    e = texture_lookup(source.textures[0], post, points)
    extra = np.zeros_like(bare)
    extra[g.island_index] = e[:, None] * base.island_direct[2]
    frame = render(scene, 0.0, 2, sea_bounces=True)
    on = frame.surface.reshape(-1) == POST
    assert on.sum() > 100 and e.max() > 0
    np.testing.assert_allclose(lit[on], bare[on] + extra[on], rtol=1e-5, atol=1e-9)
    np.testing.assert_array_equal(lit[~on & (frame.final_surface.reshape(-1) != POST)],
                                  bare[~on & (frame.final_surface.reshape(-1) != POST)])


def test_texture_lookup_reads_texel_centres_exactly_and_nothing_off_the_post():
    scene = load_named_scene("post-in-the-swell")
    post = scene.posts[0]
    source = ripple_source(scene, 0.0, 1.0, Lighting.for_scene(scene, 1.0), texels=8, cell=0.2)
    tex = source.textures[0]
    i, j = 5, 3
    p = np.array([[post.x + post.radius * np.cos(tex.phi[i]), post.y + post.radius * np.sin(tex.phi[i]), tex.z[j]]])
    assert texture_lookup(tex, post, p)[0] == pytest.approx(tex.above[j, i], rel=1e-9)
    assert texture_lookup(tex, post, p + np.array([0.5, 0.0, 0.0]))[0] == 0.0
