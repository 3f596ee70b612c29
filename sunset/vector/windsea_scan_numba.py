"""Numba twins of :mod:`sunset.vector.windsea_scan`: the wind sea's scan line interpolated and scan-converted at once.

:func:`wind_columns` interpolates each scan line's profile from the tile's
grid into a buffer of one scan line (the reference's bilinear arithmetic, in
the same order, so the profile is the same numbers) and scan-converts it
while it is in cache with the trains' compiled scan line
(:func:`sunset.vector.heightfield_numba._scan_row_b` and ``_merge_row``): no
(C, n) profile. :func:`wind_gradient_on_scanlines` interpolates the two
gradient grids. On a choppy tile (λ > 0) each point is first carried back
through the choppy map with the reference's fixed-point steps
(:func:`_choppy_origin`, :meth:`sunset.model.ocean.OceanTile.sample`'s
arithmetic in its order), and the slope is (I + λ∇D)⁻ᵀ∇z there.
:func:`wind_normals` and :func:`wind_sea_geometry` are the rows' kernels: the
gradient, then the unit normals (:func:`sunset.vector.direct_numba.put_unit_normals`),
after the sea pixels' points in one pass (:func:`_sea_points`). Chosen by
:mod:`sunset.kernels`.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import SEA
from ..model.ocean import CHOPPY_ITERATIONS
from ..kernels import jit as _jit
from . import windsea_scan as _reference
from .direct_numba import put_unit_normals
from .heightfield import _F32
from .heightfield_numba import _merge_row, _scan_row_b


@_jit
def _bilinear(grid, spacing, x, y):
    """The reference's periodic bilinear interpolation (:meth:`sunset.model.ocean.OceanTile._bilinear`) at one point."""
    m = grid.shape[0]
    u = x / spacing
    v = y / spacing
    i0f = math.floor(v)
    j0f = math.floor(u)
    fv = v - i0f
    fu = u - j0f
    i0 = int(i0f) % m
    j0 = int(j0f) % m
    i1 = (i0 + 1) % m
    j1 = (j0 + 1) % m
    w00 = (1 - fv) * (1 - fu)
    w01 = (1 - fv) * fu
    w10 = fv * (1 - fu)
    w11 = fv * fu
    return w00 * grid[i0, j0] + w01 * grid[i0, j1] + w10 * grid[i1, j0] + w11 * grid[i1, j1]


@_jit
def _choppy_origin(dx, dy, spacing, lam, x, y, iterations):
    """The point x₀ that the choppy map x₀ + λD(x₀) carries to (x, y): the reference's fixed-point steps."""
    x0 = x
    y0 = y
    for _ in range(iterations):
        ddx = _bilinear(dx, spacing, x0, y0)
        ddy = _bilinear(dy, spacing, x0, y0)
        x0 = x - lam * ddx
        y0 = y - lam * ddy
    return x0, y0


@_jit
def _wind_columns(z, spacing, s, y, u, h, zeta0, dzeta, inv_dz_t, zeta0_t, kf_t, zero_t, K, best_u, best_surf,
                  code, dx, dy, lam, iterations):
    """Each scan line's profile from the grid, then its scan line, far tail and depth buffer."""
    N = y.shape[0]
    g = np.empty(N, _F32)
    bins = np.empty(N, dtype=np.int32)
    first = np.empty(K + 1, dtype=np.int64)
    row = np.empty(K)
    n_tail = 0
    for col in range(s.shape[0]):
        sc = s[col]
        for i in range(N):
            x0, y0 = sc * y[i], y[i]
            if lam > 0.0:
                x0, y0 = _choppy_origin(dx, dy, spacing, lam, x0, y0, iterations)
            g[i] = np.float32((_bilinear(z, spacing, x0, y0) - h) * u[i])
        _scan_row_b(u, 0, g, 0, N, zeta0, dzeta, inv_dz_t, zeta0_t, kf_t, zero_t, K, row, bins, first)
        n_tail += _merge_row(row, np.float64(g[N - 1]), u[N - 1], zeta0, dzeta, True, best_u[col], best_surf[col],
                             code, True)
    return n_tail


def wind_columns(sea, s, u, h: float, t: float, zeta0: float, dzeta: float, n_pixels: int, best_u, best_surf) -> int:
    """:func:`sunset.vector.windsea_scan.wind_columns` compiled: ``best_u`` and ``best_surf`` updated in place."""
    tile = sea.wind.tile
    u = np.ascontiguousarray(u, dtype=np.float64)
    s = np.ascontiguousarray(s, dtype=np.float64)
    if u.size == 0 or s.size == 0:
        return _reference.wind_columns.reference(sea, s, u, h, t, zeta0, dzeta, n_pixels, best_u, best_surf)
    fields = tile.fields(t)
    z = fields["z"]
    dx, dy = (fields["dx"], fields["dy"]) if tile.choppiness > 0 else (z, z)
    bu, bs = np.ascontiguousarray(best_u), np.ascontiguousarray(best_surf)
    f = _F32
    tail = int(_wind_columns(z, tile.spacing, s, 1.0 / u, u, float(h), float(zeta0), float(dzeta), f(1.0 / dzeta),
                             f(zeta0), f(n_pixels), f(0.0), int(n_pixels), bu, bs, SEA, dx, dy,
                             float(tile.choppiness), CHOPPY_ITERATIONS))
    if bu is not best_u:
        best_u[...] = bu
    if bs is not best_surf:
        best_surf[...] = bs
    return tail


@_jit
def _gradient(zx, zy, dx, dy, dxx, dxy, dyy, spacing, lam, iterations, s, y, gx, gy):
    """(∂z/∂x, ∂z/∂y) at (s·y, y): the gradient grids bilinear; choppy (λ > 0): (I + λ∇D)⁻ᵀ∇z at x₀."""
    for i in range(s.shape[0]):
        x = s[i] * y[i]
        if lam > 0.0:
            x0, y0 = _choppy_origin(dx, dy, spacing, lam, x, y[i], iterations)
            ax = _bilinear(zx, spacing, x0, y0)
            ay = _bilinear(zy, spacing, x0, y0)
            a = 1.0 + lam * _bilinear(dxx, spacing, x0, y0)
            b = lam * _bilinear(dxy, spacing, x0, y0)
            d = 1.0 + lam * _bilinear(dyy, spacing, x0, y0)
            det = a * d - b * b
            gx[i] = np.float32((d * ax - b * ay) / det)
            gy[i] = np.float32((a * ay - b * ax) / det)
        else:
            gx[i] = np.float32(_bilinear(zx, spacing, x, y[i]))
            gy[i] = np.float32(_bilinear(zy, spacing, x, y[i]))


def wind_gradient_on_scanlines(sea, s, y, t: float = 0.0):
    """:func:`sunset.vector.windsea_scan.wind_gradient_on_scanlines` compiled (the same numbers, float32)."""
    tile = sea.wind.tile
    s, y = np.broadcast_arrays(np.asarray(s, dtype=np.float64), np.asarray(y, dtype=np.float64))
    if not (np.all(np.isfinite(s)) and np.all(np.isfinite(y))):
        return _reference.wind_gradient_on_scanlines.reference(sea, s, y, t)
    f = tile.fields(t)
    chop = [f[n] for n in ("dx", "dy", "dxx", "dxy", "dyy")] if tile.choppiness > 0 else [f["zx"]] * 5
    gx, gy = np.empty(s.shape, _F32), np.empty(s.shape, _F32)
    _gradient(f["zx"], f["zy"], *chop, tile.spacing, float(tile.choppiness), CHOPPY_ITERATIONS,
              np.ascontiguousarray(s).ravel(), np.ascontiguousarray(y).ravel(), gx.reshape(-1), gy.reshape(-1))
    return gx, gy


def wind_normals(sea, t: float, normal, idx, s, y) -> None:
    """:func:`sunset.vector.windsea_scan.wind_normals` compiled: the compiled gradient and unit normals (the same bits)."""
    if len(idx) == 0:
        return
    fx, fy = wind_gradient_on_scanlines(sea, s, y, t)
    put_unit_normals(normal, idx, fx, fy)


@_jit
def _sea_points(best_u, best_surf, s_all, zeta, sea_code, surface, point, flat, s_out, y_out):
    """:func:`sunset.vector.direct.sea_points` in one pass: ``surface``, the sea's points; how many, gathered."""
    W, H = best_u.shape
    n = 0
    for row in range(H):
        k = H - 1 - row
        for col in range(W):
            sc = best_surf[col, k]
            surface[row, col] = sc
            if sc == sea_code:
                yv = 1.0 / best_u[col, k]
                sv = s_all[col]
                point[row, col, 0] = sv * yv
                point[row, col, 1] = yv
                point[row, col, 2] = zeta[k] * yv
                flat[n] = row * W + col
                s_out[n] = sv
                y_out[n] = yv
                n += 1
    return n


def wind_sea_geometry(best_u, best_surf, s_all, zeta, sea, t: float, surface, point, normal) -> None:
    """:func:`sunset.vector.windsea_scan.wind_sea_geometry` compiled: the points in one pass, then :func:`wind_normals`."""
    size = best_u.size
    flat, s, y = np.empty(size, np.intp), np.empty(size), np.empty(size)
    n = _sea_points(best_u, best_surf, np.ascontiguousarray(s_all, np.float64), np.ascontiguousarray(zeta, np.float64),
                    SEA, surface, point, flat, s, y)
    wind_normals(sea, t, normal, flat[:n], s[:n], y[:n])
