"""How a wind sea's energy spreads over directions: D(k, φ), ∫ D dφ = 1.

φ is the direction a component travels, measured from the wind's. The
directional spectrum is Ψ(k, φ) = S(k) D(k, φ)/k per unit area of the
wavenumber plane (∫∫ Ψ k dk dφ = m₀). Two spreading functions:

* ``"mitsuyasu"``: cos-2s, D = G(s) cos^{2s}(φ/2), G(s) = 2^{2s−1} Γ(s+1)²/(π Γ(2s+1)),
  with Mitsuyasu et al.'s (1975) s(ω) = s_p (ω/ω_p)⁵ below the peak and
  s_p (ω/ω_p)^−2.5 above it, s_p = 11.5 Ω^−2.5 (Ω = U₁₀ω_p/g). Waves run
  downwind, narrowly at the peak, almost isotropically far above it (where
  the fit was never measured).
* ``"elfouhaily"``: D = (1 + Δ(k) cos 2φ)/(2π), Δ = tanh(a₀ + a_p (c/c_p)^2.5 +
  a_m (c_m/c)^2.5), a₀ = ln 2/4, a_p = 4, a_m = 0.13 u*/c_m (Elfouhaily et
  al. 1997), built with Cox and Munk's upwind/crosswind ratio.
  It is centrosymmetric (it describes a snapshot); the tile folds it onto the
  downwind half, D(φ) + D(φ + π) for |φ| < 90°, so that its waves run
  downwind. Folding leaves every second moment of the heights and slopes as it was.

The slope variances along and across the wind need only the mean of cos 2φ:
⟨cos²φ⟩ = (1 + ⟨cos 2φ⟩)/2, with ⟨cos 2φ⟩ = s(s − 1)/((s + 1)(s + 2)) for
cos-2s and Δ/2 for Elfouhaily et al.'s.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import gammaln

from ..errors import SunsetError
from .spectrum import ECKV_CM, WindSpectrum

#: The spreading functions a wind sea may name.
SPREADINGS = ("mitsuyasu", "elfouhaily")
#: Mitsuyasu et al. (1975): s_p = MITSUYASU_SP Ω^MITSUYASU_SP_EXP, and the exponents of s(ω) below and above ω_p.
MITSUYASU_SP, MITSUYASU_SP_EXP = 11.5, -2.5
MITSUYASU_LOW, MITSUYASU_HIGH = 5.0, -2.5


def check_spreading(name: str) -> None:
    if name not in SPREADINGS:
        raise SunsetError(f"spreading must be one of {', '.join(repr(s) for s in SPREADINGS)}, got {name!r}")


def mitsuyasu_s(spectrum: WindSpectrum, k):
    """s(ω(k)) of cos-2s spreading (Mitsuyasu et al. 1975)."""
    ratio = np.sqrt(spectrum.gravity * np.asarray(k, dtype=float)) / spectrum.peak_frequency
    sp = MITSUYASU_SP * spectrum.inverse_wave_age ** MITSUYASU_SP_EXP
    with np.errstate(divide="ignore"):
        return sp * np.where(ratio <= 1.0, ratio ** MITSUYASU_LOW, ratio ** MITSUYASU_HIGH)


def elfouhaily_delta(spectrum: WindSpectrum, k):
    """Δ(k) of Elfouhaily et al.'s spreading, in [0, 1)."""
    c = spectrum.phase_speed(np.asarray(k, dtype=float))
    cp = spectrum.gravity / spectrum.peak_frequency
    am = 0.13 * spectrum.friction_velocity / ECKV_CM
    return np.tanh(math.log(2.0) / 4.0 + 4.0 * (c / cp) ** 2.5 + am * (ECKV_CM / c) ** 2.5)


def mean_cos2(name: str, spectrum: WindSpectrum, k):
    """⟨cos 2φ⟩ over D(k, ·) (the same folded or not)."""
    check_spreading(name)
    if name == "mitsuyasu":
        s = mitsuyasu_s(spectrum, k)
        return s * (s - 1.0) / ((s + 1.0) * (s + 2.0))
    return 0.5 * elfouhaily_delta(spectrum, k)


def density(name: str, spectrum: WindSpectrum, k, phi):
    """D(k, φ), rad⁻¹, for travel at φ radians from the wind (downwind-folded for Elfouhaily et al.'s).

    ``k`` and ``phi`` broadcast; ∫ D dφ over (−π, π] is 1 for every k.
    """
    check_spreading(name)
    k = np.asarray(k, dtype=float)
    phi = np.remainder(np.asarray(phi, dtype=float) + math.pi, 2.0 * math.pi) - math.pi   # in [−π, π)
    if name == "mitsuyasu":
        s = mitsuyasu_s(spectrum, k)
        log_g = (2.0 * s - 1.0) * math.log(2.0) + 2.0 * gammaln(s + 1.0) - math.log(math.pi) - gammaln(2.0 * s + 1.0)
        c = np.abs(np.cos(0.5 * phi))
        with np.errstate(divide="ignore"):
            return np.exp(log_g + 2.0 * s * np.log(c))
    delta = elfouhaily_delta(spectrum, k)
    side = np.abs(phi) - 0.5 * math.pi                      # < 0 downwind, 0 across, > 0 upwind
    fold = np.where(side < 0, 2.0, np.where(side == 0, 1.0, 0.0))
    return fold * (1.0 + delta * np.cos(2.0 * phi)) / (2.0 * math.pi)


def slope_variances(name: str, spectrum: WindSpectrum, k_lo: float | None = None,
                    k_hi: float | None = None) -> tuple[float, float]:
    """(⟨z_u²⟩, ⟨z_c²⟩): slope variances along (upwind) and across the wind, from k_lo to k_hi.

    ⟨z_u²⟩ = ∫ k² S(k) (1 + ⟨cos 2φ⟩)/2 dk and ⟨z_c²⟩ with (1 − ⟨cos 2φ⟩)/2;
    the defaults integrate from below the peak to the capillary cutoff.
    """
    k = spectrum.grid(k_lo, k_hi)
    b = k ** 3 * spectrum(k)
    c2 = mean_cos2(name, spectrum, k)
    lk = np.log(k)
    return float(np.trapezoid(b * 0.5 * (1.0 + c2), lk)), float(np.trapezoid(b * 0.5 * (1.0 - c2), lk))
