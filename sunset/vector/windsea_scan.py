"""The wind sea's scan line: the σ-sampled scan line reads the periodic FFT tile (issue 31).

A sea given by its wind (:mod:`sunset.model.windsea`) is a height field on a
periodic tile, not a sum of trains, but the vector stage reads it unchanged
in spirit. Along the scan line x = s·y the samples are the paper's
y_i = h/(iσΔζ) (:func:`sunset.vector.heightfield.sampling`), and the profile
is the same g(y_i) = (z(s·y_i, y_i) − h)/y_i, scan-converted, tail and depth
buffer included, by :func:`sunset.vector.heightfield.sea_scan`. Only where z
comes from differs:

* **the height** at (x, y) is the tile's grid of z (spacing Δ = L/M, M the
  grid's points a side) interpolated bilinearly and periodically, from the
  four grid points about (x mod L, y mod L). Against the exact spectral sum
  z = Σ_k ẑ(k, t) e^{ik·x} (:meth:`~sunset.model.ocean.OceanTile.exact`) its
  error is stated per tile by
  :meth:`~sunset.model.ocean.OceanTile.interpolation_error`: the rms over
  the plane and time, and a bound that holds at every point (tests); the
  grid may be oversampled (``WindSea.make_tile(oversample)``) to shrink it;
* **the normals** come from the spectrum's gradient, the FFT of i k ẑ
  (∂z/∂x, ∂z/∂y on the same grid), interpolated bilinearly: not the slope
  of the interpolated heights, which is piecewise constant across a cell.

The far samples are farther apart than the tile's spacing (at a distance y
they are y²σΔζ/h apart): there the scan line samples the tile sparsely, as
it samples the short trains of Max's sea far away.

The choppy option (λ > 0) moves the grid's points: the height at a scene
point is found by carrying it back through the choppy map
(:meth:`~sunset.model.ocean.OceanTile.sample`), in both kernels (the
compiled twin takes the same fixed-point steps); a choppy sea has no second
reflection (:mod:`sunset.vector.windsea_crests`). Stokes' sharpening is a
train's, and is not applied to a wind sea.

:func:`wind_columns` has a Numba twin (:mod:`sunset.vector.windsea_scan_numba`)
that interpolates each scan line's profile into a buffer and scan-converts it
at once, as the trains' twin does.

The direct rays' rows of a wind sea have their own strip kernels beside the
trains' (:mod:`sunset.vector.direct`): :func:`wind_normals` for
:func:`~sunset.vector.direct.direct_rows` and :func:`wind_sea_geometry` for a
wave cycle's sea pixels (:func:`~sunset.vector.direct.sea_strip`), each with
its twin. The pipeline picks the kernels of the sea's kind
(:func:`sunset.pipeline.frame.sea_stage`); the trains' kernels refuse a wind sea.
"""

from __future__ import annotations

import numpy as np

from ..kernels import twin
from .direct import put_unit_normals, sea_points
from .heightfield import _F32, _profile_arrays, sea_scan

__all__ = ["wind_profile", "wind_columns", "wind_gradient_on_scanlines", "wind_normals", "wind_sea_geometry"]


def wind_profile(sea, s, u, h: float, t: float = 0.0):
    """g(y_i) = (z(s·y_i, y_i) − h)·u_i of a wind sea, (C, N) float32.

    On the scan lines ``s`` at the samples ``u``.

    Parameters as :func:`sunset.vector.heightfield.sea_profile`; z is the
    tile's bilinear interpolant (:meth:`~sunset.model.ocean.OceanTile.heights`),
    computed in float64 and rounded once.
    """
    s, u, _y, g = _profile_arrays(s, u)
    if u.size == 0 or s.size == 0:
        return g
    y = 1.0 / u
    z = sea.wind.tile.heights(s[:, None] * y[None, :], y[None, :], t)
    g[...] = (z - h) * u[None, :]
    return g


@twin("sunset.vector.windsea_scan_numba")
def wind_columns(sea, s, u, h: float, t: float, zeta0: float, dzeta: float, n_pixels: int, best_u, best_surf) -> int:
    """A wind sea on C scan lines: :func:`wind_profile`, then :func:`~sunset.vector.heightfield.sea_scan`.

    The same arguments and result as :func:`sunset.vector.heightfield.sea_columns`
    (the trains' kernel): the strip's depth buffer is updated in place, the
    far tail's pixels counted.
    """
    return sea_scan(u, wind_profile(sea, s, u, h, t), zeta0, dzeta, n_pixels, best_u, best_surf)


@twin("sunset.vector.windsea_scan_numba")
def wind_gradient_on_scanlines(sea, s, y, t: float = 0.0):
    """(∂z/∂x, ∂z/∂y) of a wind sea at (s·y, y), float32: the FFT gradient grids interpolated bilinearly.

    The same arguments as :func:`sunset.vector.heightfield.sea_gradient_on_scanlines`.
    """
    s = np.asarray(s, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    _, zx, zy = sea.wind.tile.sample(s * y, y, t)
    return zx.astype(_F32), zy.astype(_F32)


@twin("sunset.vector.windsea_scan_numba")
def wind_normals(sea, t: float, normal, idx, s, y) -> None:
    """A wind sea's pixels' unit normals into the flat pixels ``idx`` of ``normal`` (H, W, 3), in place.

    :func:`wind_gradient_on_scanlines` at (s·y, y), then
    :func:`~sunset.vector.direct.put_unit_normals`: the wind sea's
    :func:`sunset.vector.direct.put_sea_normals`.
    """
    fx, fy = wind_gradient_on_scanlines(sea, s, y, t)
    put_unit_normals(normal, idx, fx, fy)


@twin("sunset.vector.windsea_scan_numba")
def wind_sea_geometry(best_u, best_surf, s_all, zeta, sea, t: float, surface, point, normal) -> None:
    """A wind sea's :func:`sunset.vector.direct.sea_geometry`: the sea pixels' points, then :func:`wind_normals`.

    The same arguments; the same bits as :func:`~sunset.vector.direct.direct_rows`
    with :func:`wind_normals` on the sea pixels.
    """
    idx, s, y = sea_points(best_u, best_surf, s_all, zeta, surface, point)
    if len(idx):
        wind_normals(sea, t, normal, idx, s, y)
