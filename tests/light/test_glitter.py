"""The sun's glitter off a wind sea's unresolved facets (sunset/light/glitter.py).

References: a Monte Carlo sea of facets (slopes drawn from the Gaussian, the
sun's ray reflected off each, the reflected power binned by direction), the
tile's own FFT slopes sampled at random points, and the shading with the
glitter off.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from sunset.constants import SEA
from sunset.light.fresnel import reflectance
from sunset.light.glitter import Glitter, facet_variances, glitter_radiance, sun_irradiance
from sunset.light.render import frame_light
from sunset.light.shade import shade
from sunset.model.scene import Scene
from sunset.model.waves import Sea
from sunset.model.windsea import WindSea
from sunset.pipeline.rgb import trace_geometry


def test_the_glitter_is_what_a_monte_carlo_sea_of_facets_reflects():
    """Cox and Munk's L = ρ E p/(4 μ_v μ_h⁴) against reflecting the sun off a million random facets."""
    rng = np.random.default_rng(7)
    vu, vc, wind = 0.03, 0.015, 30.0
    a = math.radians(wind)
    zu, zc = rng.normal(0, math.sqrt(vu), 2_000_000), rng.normal(0, math.sqrt(vc), 2_000_000)
    zx, zy = zu * math.cos(a) - zc * math.sin(a), zu * math.sin(a) + zc * math.cos(a)
    nf = np.stack([-zx, -zy, np.ones_like(zx)], -1)
    nf /= np.linalg.norm(nf, axis=-1, keepdims=True)
    sun = np.array([0.0, math.cos(math.radians(20)), math.sin(math.radians(20))])
    cos_i = nf @ sun
    lit = cos_i > 0
    # per unit of mean-plane area a facet has area 1/n_z and intercepts E cos i of it
    power = np.where(lit, reflectance(cos_i) * cos_i / nf[:, 2], 0.0) / zx.size
    r = 2 * cos_i[:, None] * nf - sun                         # the sun's ray reflected, pointing away
    # bins in (azimuth, elevation) about three directions of view
    for az, el in ((-90.0, 20.0), (-80.0, 15.0), (-96.0, 27.0)):       # facing the sun: the glitter
        v = np.array([math.cos(math.radians(el)) * math.cos(math.radians(az)),
                      math.cos(math.radians(el)) * math.sin(math.radians(az)), math.sin(math.radians(el))])
        half = math.radians(1.0)
        r_el, r_az = np.arcsin(np.clip(r[:, 2], -1, 1)), np.arctan2(r[:, 1], r[:, 0])
        inside = (np.abs(r_el - math.radians(el)) < half) & (np.abs(r_az - math.radians(az)) < half) & lit
        omega = 2 * half * (math.sin(math.radians(el) + half) - math.sin(math.radians(el) - half))
        mc = power[inside].sum() / (omega * v[2])             # radiance: per solid angle per projected area
        want = glitter_radiance(-v[None, :], np.array([[0.0, 0.0, 1.0]]), sun, np.ones(3), vu, vc, wind)[0, 0]
        assert inside.sum() > 2000
        assert mc == pytest.approx(float(want), rel=0.06), (az, el, mc, want)


def test_a_tilted_patch_spreads_the_glitter_about_its_own_normal():
    sun = np.array([0.0, 0.6, 0.8])
    n_flat = np.array([[0.0, 0.0, 1.0]])
    d = -sun * np.array([-1, -1, 1])                          # the mirror view of the sun off a flat patch
    d = (d / np.linalg.norm(d))[None, :]
    flat = glitter_radiance(d, n_flat, sun, np.ones(3), 0.01, 0.01, 90.0)[0, 0]
    tilt = np.array([[0.0, 0.3, 1.0]]) / math.hypot(0.3, 1.0)
    tilted = glitter_radiance(d, tilt, sun, np.ones(3), 0.01, 0.01, 90.0)[0, 0]
    assert flat > 30 * tilted > 0                             # off its peak by a slope of 0.3 = 3σ: e^-4.5
    assert glitter_radiance(d, n_flat, sun * np.array([1, 1, -1]), np.ones(3), 0.01, 0.01, 90.0)[0, 0] == 0


def wind_scene(speed=7.0, size=(64, 48)):
    ws = WindSea(speed, 270.0, math.inf, 1, 64, 128.0, 64.0)
    base = Scene.default().with_size(*size)
    return replace(base, sea=Sea(wind=ws), islands=(), camera=replace(base.camera, eye_height=5.0))


def test_the_facets_make_up_the_winds_slope_variance():
    """Resolved slopes as rendered (the tile's gradient, interpolated) plus the facets' = the wind's total."""
    ws = wind_scene().sea.wind
    rng = np.random.default_rng(1)
    x, y = rng.uniform(0, ws.tile_size, 200_000), rng.uniform(0, ws.tile_size, 200_000)
    su, sc = [], []
    d = math.radians(ws.direction)
    for t in (0.0, 13.0, 29.0, 41.0):
        _, zx, zy = ws.sample(x, y, t)
        su.append(np.mean((zx * math.cos(d) + zy * math.sin(d)) ** 2))
        sc.append(np.mean((-zx * math.sin(d) + zy * math.cos(d)) ** 2))
    fu, fc = facet_variances(ws)
    tu, tc = ws.total_slopes()
    # the tile is one random sea: its slope variance is the expected one within a few per cent
    assert np.mean(su) + fu == pytest.approx(tu, rel=0.05)
    assert np.mean(sc) + fc == pytest.approx(tc, rel=0.05)
    assert fu > np.mean(su) and fc > 0                       # most of the slope is below the grid


def test_a_wind_seas_sun_is_its_facets_glitter_not_a_mirrored_disk():
    scene = wind_scene()
    geometry = trace_geometry(scene, 3.0, 1)
    gl = geometry.glitter
    assert isinstance(gl, Glitter) and len(gl.index) > 1000
    light = frame_light(scene, 3.0, 0.35)
    with_glitter = shade(geometry, light).reshape(-1, 3)
    mirror = shade(replace(geometry, glitter=None), light).reshape(-1, 3)
    no_sun = shade(geometry, replace(light, sun_xyz=np.zeros(3))).reshape(-1, 3)
    sea = np.zeros(len(mirror), bool)
    sea[gl.index] = True
    np.testing.assert_array_equal(with_glitter[~sea], mirror[~sea])          # off the sea nothing changes
    glint = with_glitter[sea] - no_sun[sea]
    want = glitter_radiance(gl.view, gl.normal, light.sun_dir, sun_irradiance(light.sun_xyz, light.delta),
                            gl.var_upwind, gl.var_crosswind, gl.wind_direction)
    np.testing.assert_allclose(glint, want, rtol=1e-3, atol=1e-3 * float(want.max()))
    assert np.count_nonzero(glint[:, 1] > 0.01 * glint[:, 1].max()) > 20 * np.count_nonzero(
        mirror[sea, 1] - no_sun[sea, 1] > 0.01 * glint[:, 1].max())               # spread, not a few disk pixels


@pytest.mark.parametrize("compiled", [False, True])
def test_a_wind_seas_rgb_frame_is_the_same_bytes_on_any_number_of_threads(compiled):
    from sunset.kernels import use_compiled, use_threads
    from sunset.pipeline.rgb import render_rgb

    scene = wind_scene(size=(40, 32))
    out = []
    for n in (1, 2):
        with use_compiled(compiled), use_threads(n):
            out.append(render_rgb(scene, 5.0, 0.35).tobytes())
    assert out[0] == out[1]
