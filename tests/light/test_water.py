"""The single-scattering water model against numerical integration and the literature's own checks."""

import math

import numpy as np
import pytest

from sunset.constants import WATER_REFRACTIVE_INDEX as N
from sunset.light import water
from sunset.light.fresnel import reflectance


def test_absorption_minimum_is_pope_and_frys():
    """Pope & Fry's abstract: the minimum is 0.0044 ± 0.0006 m⁻¹ near 418 nm."""
    lam = np.arange(380, 781, 1.0)
    a = water.absorption(lam)
    assert 410 <= lam[np.argmin(a)] <= 430
    assert 0.0038 <= a.min() <= 0.0050
    assert len(water.ABSORPTION) == len(water.ABSORPTION_NM)
    assert np.all(np.diff(water.ABSORPTION[water.ABSORPTION_NM.index(450):water.ABSORPTION_NM.index(760)]) > 0)


def test_scattering_and_albedo():
    assert water.scattering(500.0) == pytest.approx(0.00288)
    assert water.scattering(400.0) / water.scattering(600.0) == pytest.approx(1.5 ** 4.32)
    w = water.single_scattering_albedo(np.arange(380, 781, 10))
    assert np.all((w > 0) & (w < 0.6))
    assert np.argmax(w) <= 6                    # bluest light is scattered most: the water is blue


def test_phase_is_normalised():
    mu = np.linspace(-1, 1, 20001)
    integral = 2 * math.pi * np.trapezoid(water.phase(mu), mu)
    assert integral == pytest.approx(1.0, rel=1e-8)
    assert water.phase(0.0) == pytest.approx(0.06225, abs=5e-6)    # Morel's β(90°)/b = 1/16.06


def test_single_scattering_against_depth_integration():
    """ω p E'/(μ' + μ_u) against ∫ b p (E'/μ') e^(−cz/μ') e^(−cz/μ_u) dz/μ_u done numerically."""
    a, b = 0.03, 0.004
    c = a + b
    for mu_b, mu_u, cos_psi in [(0.9, 0.7, -0.5), (0.7, 0.2, 0.1), (0.99, 0.99, -0.98), (0.67, 0.05, 0.3)]:
        z = np.linspace(0, 4000.0, 400001)
        f = b * water.phase(cos_psi) / mu_b * np.exp(-c * z / mu_b - c * z / mu_u) / mu_u
        numeric = np.trapezoid(f, z)
        closed = b / c * water.upwelling(mu_u, mu_b, cos_psi)
        assert closed == pytest.approx(numeric, rel=2e-5)


def test_diffuse_reflectance_of_the_sea():
    """R̄ = ∫ R 2μ dμ: about 6.6 % for a uniform sky over water (Preisendorfer & Mobley 1986 give 0.066)."""
    theta = np.linspace(0, math.pi / 2, 200001)
    r = reflectance(np.cos(theta))
    numeric = np.trapezoid(r * 2 * np.cos(theta) * np.sin(theta), theta)
    assert water.diffuse_reflectance() == pytest.approx(numeric, rel=1e-5)
    assert water.diffuse_reflectance() == pytest.approx(0.066, abs=0.002)


def test_mean_cosine_in_the_water():
    """μ̄ by integrating over the refracted cone in the water (the other variable of the module's integral)."""
    tc = math.asin(1 / N)
    t = np.linspace(0, tc, 200001)[:-1]
    mu_air = np.sqrt(np.clip(1 - (N * np.sin(t)) ** 2, 0, 1))
    lw = N * N * (1 - reflectance(mu_air))          # radiance in the water for unit sky radiance
    e = np.trapezoid(lw * np.cos(t) * np.sin(t), t)
    e0 = np.trapezoid(lw * np.sin(t), t)
    assert water.diffuse_mean_cosine() == pytest.approx(e / e0, rel=1e-4)
    assert 0.8 < water.diffuse_mean_cosine() < 0.9


@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_shapes(shape):
    assert np.shape(water.upwelling(np.full(shape, 0.5), 0.8, np.full(shape, 0.1))) == shape
    assert np.shape(water.refracted_cosine(np.full(shape, 0.5))) == shape


#: The 10 nm rows of a published transcription of Pope & Fry (1997), Table 3 (m⁻¹), with Smith & Baker (1981)
#: beyond 727.5 nm: data/pope97.dat of github.com/cilori/primary_production_satellite (commit 8a326a5).
POPE97_TRANSCRIPTION = {
    380: 0.01137, 390: 0.00851, 400: 0.00663, 410: 0.00473, 420: 0.00454, 430: 0.00495, 440: 0.00635,
    450: 0.00922, 460: 0.00979, 470: 0.0106, 480: 0.0127, 490: 0.015, 500: 0.0204, 510: 0.0325, 520: 0.0409,
    530: 0.0434, 540: 0.0474, 550: 0.0565, 560: 0.0619, 570: 0.0695, 580: 0.0896, 590: 0.1351, 600: 0.2224,
    610: 0.2644, 620: 0.2755, 630: 0.2916, 640: 0.3108, 650: 0.34, 660: 0.41, 670: 0.439, 680: 0.465,
    690: 0.516, 700: 0.624, 710: 0.827, 720: 1.231, 730: 1.799, 740: 2.38, 750: 2.47, 760: 2.55, 770: 2.51,
    780: 2.36,
}


def test_absorption_is_the_published_table_value_by_value():
    assert tuple(POPE97_TRANSCRIPTION) == water.ABSORPTION_NM
    np.testing.assert_array_equal(water.ABSORPTION, tuple(POPE97_TRANSCRIPTION.values()))
    np.testing.assert_array_equal(water.absorption(list(POPE97_TRANSCRIPTION)), list(POPE97_TRANSCRIPTION.values()))
