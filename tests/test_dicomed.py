"""The film recorder stage (sunset/dicomed.py): physics, tables, passes, the sun's disk."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.stats import spearmanr

from sunset import dicomed
from sunset.camera import Camera
from sunset.codes import CODE_MAP, island_code_rho, sun_plane_angle, track_code_elevations
from sunset.constants import (AEROSOL_ALBEDO, AEROSOL_ASYMMETRY, EARTH_RADIUS, RAYLEIGH_SCALE_HEIGHT)
from sunset.dicomed import (expose, kasten_young_air_mass, ozone_air_mass, sky_radiance, slant_columns,
                            spectral_data, sun_colour, sun_coverage, sun_radiance, tables, tables_linear,
                            visible_fraction)
from sunset.errors import SunsetError
from sunset.io import png_bytes
from sunset.scene import Scene
from sunset.sun import Sun

SUN = Sun(azimuth=2.0, tilt=50.0, radius=0.75)


def sun_camera(sun, hours, half=0.05, size=64):
    """A camera whose window is centred on the sun's picture-plane position."""
    p = sun.position(hours)
    s, z = p[0] / p[1], p[2] / p[1]
    return Camera(width=size, height=size, s_min=s - half, s_max=s + half, zy_min=z - half, zy_max=z + half)


# --------------------------------------------------------------------------- air mass and columns
def test_kasten_young_air_mass():
    assert math.isclose(float(kasten_young_air_mass(math.pi / 2)), 1.0, abs_tol=1e-3)
    # plane-parallel 1/sin(e) holds well above the horizon
    for e in np.radians([30, 45, 60, 75]):
        assert math.isclose(float(kasten_young_air_mass(e)), 1 / math.sin(e), rel_tol=5e-3)
    # about 38 at the horizon, and clipped below it
    assert 37 < float(kasten_young_air_mass(0.0)) < 39
    assert float(kasten_young_air_mass(-0.1)) == float(kasten_young_air_mass(0.0))
    assert kasten_young_air_mass(np.zeros((2, 3, 1))).shape == (2, 3, 1)


def exact_column(e, H):
    """∫ exp(−h(s)/H) ds / H along a ray from sea level at elevation e (spherical Earth), by quadrature."""
    R = EARTH_RADIUS
    mu = math.sin(e)
    f = lambda s: math.exp(-(math.sqrt(R * R + 2 * R * mu * s + s * s) - R) / H) / H  # noqa: E731
    return quad(f, 0, 2e6, limit=400, points=[1e3, 1e4, 1e5, 3e5])[0]


@pytest.mark.parametrize("elev", [90.0, 30.0, 10.0, 3.0, 0.0])
def test_slant_column_against_quadrature(elev):
    e = math.radians(elev)
    col = slant_columns(0.0, math.sin(e), n=64)
    assert col.shape == (3,)
    assert math.isclose(float(col[0]), exact_column(e, RAYLEIGH_SCALE_HEIGHT), rel_tol=0.01)


def test_slant_column_tracks_kasten_young_and_komhyr():
    for elev in (60.0, 20.0, 10.0, 5.0):
        e = math.radians(elev)
        col = slant_columns(0.0, math.sin(e))
        assert math.isclose(float(col[0]), float(kasten_young_air_mass(e)), rel_tol=0.03)
        assert math.isclose(float(col[2]), float(ozone_air_mass(e)), rel_tol=0.04)


def test_a_ray_through_the_earth_is_opaque_and_the_shadow_is_gradual():
    # from 2 km up, rays dipping ever further below the horizontal
    mus = -np.linspace(0.0, 0.1, 50)
    cols = slant_columns(2000.0, mus)
    assert np.all(np.diff(cols[:, 0]) > 0)          # ever longer, ever denser paths
    assert np.all(np.isfinite(cols))
    trans = np.exp(-(cols @ spectral_data().tau))   # (50, λ)
    assert np.all(trans[-1] < 1e-12)                # through the ground: no light at all
    assert np.all(np.diff(trans[:, -1]) <= 0)


def test_visible_fraction_of_a_setting_disk():
    d = 0.01
    assert float(visible_fraction(2 * d, d)) == 1.0
    assert float(visible_fraction(-2 * d, d)) == 0.0
    assert math.isclose(float(visible_fraction(0.0, d)), 0.5)
    # against the area of a circular segment, computed by quadrature
    for x in (-0.7, -0.2, 0.4, 0.9):
        area = quad(lambda y: 2 * math.sqrt(max(0.0, 1 - y * y)), -x, 1)[0] / math.pi
        assert math.isclose(float(visible_fraction(x * d, d)), area, rel_tol=1e-6)


# --------------------------------------------------------------------------- the sky
def test_sky_at_zenith_with_the_sun_overhead_matches_the_closed_form():
    """View and sun both vertical: every scattered photon crosses the whole column once.

    L = E₀ e^(−τ_total) Σ_species ω P(0) τ, exactly (plane-parallel limit).
    """
    sp = spectral_data()
    up = np.array([[0.0, 0.0, 1.0]])
    L = sky_radiance(up, up[0], n_view=400, n_sun=64)[0]
    g = AEROSOL_ASYMMETRY
    p_r = 3 / (16 * math.pi) * 2
    p_a = (1 - g * g) / (4 * math.pi * (1 - g) ** 3)
    expect = sp.sun * np.exp(-sp.tau.sum(0)) * (sp.tau[0] * p_r + AEROSOL_ALBEDO * sp.tau[1] * p_a)
    np.testing.assert_allclose(L, expect, rtol=0.01)


def test_sky_is_symmetric_about_the_suns_vertical_and_bluer_overhead():
    e = math.radians(20)
    p = np.array([0.0, math.cos(e), math.sin(e)])
    a = math.radians(40)
    dirs = np.array([[math.sin(a) * 0.9, math.cos(a) * 0.9, math.sqrt(1 - 0.81)],
                     [-math.sin(a) * 0.9, math.cos(a) * 0.9, math.sqrt(1 - 0.81)],
                     [0.0, -math.cos(0.02), math.sin(0.02)], [0.0, 0.0, 1.0]])
    L = sky_radiance(dirs, p)
    np.testing.assert_allclose(L[0], L[1], rtol=1e-10)
    lam = spectral_data().wavelengths
    blue, red = lam == 450, lam == 650
    assert L[3][blue] / L[3][red] > L[2][blue] / L[2][red]      # zenith bluer than the horizon
    assert sky_radiance(dirs[:1], p).shape == (1, len(lam))


def test_the_sun_reddens_as_it_sets():
    lam = spectral_data().wavelengths
    ratios = [float(sun_radiance(math.radians(e), SUN.delta)[lam == 650][0] /
                    sun_radiance(math.radians(e), SUN.delta)[lam == 450][0]) for e in (60, 20, 5, 1, 0)]
    assert np.all(np.diff(ratios) > 0)
    # a larger disk spreads the same sunlight: lower radiance
    assert np.all(sun_radiance(0.3, 0.02) < sun_radiance(0.3, 0.01))


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


# --------------------------------------------------------------------------- the sun's disk
def test_sun_coverage_area_and_extent():
    hours = 0.5
    cam = sun_camera(SUN, hours, size=96)
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    assert cov.min() >= 0 and cov.max() == 1
    ds, dz = cam.pixel_pitch
    p = SUN.position(hours)
    # gnomonic area of a small cap of radius δ seen at angle α off the axis: π tan²δ / cos³α
    cos_a = p[1]
    expect = math.pi * math.tan(SUN.delta) ** 2 / cos_a**3
    assert math.isclose(cov.sum() * ds * dz, expect, rel_tol=0.01)


def test_sun_coverage_is_monotone_towards_the_rim():
    hours = 0.5
    cam = sun_camera(SUN, hours, half=0.03, size=128)
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    full = np.zeros((cam.height, cam.width))
    full[rows, cols] = cov
    r = cam.height // 2
    row = full[r]
    c = int(np.argmax(row))
    assert np.all(np.diff(row[c:]) <= 0) and np.all(np.diff(row[:c + 1]) >= 0)
    assert 0 < row.min() or row[0] == 0
    partial = (full > 0) & (full < 1)
    assert partial.any()                               # an anti-aliased rim


def test_sun_coverage_stops_at_the_horizon():
    hours = 0.0                                         # the sun's centre on the horizon
    cam = sun_camera(SUN, hours, size=80)
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    full = np.zeros((cam.height, cam.width))
    full[rows, cols] = cov
    zc = cam.zy_centres()
    dz = cam.pixel_pitch[1]
    assert np.all(full[zc + dz / 2 <= 0] == 0)
    assert full[zc - dz / 2 >= 0].max() == 1
    # about half of the disk is left
    p = SUN.position(hours)
    half = 0.5 * math.pi * math.tan(SUN.delta) ** 2 / p[1] ** 3
    assert math.isclose(full.sum() * cam.pixel_pitch[0] * dz, half, rel_tol=0.03)


def test_sun_out_of_view_or_behind():
    cam = Camera(width=16, height=16)
    rows, cols, cov = sun_coverage(cam, SUN, 4.5)       # high in the sky, above the window
    assert cov.size == 0 or cov.max() == 0
    behind = Sun(azimuth=180.0, tilt=40.0, radius=0.75)
    assert sun_coverage(cam, behind, 0.5)[2].size == 0


def test_sun_disk_rule_in_expose():
    hours = 0.5
    cam = sun_camera(SUN, hours, size=64)
    scene = Scene(camera=cam, sun=SUN)
    sky_code = CODE_MAP.sky.start + 5
    hill_code = CODE_MAP.hill.start + 3
    codes = np.full((64, 64), sky_code, np.uint8)
    codes[32:, 32:] = hill_code                          # an island covering one quarter
    rgb = expose(scene, codes, hours)
    t = tables(SUN, hours)
    sun_byte = np.rint(255 * dicomed._encode(sun_colour(SUN, hours))).astype(int)
    # the pixel at the sun's centre (a sky pixel) is sun colour
    c = cam.to_pixel(*(SUN.position(hours)[[0, 2]] / SUN.position(hours)[1]))
    cx, cy = int(round(c[0])), int(round(c[1]))
    cy -= 2                                              # stay in the sky quarter
    assert np.array_equal(rgb[cy, cx - 3].astype(int), sun_byte)
    # far away: the table's sky colour; the island quarter: the hill entry, never the sun
    assert np.array_equal(rgb[0, 0], t[:, sky_code])
    assert np.all(rgb[32:, 32:] == t[:, hill_code])
    # rim pixels lie between the two colours
    rows, cols, cov = sun_coverage(cam, SUN, hours)
    full = np.zeros((64, 64))
    full[rows, cols] = cov
    rim = (full > 0.2) & (full < 0.8) & (codes == sky_code)
    assert rim.any()
    lo = np.minimum(sun_byte, t[:, sky_code].astype(int))
    hi = np.maximum(sun_byte, t[:, sky_code].astype(int))
    assert np.all((rgb[rim] >= lo - 1) & (rgb[rim] <= hi + 1))
    assert not np.any(np.all(rgb[rim] == t[:, sky_code], axis=-1))


def test_expose_passes_and_determinism():
    scene = Scene(camera=Camera(width=40, height=30), sun=SUN)
    rng = np.random.default_rng(0)
    codes = rng.integers(0, 256, size=(30, 40), dtype=np.uint8)
    a = expose(scene, codes, 1.5)
    t = tables(SUN, 1.5)
    # with the sun out of this window, each pass is a pure table look-up
    for k in range(3):
        assert np.array_equal(a[..., k], t[k][codes])
    b = expose(scene, codes.copy(), 1.5)
    assert a.dtype == np.uint8 and a.shape == (30, 40, 3)
    assert png_bytes(a) == png_bytes(b)


def test_expose_rejects_bad_codes():
    scene = Scene(camera=Camera(width=8, height=6), sun=SUN)
    with pytest.raises(SunsetError, match="uint8"):
        expose(scene, np.zeros((6, 8), np.int32), 1.0)
    with pytest.raises(SunsetError, match="shape"):
        expose(scene, np.zeros((8, 6), np.uint8), 1.0)


# --------------------------------------------------------------------------- skylight and the eye
def test_irradiance_quadrature_against_closed_forms():
    from sunset.dicomed import _sphere, irradiance

    dirs, d_omega = _sphere()
    assert math.isclose(d_omega.sum(), 4 * math.pi, rel_tol=1e-12)
    rng = np.random.default_rng(5)
    n = rng.normal(size=(2, 3, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    # a uniform field of radiance 1 gives π on every surface
    e = irradiance(n, dirs, np.ones((len(dirs), 2)), d_omega)
    assert e.shape == (2, 3, 2)
    np.testing.assert_allclose(e, math.pi, rtol=0.02)
    # a cosine lobe L = max(ω·a, 0) gives 2π/3 on the surface facing a, 0 facing away
    a = np.array([0.0, 0.0, 1.0])
    lobe = np.clip(dirs @ a, 0, None)[:, None]
    assert math.isclose(float(irradiance(a, dirs, lobe, d_omega)[0]), 2 * math.pi / 3, rel_tol=0.02)
    assert float(irradiance(-a, dirs, lobe, d_omega)[0]) == 0.0


def test_fresnel_reflectance_of_water():
    from sunset.constants import WATER_REFRACTIVE_INDEX as n
    from sunset.dicomed import fresnel_reflectance

    assert math.isclose(float(fresnel_reflectance(1.0)), ((n - 1) / (n + 1)) ** 2, rel_tol=1e-12)
    assert math.isclose(float(fresnel_reflectance(0.0)), 1.0, rel_tol=1e-12)
    # at Brewster's angle the p-polarised part vanishes: R = R_s / 2
    b = math.atan(n)
    ct = math.cos(math.asin(math.sin(b) / n))
    rs = ((math.cos(b) - n * ct) / (math.cos(b) + n * ct)) ** 2
    assert math.isclose(float(fresnel_reflectance(math.cos(b))), rs / 2, rel_tol=1e-9)
    r = fresnel_reflectance(np.linspace(0, 1, 50))
    assert np.all(np.diff(r) < 0)
    assert fresnel_reflectance(np.zeros((2, 3, 1))).shape == (2, 3, 1)


def test_island_normals_keep_the_code_angle_and_face_up():
    from sunset.dicomed import island_normals

    psi = np.linspace(0, 2 * math.pi, 40, endpoint=False)
    n, w = island_normals(SUN, psi)
    assert n.shape == (40, 12, 3) and w.shape == (40, 12)
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-12)
    got = np.mod(np.arctan2(n @ SUN.V, n @ SUN.U), 2 * math.pi)
    np.testing.assert_allclose(np.cos(got - psi[:, None]), 1.0, atol=1e-9)
    np.testing.assert_allclose(w.sum(axis=1), 1.0)
    assert np.all(n[..., 2][w > 0] > 0)


def test_eye_response():
    from sunset.constants import EYE_RESPONSE_EXPONENT as n, EYE_SEMI_SATURATION as sigma
    from sunset.dicomed import eye_response

    assert math.isclose(float(eye_response(sigma)), 0.5)
    x = np.logspace(-4, 3, 50)
    y = eye_response(x)
    assert np.all(np.diff(y) > 0) and np.all((y >= 0) & (y < 1))
    # far below σ it is the power law (x/σ)^n: a luminance ratio r becomes r^n
    small = eye_response(np.array([1e-12, 3e-12]))
    assert math.isclose(small[1] / small[0], 3.0**n, rel_tol=1e-4)
    assert eye_response(np.zeros((2, 3, 1))).shape == (2, 3, 1)


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
    from sunset.codes import sky_code_z

    tab = tables(Scene.default().sun, 0.35).astype(int)
    z = sky_code_z(CODE_MAP.sky.size)
    inside = np.nonzero(z < math.sin(math.radians(10)))[0] + CODE_MAP.sky.start
    assert np.ptp(tab[:, inside], axis=1).max() > 10
