"""Stokes' expansion of deep-water gravity waves (paper eq. 2).

The paper's perturbation amplitudes, as functions of α = k·a₁, the maximum
slope of the first term. (The exact numerical solver is added below by the
Stokes-waves work.)
"""

from __future__ import annotations

import numpy as np

from .errors import SunsetError, require_finite, require_int_range


def stokes_coefficients(alpha, order: int = 4) -> np.ndarray:
    """The paper's Stokes amplitudes k·a_n, n = 1..order (paper, after eq. 2).

    Parameters
    ----------
    alpha : float or array_like
        α = k·a₁, the maximum slope of the first harmonic (dimensionless).
    order : int
        Highest power of α kept, 1 to 4. Each a_n is truncated at α^order,
        so order 2 gives a₂ = α²/2 /k without the α⁴ term.

    Returns
    -------
    ndarray, shape ``np.shape(alpha) + (order,)``
        k·a_n for n = 1..order (dimensionless): α, α²/2 + 17α⁴/24, 3α³/8, α⁴/3,
        truncated at ``order``.
    """
    require_int_range("order", order, 1, 4)
    require_finite("alpha", alpha)
    a = np.asarray(alpha, dtype=float)
    if np.any(a < 0):
        raise SunsetError(f"alpha must not be negative, got {alpha!r}")
    out = np.zeros(a.shape + (order,))
    out[..., 0] = a
    if order >= 2:
        out[..., 1] = a**2 / 2 + (17.0 / 24.0 * a**4 if order >= 4 else 0.0)
    if order >= 3:
        out[..., 2] = 3.0 / 8.0 * a**3
    if order >= 4:
        out[..., 3] = a**4 / 3.0
    return out
