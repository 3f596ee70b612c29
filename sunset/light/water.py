"""The colour of the water: light scattered up out of a deep, clear sea.

A steep ray does not only see the sky reflected in the water (Fresnel's R);
the fraction 1 − R enters the sea, and what the eye then receives is the
light that the water body scatters back up along that refracted ray. This
module is a documented single-scattering model of that light for a deep,
homogeneous sea of clear (pure) sea water.

The model
---------
Below a flat surface, a beam of sunlight travels down along s' (cosine μ'
with the downward vertical, Snell's law) carrying, across a horizontal
plane, the irradiance E'_h = (1 − R(μ_s)) μ_s E_sun that the surface let in.
Water attenuates it with the beam attenuation c = a + b (absorption a,
scattering b, both m⁻¹). A volume element at depth z scatters the fraction
b p(ψ) dΩ per unit length into the direction u (cosine μ_u with the upward
vertical), ψ the angle between s' and u, p the phase function (∫p dΩ = 1).
Adding up single scatterings along the upward ray, attenuated on the way,

    L_u(u) = ∫₀^∞ b p(ψ) (E'_h/μ') e^(−cz/μ') e^(−cz/μ_u) dz/μ_u
           = ω p(ψ) E'_h / (μ' + μ_u),          ω = b/c,

the single-scattering albedo. Through the surface the radiance is divided
by n² (the n²-law of radiance) and multiplied by the transmittance 1 − R of
the eye's ray, so the water leaves with L_w = (1 − R) L_u / n².

The spectrum enters only through ω(λ) and the light's own spectrum: the
geometry factor p(ψ)/(μ' + μ_u) is the same at every wavelength, so the
colour of the water is one XYZ vector per hour, times a per-pixel scalar.
That is what makes deferred shading of the sea cheap (:mod:`sunset.light.shade`).

Skylight enters too: the diffuse horizontal irradiance E_d of the sky, let in
with the diffuse transmittance 1 − R̄ (R̄ = ∫ R(μ) 2μ dμ over a uniform sky,
:func:`diffuse_reflectance`), is treated as one beam at the mean cosine μ̄ of
refracted uniform skylight (:func:`diffuse_mean_cosine`) with an isotropic
phase function 1/4π (the molecular phase function averaged over the cone of
refracted skylight).

What is left out, and why it matters little or not
--------------------------------------------------
* multiple scattering: clear water absorbs so little in the violet and blue
  that ω = b/(a + b) reaches about 0.59 at 410 nm (and falls below 0.1 beyond
  500 nm, :func:`single_scattering_albedo`), so there the second and later
  orders of scattering add light this model leaves out: the water it renders
  is somewhat too dark in the blue, never the wrong hue;
* particles, phytoplankton, dissolved organic matter ("clear" sea water);
* the bottom (the sea is deep) and the waves' tilt for the sunlight entering
  the water (the sun's beam is refracted by the mean surface; the eye's ray
  by the facet it meets);
* polarisation (R is the unpolarised reflectance).

Data, each number's source
--------------------------
* absorption a_w(λ) of pure water, 380–720 nm: Pope & Fry (1997), Table 3,
  at 10 nm; 730–780 nm: Smith & Baker (1981), Table 1 (Pope & Fry end at
  727.5 nm). Salt changes the absorption of water in the visible by less than
  the measurement's uncertainty, so it serves for sea water (Pope & Fry 1997).
  Checked value by value, all 41 of them, against a published transcription of
  Pope & Fry's table (every 2.5 nm, in m⁻¹, with Smith & Baker's values beyond
  727.5 nm): ``data/pope97.dat`` of the GitHub repository
  cilori/primary_production_satellite (commit 8a326a5), headed "R. M. Pope and
  E. S. Fry, Absorption spectrum (380–700 nm) of pure water. II. Integrating
  cavity measurements, Appl. Opt. 36, 8710–8723 (1997)"; the values agree to
  the last digit given (``tests/light/test_water.py`` holds a copy
  of that file's 10 nm rows). That is a check against a copy of the
  paper's table, not against the paper itself, which was not at hand;
* scattering of pure sea water (35–39 ‰): b_sw(λ) = 0.00288 m⁻¹ (λ/500 nm)^−4.32,
  Morel (1974), as tabulated by Smith & Baker (1981) and Mobley (1994, Table 3.8);
* its phase function p(ψ) = (1 + 0.835 cos²ψ)/(4π (1 + 0.835/3)) =
  0.06225 (1 + 0.835 cos²ψ), the depolarisation δ = 0.09 of Morel (1974)
  giving 0.835 = (1 − δ)/(1 + δ) (Mobley 1994, eq. 3.30).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..constants import WATER_REFRACTIVE_INDEX
from .fresnel import reflectance

__all__ = [
    "ABSORPTION_NM", "ABSORPTION", "SCATTERING_500", "SCATTERING_EXPONENT", "PHASE_ANISOTROPY",
    "absorption", "scattering", "single_scattering_albedo", "phase", "diffuse_reflectance",
    "diffuse_mean_cosine", "upwelling", "refracted_cosine",
]

#: Wavelengths (nm) of :data:`ABSORPTION`.
ABSORPTION_NM = tuple(range(380, 781, 10))

#: Absorption coefficient of pure water, m⁻¹: Pope & Fry (1997), Table 3, 380–720 nm;
#: Smith & Baker (1981), Table 1, 730–780 nm.
ABSORPTION = (
    0.01137, 0.00851, 0.00663, 0.00473, 0.00454, 0.00495, 0.00635, 0.00922, 0.00979, 0.01060,   # 380–470
    0.01270, 0.01500, 0.02040, 0.03250, 0.04090, 0.04340, 0.04740, 0.05650, 0.06190, 0.06950,   # 480–570
    0.08960, 0.1351, 0.2224, 0.2644, 0.2755, 0.2916, 0.3108, 0.3400, 0.4100, 0.4390,            # 580–670
    0.4650, 0.5160, 0.6240, 0.8270, 1.2310,                                                     # 680–720
    1.799, 2.38, 2.47, 2.55, 2.51, 2.36,                                                        # 730–780
)

#: Scattering coefficient of pure sea water at 500 nm, m⁻¹, and its spectral exponent (Morel 1974).
SCATTERING_500 = 0.00288
SCATTERING_EXPONENT = 4.32

#: The molecular phase function's cos² coefficient, (1 − δ)/(1 + δ) with depolarisation δ = 0.09 (Morel 1974).
PHASE_ANISOTROPY = 0.835


def absorption(wavelengths) -> np.ndarray:
    """a_w(λ), m⁻¹, linearly interpolated in the table (λ in nm, 380–780)."""
    return np.interp(np.asarray(wavelengths, dtype=float), ABSORPTION_NM, ABSORPTION)


def scattering(wavelengths) -> np.ndarray:
    """b_sw(λ) = 0.00288 (λ/500)^−4.32 m⁻¹ (Morel 1974), λ in nm."""
    return SCATTERING_500 * (np.asarray(wavelengths, dtype=float) / 500.0) ** (-SCATTERING_EXPONENT)


def single_scattering_albedo(wavelengths) -> np.ndarray:
    """ω = b/(a + b) of clear sea water."""
    a = absorption(wavelengths)
    b = scattering(wavelengths)
    return b / (a + b)


def phase(cos_psi) -> np.ndarray:
    """p(ψ) = (1 + 0.835 cos²ψ) / (4π (1 + 0.835/3)), sr⁻¹; ∫ p dΩ = 1."""
    c = np.asarray(cos_psi)
    return (1.0 + PHASE_ANISOTROPY * c * c) * (1.0 / (4.0 * math.pi * (1.0 + PHASE_ANISOTROPY / 3.0)))


def refracted_cosine(mu, n: float = WATER_REFRACTIVE_INDEX):
    """cos t = √(1 − (1 − μ²)/n²) of a ray entering water at cos i = μ."""
    mu = np.clip(np.asarray(mu, dtype=float), 0.0, 1.0)
    return np.sqrt(1.0 - (1.0 - mu * mu) / (n * n))


@functools.lru_cache(maxsize=None)
def _diffuse(n: float, samples: int = 4096) -> tuple[float, float]:
    mu = (np.arange(samples) + 0.5) / samples            # midpoint rule in μ
    t = 1.0 - reflectance(mu, n)
    r_bar = float(np.sum(reflectance(mu, n) * 2.0 * mu) / samples)
    # planar over scalar irradiance of the refracted light (dΩ_w = dΩ μ/(n² μ'), L_w = n² L T)
    mean = float(np.sum(t * mu) / np.sum(t * mu / refracted_cosine(mu, n)))
    return r_bar, mean


def diffuse_reflectance(n: float = WATER_REFRACTIVE_INDEX) -> float:
    """R̄ = ∫₀¹ R(μ) 2μ dμ: the fraction of a uniform sky's irradiance the flat sea reflects."""
    return _diffuse(float(n))[0]


def diffuse_mean_cosine(n: float = WATER_REFRACTIVE_INDEX) -> float:
    """μ̄: planar over scalar irradiance of uniform skylight refracted into the water."""
    return _diffuse(float(n))[1]


def upwelling(mu_up, mu_beam, cos_psi=None) -> np.ndarray:
    """The geometry factor p(ψ)/(μ' + μ_u) of single-scattered light, sr⁻¹.

    Multiplied by ω(λ) E'_h(λ) it is the radiance L_u just below the surface
    (module docstring). ``cos_psi`` None takes the isotropic phase 1/4π (skylight).

    Parameters
    ----------
    mu_up : array_like
        μ_u, cosine of the upward in-water ray with the vertical (clipped at 0).
    mu_beam : float or array_like
        μ', cosine of the downward beam with the downward vertical.
    cos_psi : array_like, optional
        Cosine of the scattering angle between the beam and the upward ray.
    """
    mu_up = np.maximum(np.asarray(mu_up), 0.0)
    p = 1.0 / (4.0 * math.pi) if cos_psi is None else phase(cos_psi)
    return p / (mu_beam + mu_up)
