"""The physical sky (sunset/model/sky.py): air mass, columns, sky radiance, skylight, Fresnel."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from sunset.constants import (AEROSOL_ALBEDO, AEROSOL_ASYMMETRY, EARTH_RADIUS, RAYLEIGH_SCALE_HEIGHT)
from sunset.model.sky import kasten_young_air_mass, ozone_air_mass, sky_radiance, slant_columns, spectral_data, sun_radiance, visible_fraction
from sunset.model.sun import Sun


SUN = Sun(azimuth=2.0, tilt=50.0, radius=0.75)


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


# --------------------------------------------------------------------------- skylight and the eye
def test_irradiance_quadrature_against_closed_forms():
    from sunset.model.sky import _sphere, irradiance

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
    from sunset.model.sky import fresnel_reflectance

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
    from sunset.model.sky import island_normals

    psi = np.linspace(0, 2 * math.pi, 40, endpoint=False)
    n, w = island_normals(SUN, psi)
    assert n.shape == (40, 12, 3) and w.shape == (40, 12)
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-12)
    got = np.mod(np.arctan2(n @ SUN.V, n @ SUN.U), 2 * math.pi)
    np.testing.assert_allclose(np.cos(got - psi[:, None]), 1.0, atol=1e-9)
    np.testing.assert_allclose(w.sum(axis=1), 1.0)
    assert np.all(n[..., 2][w > 0] > 0)


# --------------------------------------------------------------------------- the spectra, from colour-science
def test_the_spectra_are_the_published_ones():
    """colour-science's spectra (imported by spectral_data) against the sources, computed or read here.

    The sun: Planck's law at 5778 K with CODATA's second radiation constant (colour-science takes ITS-90's
    1.4388e-2 m K: 3e-5 apart); the CMFs: the CIE 1931 2° table at 450, 550 and 600 nm; the Rayleigh depth:
    Bodhaine et al.'s (1999) fit, their eq. 30 (for 360 ppm of CO₂ where colour-science takes 300: 0.1 % apart).
    """
    from sunset.constants import SUN_TEMPERATURE

    sp = spectral_data()
    lam = sp.wavelengths * 1e-9
    planck = lam**-5 / np.expm1(1.438776877e-2 / (lam * SUN_TEMPERATURE))
    np.testing.assert_allclose(sp.sun, planck / planck.mean(), rtol=4e-5)
    at = {450: (0.33620, 0.038000, 1.772110), 550: (0.433450, 0.994950, 0.008750), 600: (1.062200, 0.631000, 0.000800)}
    for nm, xyz in at.items():
        np.testing.assert_allclose(sp.cmfs[sp.wavelengths == nm][0], xyz, atol=1e-6)
    um = sp.wavelengths / 1000.0
    fit = 0.0021520 * (1.0455996 - 341.29061 * um**-2 - 0.90230850 * um**2) / (1 + 0.0027059889 * um**-2
                                                                                 - 85.968563 * um**2)
    np.testing.assert_allclose(sp.tau[0], fit, rtol=1.5e-3)
    assert np.all((0.0 <= sp.reflectance["hill"]) & (sp.reflectance["hill"] <= 1.0))
    assert sp.reflectance["hill"][sp.wavelengths == 550] > sp.reflectance["hill"][sp.wavelengths == 450]  # green


def _colour_modules_after(code: str) -> list[str]:
    """The colour-science modules loaded in a fresh Python once it has run ``code``."""
    import subprocess
    import sys

    code += "\nimport sys\nprint(*sorted(m for m in sys.modules if m == 'colour' or m.startswith('colour.')))\n"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=600)
    return out.stdout.split()


def test_colour_science_is_imported_where_colour_is_computed_not_before():
    """``import sunset`` and the vector stage to the tape do not import colour-science; the colour tables do."""
    assert _colour_modules_after("import sunset") == []
    assert _colour_modules_after("import sunset\ns = sunset.Scene.default().with_size(32, 24)\n"
                                 "sunset.encode(s, sunset.render(s, 0.0))") == []
    assert "colour" in _colour_modules_after("import sunset\nfrom sunset.recorder.colour_tables import tables\n"
                                             "tables(sunset.Scene.default().sun, 0.35)")
