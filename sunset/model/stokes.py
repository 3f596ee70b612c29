"""Stokes waves on deep water: the paper's expansion (eq. 2) and the exact wave.

A Stokes wave is a periodic, irrotational gravity wave of permanent form on
deep water, travelling at speed c, symmetric about its crest at x = 0. Its
elevation about the mean level is the Fourier cosine series of eq. 2,

    z(x, t) = Σ_{n>=1} a_n cos n k (x − c t).

This module gives it twice:

* the paper's truncated expansion in powers of α = k·a₁ (the maximum slope of
  the first term): :func:`stokes_coefficients`, with the speed
  :func:`series_speed` and the crest curvature :func:`series_crest_curvature`
  of that truncated series;
* the exact wave, computed numerically: :func:`solve_stokes` returns a
  :class:`StokesWave` (coefficients a_n of the exact Eulerian elevation, speed,
  crest curvature, profile), and :func:`expansion_fit` recovers the expansion's
  low-order coefficients from exact waves of small amplitude, which is how the
  book checks the paper's 1/2, 17/24, 3/8 and 1/3.

Everything here is dimensionless: lengths are multiplied by the wave number k
(so ``k a_n``, ``k x``, ``k H``), speeds are divided by √(g/k).

The exact solver is in :mod:`sunset.model.stokes_exact`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SunsetError, require_finite, require_int_range
from .stokes_amplitudes import _check_alpha, stokes_coefficients
from .stokes_exact import solve_stokes

__all__ = ["stokes_coefficients", "series_speed", "series_crest_curvature", "ExpansionFit", "expansion_fit"]


# --------------------------------------------------------------------------- the paper's expansion
def series_speed(alpha, order: int = 4) -> np.ndarray:
    """Phase speed c/√(g/k) of Stokes' expansion to ``order`` in α = k·a₁.

    c = √(g/k) (1 + α²/2 + α⁴/2 + O(α⁶)), the square root of Stokes'
    c² = (g/k)(1 + α² + 5α⁴/4); order 1 is the linear c = √(g/k) (paper,
    before eq. 1), which the paper keeps for every order ("this effect has
    been neglected here").

    Parameters
    ----------
    alpha : float or array_like
        α = k·a₁ (dimensionless, >= 0).
    order : int
        Highest power of α kept, 1 to 4.

    Returns
    -------
    ndarray, shape ``np.shape(alpha)``
        c/√(g/k), dimensionless.
    """
    require_int_range("order", order, 1, 4)
    a = _check_alpha(alpha)
    c = np.ones(a.shape)
    if order >= 2:
        c = c + a**2 / 2
    if order >= 4:
        c = c + a**4 / 2
    return c


def series_crest_curvature(alpha, order: int = 4) -> np.ndarray:
    """Curvature κ/k at the crest of the paper's truncated series (eq. 2).

    z(x) = Σ a_n cos nkx has z'(0) = 0, so its curvature at the crest is
    κ = −z''(0) = Σ n² k² a_n; in units of k, κ/k = Σ n² (k a_n) with the
    amplitudes of :func:`stokes_coefficients`. Positive for a convex crest.
    This is the curvature of the parabolic cylinder that the secondary
    reflections (sunset.vector.pierce) fit to a crest.

    Parameters
    ----------
    alpha : float or array_like
        α = k·a₁ (dimensionless, >= 0).
    order : int
        Number of terms (and highest power of α), 1 to 4.

    Returns
    -------
    ndarray, shape ``np.shape(alpha)``
        κ/k, dimensionless: α, α + 2α², α + 2α² + 27α³/8,
        α + 2α² + 27α³/8 + 49α⁴/6 for orders 1..4.
    """
    amps = stokes_coefficients(alpha, order)
    n = np.arange(1, order + 1)
    return amps @ (n * n).astype(float)


# --------------------------------------------------------------------------- the expansion, measured
@dataclass(frozen=True, eq=False)
class ExpansionFit:
    """Low-order coefficients of Stokes' expansion, fitted to exact waves.

    Each array holds the coefficients of successive powers, lowest first:

    - ``a2``: k a₂ = a2[0] α² + a2[1] α⁴ + a2[2] α⁶ + …
    - ``a3``: k a₃ = a3[0] α³ + a3[1] α⁵ + …
    - ``a4``: k a₄ = a4[0] α⁴ + a4[1] α⁶ + …
    - ``a5``: k a₅ = a5[0] α⁵ + …
    - ``speed``: c/√(g/k) = speed[0] + speed[1] α² + speed[2] α⁴ + …
    - ``speed_squared``: c²k/g = speed_squared[0] + speed_squared[1] α² + …
    - ``crest_curvature``: κ/k = crest_curvature[0] α + crest_curvature[1] α² + …

    with α = k a₁; and, in the other common convention ε = kH/2 (half the
    crest-to-trough height): ``eps_a1`` (k a₁ = eps_a1[0] ε + eps_a1[1] ε³ + …),
    ``eps_a2`` (k a₂ = eps_a2[0] ε² + eps_a2[1] ε⁴ + …) and ``eps_speed``.
    ``alpha_max`` is the largest α of the exact waves used.
    """

    alpha_max: float
    a2: np.ndarray
    a3: np.ndarray
    a4: np.ndarray
    a5: np.ndarray
    speed: np.ndarray
    speed_squared: np.ndarray
    crest_curvature: np.ndarray
    eps_a1: np.ndarray
    eps_a2: np.ndarray
    eps_speed: np.ndarray


def _fit(x, y, first: int, stride: int, terms: int) -> np.ndarray:
    """Least-squares coefficients of y = Σ_j b_j x^(first + stride j), j < terms."""
    t = x**stride
    V = np.stack([t**j for j in range(terms)], axis=1)
    scale = np.max(np.abs(V), axis=0)
    b, *_ = np.linalg.lstsq(V / scale, y / x**first, rcond=None)
    return b / scale


def expansion_fit(max_height: float = 0.2, samples: int = 16, terms: int = 7,
                  n_modes: int = 48) -> ExpansionFit:
    """Fit the expansion's low-order coefficients to small exact Stokes waves.

    Solves ``samples`` exact waves with k·H evenly spaced up to ``max_height``
    and fits each quantity by least squares with ``terms`` powers (the
    polynomial extrapolation to α → 0 of Richardson's method). With the
    defaults (α <= 0.1, exact waves to about 1e-15) the leading coefficient of
    each quantity comes out to about 1e-11 and the next one to about 1e-8.

    Parameters
    ----------
    max_height : float
        Largest k·H (0 < max_height <= 0.5).
    samples : int
        Number of exact waves (>= terms + 2).
    terms : int
        Powers fitted per quantity (2..8).
    n_modes : int
        Collocation points minus one for each exact wave.

    Returns
    -------
    ExpansionFit
    """
    require_finite("max_height", max_height)
    if not 0.0 < max_height <= 0.5:
        raise SunsetError(f"max_height must be in (0, 0.5], got {max_height!r}")
    require_int_range("terms", terms, 2, 8)
    require_int_range("samples", samples, terms + 2, 200)
    heights = max_height * np.arange(1, samples + 1) / samples
    waves = [solve_stokes(h / (2 * np.pi), n_modes=n_modes, map_parameter=1.0)
             for h in heights]
    a = np.array([w.coefficients[:5] for w in waves])
    al = a[:, 0]
    c = np.array([w.speed for w in waves])
    # The crest series K(α) = Σ n² k a_n(α) has every power of α. Its value at −α
    # is that of the wave shifted by half a wavelength (a_n -> (−1)^n a_n), whose
    # "crest" is the trough: K(−α) = −(trough curvature). So the odd and even parts
    # of K are fitted separately, each in powers of α².
    crest = np.array([w.crest_curvature for w in waves])
    trough = np.array([w.trough_curvature for w in waves])
    curvature = np.empty(2 * terms)
    curvature[0::2] = _fit(al, (crest + trough) / 2, 1, 2, terms)
    curvature[1::2] = _fit(al, (crest - trough) / 2, 2, 2, terms)
    eps = heights / 2
    return ExpansionFit(
        alpha_max=float(al.max()),
        a2=_fit(al, a[:, 1], 2, 2, terms), a3=_fit(al, a[:, 2], 3, 2, terms),
        a4=_fit(al, a[:, 3], 4, 2, terms), a5=_fit(al, a[:, 4], 5, 2, terms),
        speed=_fit(al, c, 0, 2, terms), speed_squared=_fit(al, c * c, 0, 2, terms),
        crest_curvature=curvature,
        eps_a1=_fit(eps, a[:, 0], 1, 2, terms),
        eps_a2=_fit(eps, a[:, 1], 2, 2, terms),
        eps_speed=_fit(eps, c, 0, 2, terms),
    )
