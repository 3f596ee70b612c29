"""The colour tables (sunset/recorder/colour_tables.py): bytes, smoothness, islands, glitter, hours."""

import math

import numpy as np
import pytest
from scipy.stats import spearmanr

from sunset.model.camera import Camera
from sunset.tape.codes import CODE_MAP, island_code_rho, sun_plane_angle, track_code_elevations
from sunset.pipeline.frame import expose
from sunset.recorder.colour_tables import sun_colour, tables, tables_linear
from sunset.errors import SunsetError
from sunset.model.scene import Scene
from sunset.model.sun import Sun


SUN = Sun(azimuth=2.0, tilt=50.0, radius=0.75)


# --------------------------------------------------------------------------- the tables
HOURS = [-0.6, -0.2, 0.0, 0.1, 0.35, 0.8, 1.5, 3.0, 4.5, 6.0]


@pytest.mark.parametrize("hours", HOURS)
def test_tables_are_bytes_in_range(hours):
    t = tables(SUN, hours)
    assert t.shape == (3, 256) and t.dtype == np.uint8
    assert not t.flags.writeable
    lin = tables_linear(SUN, hours)
    assert lin.shape == (3, 256)
    assert np.all(np.isfinite(lin)) and lin.min() >= 0.0 and lin.max() <= 1.0
    # the bytes are the sRGB encoding of the linear values
    enc = np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * lin ** (1 / 2.4) - 0.055)
    assert np.max(np.abs(np.rint(enc * 255) - t)) <= 1


def test_tables_vary_smoothly_with_the_hour():
    """No jumps: the change between tables shrinks with the step in hours."""
    for h in np.linspace(-0.5, 5.0, 12):
        base = tables(SUN, h).astype(int)
        big = np.abs(tables(SUN, h + 1e-3).astype(int) - base).max()
        small = np.abs(tables(SUN, h + 1e-4).astype(int) - base).max()
        assert big <= 16, (h, big)
        assert small <= 2, (h, small)


@pytest.mark.parametrize("hours", [0.2, 0.8, 2.0, 4.5])
def test_islands_lit_and_shadowed_by_rho_against_sin_theta(hours):
    theta = hours * math.pi / 12
    lin = tables_linear(SUN, hours)
    lum = lin.T @ np.array([0.2126, 0.7152, 0.0722])
    for rg in CODE_MAP.islands:
        B = rg.size / 4
        rh = island_code_rho(rg.size)
        # whole dither interval (±1/B) lit, or whole interval in shadow (band sin θ .. 2 + sin θ)
        lit = (rh + 1 / B < math.sin(theta)) | (rh - 1 / B > 2 + math.sin(theta))
        dark = (rh - 1 / B > math.sin(theta)) & (rh + 1 / B < 2 + math.sin(theta))
        part = lum[rg.start:rg.stop]
        assert lit.any() and dark.any()
        assert part[lit].min() > part[dark].max()
        # shadow: skylight only, which varies with the normal far less than sunlight does
        assert np.ptp(part[dark]) < 0.5 * (part[lit].min() - part[dark].max()) + 0.5 * np.ptp(part[lit])
        # the brightest code is the one at ρ̂ = sin(θ − π/2) (N along the sun, within one code)
        k = int(np.argmax(part))
        assert abs(rh[k] - math.sin(theta - math.pi / 2)) <= 1.5 / B
        # and brightness follows cos(θ − ψ) of the code's centre
        psi = sun_plane_angle(rh[lit])
        # (in rank: the eye's response is compressive, and skylight, which varies with the
        # normal too, competes with the low sun's weak beam near sunset)
        assert spearmanr(np.cos(theta - psi), part[lit])[0] > (0.95 if hours >= 2 else 0.8)


@pytest.mark.parametrize("hours", [0.05, 0.3, 1.0, 2.5, 4.5])
def test_glitter_entries_along_the_track(hours):
    lin = tables_linear(SUN, hours)
    sun_lin = sun_colour(SUN, hours)
    track = lin[:, CODE_MAP.track.start:CODE_MAP.track.stop].T
    is_sun = np.all(np.abs(track - sun_lin) < 1e-12, axis=1)
    assert is_sun.any()                                     # at least one entry is sun colour
    e = track_code_elevations(CODE_MAP.track.size, SUN)
    e_sun = math.asin(SUN.position(hours)[2])
    k = int(np.argmin(np.abs(e - e_sun)))
    assert is_sun[k]                                        # the one at the sun's height
    # neighbours of the sun-coloured run are intermediate, and far entries are not sun colour
    run = np.nonzero(is_sun)[0]
    far = np.abs(e - e_sun) > 4 * max(SUN.delta, e[1] - e[0])
    assert far.any() and not is_sun[far].any()
    for j in (run[0] - 1, run[-1] + 1):
        if 0 <= j < len(e) and not far[j]:
            assert not is_sun[j]


def test_glitter_moves_down_the_track_as_the_sun_sets():
    e = track_code_elevations(CODE_MAP.track.size, SUN)
    heights = []
    for hours in (3.0, 2.0, 1.0, 0.5, 0.2):
        track = tables_linear(SUN, hours)[:, CODE_MAP.track.start:CODE_MAP.track.stop].T
        heights.append(e[np.all(np.abs(track - sun_colour(SUN, hours)) < 1e-12, axis=1)].mean())
    assert np.all(np.diff(heights) < 0)


def test_sky_gets_darker_after_sunset():
    sky = slice(CODE_MAP.sky.start, CODE_MAP.sky.stop)
    lum = [tables_linear(SUN, h)[:, sky].sum() for h in (0.5, 0.0, -0.3, -1.0)]
    assert np.all(np.diff(lum) < 0)


def test_bad_hours():
    with pytest.raises(SunsetError, match="hours"):
        tables(SUN, float("nan"))
    with pytest.raises(SunsetError, match="hours"):
        expose(Scene(camera=Camera(width=4, height=4)), np.zeros((4, 4), np.uint8), float("inf"))


def test_islands_in_shadow_are_dimly_visible_at_sunset():
    """Near sunset, the shadowed island codes are dark but well above black, and below the sky."""
    sun = Scene.default().sun
    lin = tables_linear(sun, 0.35)
    lum = lin.T @ np.array([0.2126, 0.7152, 0.0722])
    sky = lum[CODE_MAP.sky.start:CODE_MAP.sky.start + 10].mean()
    for rg in CODE_MAP.islands:
        part = lum[rg.start:rg.stop]
        assert 0.01 < part.min() < 0.3 * sky


def test_sky_grades_with_height_at_sunset():
    """The sky codes in the picture (0–10°) differ visibly: more than 10 levels in some pass."""
    from sunset.tape.codes import sky_code_z

    tab = tables(Scene.default().sun, 0.35).astype(int)
    z = sky_code_z(CODE_MAP.sky.size)
    inside = np.nonzero(z < math.sin(math.radians(10)))[0] + CODE_MAP.sky.start
    assert np.ptp(tab[:, inside], axis=1).max() > 10


# --------------------------------------------------------------------------- the same bytes, computed plainly
def plain_tables_linear(sun, hours, clouds=None):
    """The tables one code range at a time, every direction integrated and every weight recomputed.

    What :func:`sunset.recorder.colour_tables._tables_linear` computed before it
    integrated each distinct direction once, kept the hour-independent
    geometry and took the film's response to all codes at once.
    """
    from sunset.model import sky
    from sunset.model.clouds import cloud_radiance
    from sunset.model.eye import exposure_key, film_response
    from sunset.recorder.colour_tables import _axis_direction, _island_factors, glitter_weights
    from sunset.tape.codes import CLOUDY_CODE_MAP, cloud_code_depths, sky_code_z

    cmap = CLOUDY_CODE_MAP if clouds is not None else CODE_MAP
    theta = float(Sun.theta(hours))
    p = sun.position(hours)
    out = np.zeros((256, 3))
    z = sky_code_z(cmap.sky.size)
    sky_dirs = np.stack([np.zeros_like(z), np.cos(np.arcsin(z)), z], axis=-1)
    dirs = np.concatenate([sky_dirs, _axis_direction(track_code_elevations(cmap.track.size, sun)),
                           _axis_direction(track_code_elevations(cmap.halo.size, sun))])
    key = exposure_key(p)
    lin = film_response(sky.sky_radiance(dirs, p), key)
    n1, n2 = cmap.sky.size, cmap.sky.size + cmap.track.size
    sun_lin = film_response(sky.sun_radiance(sky.elevation(p), sun.delta), key)
    wts = glitter_weights(sun, hours)
    a = wts[cmap.track.start:cmap.track.stop, None]
    b = wts[cmap.halo.start:cmap.halo.stop, None]
    out[cmap.sky.start:cmap.sky.stop] = lin[:n1]
    out[cmap.track.start:cmap.track.stop] = (1 - a) * lin[n1:n2] + a * sun_lin
    out[cmap.halo.start:cmap.halo.stop] = (1 - b) * lin[n2:] + b * sun_lin
    direct = sky.direct_irradiance(p, sun.delta)
    dirs_m, d_omega = sky.dome_directions()
    up = sky.sky_radiance(dirs_m[:len(dirs_m) // 2], p)           # the dome, integrated afresh
    dome = (dirs_m, np.concatenate([up, sky.fresnel_reflectance(dirs_m[:len(up), 2])[:, None] * up]), d_omega)
    sp = sky.spectral_data()
    for rng, name in zip(cmap.islands, ("hill", "cliff", "beach")):
        f = _island_factors(theta, rng.size)[:, None]
        normals, w = sky.island_normals(sun, sun_plane_angle(island_code_rho(rng.size)))
        cos_beta = (w * np.hypot(normals @ sun.U, normals @ sun.V)).sum(axis=1)[:, None]
        skylight = np.einsum("kj,kjl->kl", w, sky.irradiance(normals, *dome))
        out[rng.start:rng.stop] = film_response(sp.reflectance[name] * (direct * cos_beta * f + skylight) / math.pi,
                                                key)
    if clouds is not None:
        depth = cloud_code_depths(cmap.cloud.size, clouds.max_top, clouds.max_bottom)
        out[cmap.cloud.start:cmap.cloud.stop] = film_response(cloud_radiance(depth, p, clouds, sun.delta), key)
    return out, sun_lin


@pytest.mark.parametrize("scene", ["carlas-island", "carlas-island-clouds", "still-lake-at-noon"])
def test_the_tables_are_the_plain_computations_bytes(scene):
    from sunset.recorder.colour_tables import _tables_linear

    sc = Scene.named(scene)
    for hours in (1.5, 0.62, 0.05, -0.25, 4.0):
        got, got_sun = _tables_linear(sc.sun, hours, sc.clouds)
        want, want_sun = plain_tables_linear(sc.sun, hours, sc.clouds)
        assert np.array_equal(got.view(np.uint8), want.view(np.uint8)), hours
        assert np.array_equal(np.asarray(got_sun).view(np.uint8), np.asarray(want_sun).view(np.uint8)), hours
