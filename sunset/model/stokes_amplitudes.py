"""The paper's Stokes amplitudes k·a_n in powers of α (after eq. 2), truncated at an order.

Read by the expansion's module (:mod:`sunset.model.stokes`, which gives the
series' speed and crest curvature and fits the expansion to exact waves) and
by the exact wave (:meth:`sunset.model.stokes_exact.StokesWave.series_profile`,
the paper's series with the exact wave's α): both import them from here, so
neither module imports the other's way back.
"""

from __future__ import annotations

import numpy as np

from ..errors import require_int_range, require_nonnegative

__all__ = ["stokes_coefficients"]


def _check_alpha(alpha) -> np.ndarray:
    require_nonnegative("alpha", alpha)
    return np.asarray(alpha, dtype=float)


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
        truncated at ``order``. With α the amplitude of the exact wave's first
        Fourier harmonic, these are the exact wave's coefficients to O(α⁵)
        (checked against :func:`~sunset.model.stokes_exact.solve_stokes` by
        :func:`~sunset.model.stokes.expansion_fit`).
    """
    require_int_range("order", order, 1, 4)
    a = _check_alpha(alpha)
    out = np.zeros(a.shape + (order,))
    out[..., 0] = a
    if order >= 2:
        out[..., 1] = a**2 / 2 + (17.0 / 24.0 * a**4 if order >= 4 else 0.0)
    if order >= 3:
        out[..., 2] = 3.0 / 8.0 * a**3
    if order >= 4:
        out[..., 3] = a**4 / 3.0
    return out
