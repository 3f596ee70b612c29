"""The wind's sea as a spectrum: Pierson–Moskowitz, JONSWAP, and Elfouhaily et al.'s short waves.

The sea is a sum of very many small trains; its spectrum S(k) says how its
height variance is shared among wavenumbers, ∫ S(k) dk = m₀ = ⟨z²⟩, and its
significant wave height is H_s = 4√m₀. Spectra are written in the frequency
ω and carried to k by deep-water dispersion, ω² = g k:
S(k) = S(ω) dω/dk, dω/dk = g/(2ω).

The body of the spectrum, which holds its energy, is one of two published fits:

* fully developed (infinite fetch): Pierson and Moskowitz (1964),
  S(ω) = α g² ω⁻⁵ exp(−β (g/(U₁₉.₅ ω))⁴), α = 8.1·10⁻³, β = 0.74, whose peak is at
  ω_p = (4β/5)^¼ g/U₁₉.₅ = 0.877 g/U₁₉.₅ and whose H_s = 2√(α/β) U₁₉.₅²/g ≈ 0.21 U₁₉.₅²/g;
* fetch-limited: JONSWAP (Hasselmann et al. 1973),
  S(ω) = α g² ω⁻⁵ exp(−(5/4)(ω_p/ω)⁴) γ^r, r = exp(−(ω − ω_p)²/(2σ²ω_p²)),
  γ = 3.3, σ = 0.07 (ω ≤ ω_p) or 0.09, with the fetch F in x̃ = gF/U₁₀²:
  α = 0.076 x̃^−0.22 and ω_p = 2π · 3.5 x̃^−0.33 g/U₁₀. A fetch past the one at
  which this ω_p falls to Pierson and Moskowitz's no longer limits the sea: it
  is fully developed.

The ω⁻⁵ tail of either fit cannot be carried to the short waves that make
the sea's slopes: its slope variance ∫ k² S dk grows only as (α/2) ln k_c,
and no single cutoff k_c reproduces Cox and Munk's slopes at every wind (the
book's chapter "From trains to spectra" shows the table). Above the peak the
spectrum therefore hands over to the unified spectrum of Elfouhaily, Chapron,
Katsaros and Vandemark (1997, "ECKV"), built to reproduce Cox and Munk:
S_E(k) = k⁻³ (B_l + B_h), with the long-wave curvature
B_l = ½ α_p (c_p/c) L_PM J_p exp(−(Ω/√10)(√(k/k_p) − 1)) and the short-wave curvature
B_h = ½ α_m (c_m/c) L_PM exp(−¼ (k/k_m − 1)²) (c = √(g/k (1 + (k/k_m)²)),
c_m = 0.23 m s⁻¹, k_m = 370 rad m⁻¹, α_p = 6·10⁻³ Ω^0.55,
α_m = 10⁻² (1 + ln(u*/c_m)) for u* ≤ c_m, 10⁻² (1 + 3 ln(u*/c_m)) above, never
below 0), evaluated at the body's own inverse wave age Ω = U₁₀ ω_p/g and peak
k_p = ω_p²/g. The two are joined at ω = 2ω_p, k = 4k_p:

    S(k) = w S_body + (1 − w) S_E,    w = 1/(1 + (k/4k_p)⁴).

Slope integrals stop at the capillary cutoff k_c = 10 k_m (λ = 1.7 mm), past
which B_h holds less than 10⁻⁸ of the slope variance.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..constants import GRAVITY
from ..errors import SunsetError, require_range
from .wind import Wind

#: Pierson and Moskowitz (1964): Phillips' constant α and the shape constant β (with ω₀ = g/U₁₉.₅).
PM_ALPHA, PM_BETA = 8.1e-3, 0.74
#: Pierson and Moskowitz's published H_s = 0.21 U₁₉.₅²/g and ω_p = 0.877 g/U₁₉.₅ (Stewart 2008, eqs. 16.30, 16.33).
PM_HS, PM_PEAK = 0.21, 0.877
#: JONSWAP (Hasselmann et al. 1973): peak enhancement γ, peak widths σ below and above ω_p.
JONSWAP_GAMMA, JONSWAP_SIGMA_LOW, JONSWAP_SIGMA_HIGH = 3.3, 0.07, 0.09
#: JONSWAP's fetch laws in x̃ = gF/U₁₀²: α = 0.076 x̃^−0.22, f_p U₁₀/g = 3.5 x̃^−0.33, and the
#: energy law g² m₀/U₁₀⁴ = 1.6·10⁻⁷ x̃ (H_s = 1.6·10⁻³ √x̃ U₁₀²/g; Hasselmann et al. 1973).
JONSWAP_ALPHA, JONSWAP_ALPHA_EXP = 0.076, -0.22
JONSWAP_PEAK, JONSWAP_PEAK_EXP = 3.5, -0.33
JONSWAP_ENERGY = 1.6e-7
#: ECKV's short-wave constants: the minimum phase speed c_m (m s⁻¹) and its wavenumber k_m (rad m⁻¹).
ECKV_CM, ECKV_KM = 0.23, 370.0
#: The body hands over to ECKV at k = JOIN k_p (ω = 2ω_p), with w = 1/(1 + (k/(JOIN k_p))^JOIN_POWER).
JOIN, JOIN_POWER = 4.0, 4
#: Slope integrals stop at k_c = CUTOFF k_m (the capillary cutoff).
CUTOFF = 10.0
#: The shortest and longest fetch a wind sea accepts, metres (inf: fully developed).
MIN_FETCH, MAX_FETCH = 1.0e3, 1.0e7
#: Points per decade of the log-spaced quadrature of the spectrum's integrals.
QUAD_PER_DECADE = 400


@dataclass(frozen=True)
class WindSpectrum:
    """The omnidirectional wavenumber spectrum S(k) of a wind sea.

    Parameters
    ----------
    wind : Wind
        The wind (its speed at a stated height; see :mod:`sunset.model.wind`).
    fetch : float
        F, metres, over which the wind has blown, in [1 km, 10⁴ km], or
        ``math.inf`` for a fully developed sea (Pierson–Moskowitz).
    """

    wind: Wind
    fetch: float = math.inf

    def __post_init__(self):
        if not isinstance(self.wind, Wind):
            raise SunsetError(f"wind must be a Wind, got {self.wind!r}")
        if not (isinstance(self.fetch, (int, float)) and self.fetch == math.inf):
            require_range("fetch", self.fetch, MIN_FETCH, MAX_FETCH, "m (or inf: fully developed)")

    # -- the wind's numbers ---------------------------------------------------
    @property
    def gravity(self) -> float:
        return self.wind.gravity

    @functools.cached_property
    def u10(self) -> float:
        return self.wind.u10

    @functools.cached_property
    def u19_5(self) -> float:
        return self.wind.u19_5

    @functools.cached_property
    def friction_velocity(self) -> float:
        return self.wind.friction_velocity

    @property
    def dimensionless_fetch(self) -> float:
        """x̃ = gF/U₁₀² (inf for a fully developed sea)."""
        return self.gravity * self.fetch / self.u10 ** 2

    @property
    def developed_fetch(self) -> float:
        """x̃ at which JONSWAP's peak falls to Pierson–Moskowitz's for this wind."""
        ratio = 2.0 * math.pi * JONSWAP_PEAK * self.u19_5 / (PM_PEAK * self.u10)
        return ratio ** (-1.0 / JONSWAP_PEAK_EXP)

    @property
    def fully_developed(self) -> bool:
        """True when the fetch no longer limits the sea: Pierson–Moskowitz."""
        return self.dimensionless_fetch >= self.developed_fetch

    @property
    def kind(self) -> str:
        """``"pierson-moskowitz"`` or ``"jonswap"``: the body's fit."""
        return "pierson-moskowitz" if self.fully_developed else "jonswap"

    @functools.cached_property
    def peak_frequency(self) -> float:
        """ω_p, rad s⁻¹, of the body."""
        g = self.gravity
        if self.fully_developed:
            return (4.0 * PM_BETA / 5.0) ** 0.25 * g / self.u19_5
        return 2.0 * math.pi * JONSWAP_PEAK * self.dimensionless_fetch ** JONSWAP_PEAK_EXP * g / self.u10

    @property
    def peak_wavenumber(self) -> float:
        """k_p = ω_p²/g, rad m⁻¹."""
        return self.peak_frequency ** 2 / self.gravity

    @property
    def peak_wavelength(self) -> float:
        """λ_p = 2π/k_p, metres."""
        return 2.0 * math.pi / self.peak_wavenumber

    @property
    def inverse_wave_age(self) -> float:
        """Ω = U₁₀/c_p = U₁₀ ω_p/g (0.83 fully developed, larger for a young sea)."""
        return self.u10 * self.peak_frequency / self.gravity

    @property
    def alpha(self) -> float:
        """The body's Phillips constant α."""
        if self.fully_developed:
            return PM_ALPHA
        return JONSWAP_ALPHA * self.dimensionless_fetch ** JONSWAP_ALPHA_EXP

    # -- the published laws the sea is checked against -------------------------
    @property
    def published_hs(self) -> float:
        """H_s of the published law for this wind, metres: 0.21 U₁₉.₅²/g, or 1.6·10⁻³ √x̃ U₁₀²/g."""
        g = self.gravity
        if self.fully_developed:
            return PM_HS * self.u19_5 ** 2 / g
        return 4.0 * math.sqrt(JONSWAP_ENERGY * self.dimensionless_fetch) * self.u10 ** 2 / g

    @property
    def published_peak_period(self) -> float:
        """T_p = 2π/ω_p of the published law, seconds (0.877 g/U₁₉.₅, or 3.5 x̃^−0.33 g/U₁₀ in hertz)."""
        if self.fully_developed:
            return 2.0 * math.pi * self.u19_5 / (PM_PEAK * self.gravity)
        return self.u10 / (JONSWAP_PEAK * self.dimensionless_fetch ** JONSWAP_PEAK_EXP * self.gravity)

    # -- the spectrum -----------------------------------------------------------
    def body_frequency(self, omega):
        """S(ω) of the body (PM or JONSWAP), m² s rad⁻¹; 0 at ω = 0."""
        w = np.asarray(omega, dtype=float)
        g, wp = self.gravity, self.peak_frequency
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            s = self.alpha * g * g * w ** -5.0 * np.exp(-1.25 * (wp / w) ** 4)
            if not self.fully_developed:               # JONSWAP's peak enhancement
                sigma = np.where(w <= wp, JONSWAP_SIGMA_LOW, JONSWAP_SIGMA_HIGH)
                r = np.exp(-((w - wp) ** 2) / (2.0 * sigma ** 2 * wp ** 2))
                s = s * JONSWAP_GAMMA ** r
        return np.where(w > 0, s, 0.0)

    def body(self, k):
        """S_body(k) = S(ω) g/(2ω), ω = √(g k), m³ rad⁻¹."""
        k = np.asarray(k, dtype=float)
        omega = np.sqrt(self.gravity * np.maximum(k, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(k > 0, self.body_frequency(omega) * self.gravity / (2.0 * np.where(k > 0, omega, 1.0)),
                            0.0)

    def phase_speed(self, k):
        """c = √(g/k (1 + (k/k_m)²)), m s⁻¹: gravity–capillary dispersion (ECKV's)."""
        k = np.asarray(k, dtype=float)
        return np.sqrt(self.gravity / k * (1.0 + (k / ECKV_KM) ** 2))

    @property
    def alpha_m(self) -> float:
        """ECKV's short-wave α_m from u*/c_m, never negative."""
        r = self.friction_velocity / ECKV_CM
        return max(0.0, 1e-2 * (1.0 + (1.0 if r <= 1.0 else 3.0) * math.log(r)))

    def eckv_curvature(self, k):
        """(B_l, B_h): ECKV's long- and short-wave curvature spectra, k³ S."""
        k = np.asarray(k, dtype=float)
        om, kp = self.inverse_wave_age, self.peak_wavenumber
        c, cp = self.phase_speed(k), math.sqrt(self.gravity / kp)
        gamma = 1.7 if om <= 1.0 else 1.7 + 6.0 * math.log10(om)
        sigma = 0.08 * (1.0 + 4.0 * om ** -3)
        root = np.sqrt(k / kp)
        lpm = np.exp(-1.25 * (kp / k) ** 2)
        jp = gamma ** np.exp(-((root - 1.0) ** 2) / (2.0 * sigma ** 2))
        side = np.exp(-(om / math.sqrt(10.0)) * (root - 1.0))
        b_l = 0.5 * 6e-3 * om ** 0.55 * (cp / c) * lpm * jp * side
        gc = np.exp(-0.25 * (k / ECKV_KM - 1.0) ** 2)
        b_h = 0.5 * self.alpha_m * (ECKV_CM / c) * lpm * gc
        return b_l, b_h

    def join_weight(self, k):
        """w(k) = 1/(1 + (k/4k_p)⁴): the body's share of S."""
        return 1.0 / (1.0 + (np.asarray(k, dtype=float) / (JOIN * self.peak_wavenumber)) ** JOIN_POWER)

    def __call__(self, k):
        """S(k), m³ rad⁻¹ (∫ S dk = m₀), for k >= 0 of any shape; 0 at k = 0."""
        k = np.asarray(k, dtype=float)
        if np.any(np.isnan(k)) or np.any(k < 0):
            raise SunsetError("k must be non-negative wavenumbers (rad/m)")
        safe = np.where(k > 0, k, 1.0)
        b_l, b_h = self.eckv_curvature(safe)       # Elfouhaily et al.'s B_l, B_h
        w = self.join_weight(safe)                 # 1/(1 + (k/4k_p)⁴)
        s = w * self.body(safe) + (1.0 - w) * (b_l + b_h) / safe ** 3
        return np.where(k > 0, s, 0.0)

    def frequency_spectrum(self, omega):
        """S(ω) of the whole sea, S(k(ω)) dk/dω with k = ω²/g, m² s rad⁻¹."""
        w = np.asarray(omega, dtype=float)
        return self(w * w / self.gravity) * 2.0 * w / self.gravity

    # -- integrals ----------------------------------------------------------------
    @property
    def cutoff(self) -> float:
        """The capillary cutoff k_c, rad m⁻¹, of the slope integrals."""
        return CUTOFF * ECKV_KM

    def grid(self, k_lo: float | None = None, k_hi: float | None = None) -> np.ndarray:
        """A log-spaced quadrature grid from k_lo (default k_p/30) to k_hi (default k_c)."""
        lo = self.peak_wavenumber / 30.0 if k_lo is None else k_lo
        hi = self.cutoff if k_hi is None else k_hi
        n = max(16, int(QUAD_PER_DECADE * math.log10(hi / lo)) + 1)
        return np.geomspace(lo, hi, n)

    def moment(self, power: int = 0, k_lo: float | None = None, k_hi: float | None = None) -> float:
        """∫ k^power S(k) dk over [k_lo, k_hi] (trapezoid in ln k): m₀ at 0, the slope variance at 2."""
        k = self.grid(k_lo, k_hi)
        return float(np.trapezoid(k ** (power + 1) * self(k), np.log(k)))

    @property
    def m0(self) -> float:
        """m₀ = ⟨z²⟩, m²."""
        return self.moment(0)

    @property
    def hs(self) -> float:
        """H_s = 4√m₀, metres."""
        return 4.0 * math.sqrt(self.m0)

    @property
    def mean_square_slope(self) -> float:
        """⟨|∇z|²⟩ = ∫ k² S dk up to the capillary cutoff (dimensionless)."""
        return self.moment(2)


def fetch_text(fetch: float) -> str:
    """The fetch as a reader says it: ``fully developed`` or ``50 km``."""
    return "fully developed" if fetch == math.inf else f"{fetch / 1000.0:g} km"


def check_gravity(gravity: float) -> None:
    """The spectra are fits to Earth's sea: a wind sea needs standard gravity."""
    if gravity != GRAVITY:
        raise SunsetError(f"gravity must be standard gravity ({GRAVITY} m/s²) for a wind sea (its spectra are "
                          f"fits to Earth's oceans), got {gravity!r}")
