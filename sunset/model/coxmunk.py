"""Cox and Munk's (1954) sea slopes: their published laws, and a Gaussian distribution of facets.

Cox and Munk photographed the sun's glitter off Maui and read from it the
distribution of the sea's slopes. For a clean surface and the wind U at 12.5 m
(m s⁻¹) they fitted the mean-square slopes

    along the wind (upwind)  σ_u² = 0.000 + 3.16·10⁻³ U  ± 0.004
    across the wind          σ_c² = 0.003 + 1.92·10⁻³ U  ± 0.002
    total                    σ²   = 0.003 + 5.12·10⁻³ U  ± 0.004

over 0 < U < 14 m s⁻¹ (the ± are the rms scatter of their points about the line).
To first order the slopes are Gaussian; the skewness and peakedness they also
measured (the Gram–Charlier terms) are left out here. :func:`facet_density` is
that Gaussian, the distribution of the facets a renderer cannot resolve:
the back end's glitter will give it the slope variance the tile leaves out
(:meth:`sunset.model.windsea.WindSea.unresolved_slopes`).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import SunsetError, require_range

#: (intercept, slope per m s⁻¹, rms scatter) of the clean-surface laws: total, upwind, crosswind.
COX_MUNK_TOTAL = (0.003, 5.12e-3, 0.004)
COX_MUNK_UPWIND = (0.000, 3.16e-3, 0.004)
COX_MUNK_CROSSWIND = (0.003, 1.92e-3, 0.002)
#: The wind speeds (at 12.5 m) the laws were fitted over, m s⁻¹.
COX_MUNK_MAX_WIND = 14.0


def cox_munk_clean(u12_5) -> dict[str, tuple]:
    """The clean-surface mean-square slopes for the wind at 12.5 m, with their scatter.

    Returns ``{"total": (σ², ±), "upwind": (σ_u², ±), "crosswind": (σ_c², ±)}``;
    the values have the shape of ``u12_5``.
    """
    u = np.asarray(u12_5, dtype=float)
    if np.any(np.isnan(u)) or np.any(u < 0) or np.any(u > COX_MUNK_MAX_WIND):
        raise SunsetError(f"u12_5 must be in [0, {COX_MUNK_MAX_WIND:g}] m/s (Cox and Munk's range), got {u12_5!r}")
    laws = {"total": COX_MUNK_TOTAL, "upwind": COX_MUNK_UPWIND, "crosswind": COX_MUNK_CROSSWIND}
    return {name: (a + b * u, e) for name, (a, b, e) in laws.items()}


def facet_density(zx, zy, var_upwind: float, var_crosswind: float, wind_direction: float = 90.0):
    """p(z_x, z_y): the Gaussian density of facet slopes, per unit slope².

    Parameters
    ----------
    zx, zy : array_like
        Slopes ∂z/∂x and ∂z/∂y (broadcast).
    var_upwind, var_crosswind : float
        σ_u² and σ_c², the slope variances along and across the wind (> 0).
    wind_direction : float
        The direction the wind blows toward, degrees from +x toward +y.

    Returns
    -------
    ndarray
        p = exp(−½ (z_u²/σ_u² + z_c²/σ_c²)) / (2π σ_u σ_c), with z_u, z_c the
        slopes along and across the wind; ∫∫ p dz_x dz_y = 1.
    """
    require_range("var_upwind", var_upwind, 0.0, 1.0, lo_open=True)
    require_range("var_crosswind", var_crosswind, 0.0, 1.0, lo_open=True)
    require_range("wind_direction", wind_direction, -3600.0, 3600.0, "degrees")
    d = math.radians(wind_direction)
    zx, zy = np.asarray(zx, dtype=float), np.asarray(zy, dtype=float)
    zu = zx * math.cos(d) + zy * math.sin(d)
    zc = -zx * math.sin(d) + zy * math.cos(d)
    q = zu * zu / var_upwind + zc * zc / var_crosswind
    return np.exp(-0.5 * q) / (2.0 * math.pi * math.sqrt(var_upwind * var_crosswind))
