"""Numba twin of :func:`sunset.light.raster.rasterise`: one triangle at a time, one texel of its box at a time.

The same clipping (Sutherland–Hodgman against the texel's four edges, in the
texel's own coordinates) and the same shoelace fan, in registers; the texels'
shares are added to the texture triangle after triangle, in order, so the
result does not depend on anything but the input (one thread). It agrees
with the NumPy reference, which adds the shares up texel by texel with
``bincount``, within the round-off of those sums (tested: 1e-12 of the
largest texel).
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels import jit as _jit
from .raster import MAX_VERTICES

__all__ = ["rasterise", "RASTER_RTOL"]

#: How far the compiled texture may stray from the reference's, relative to its largest texel (and the kept
#: shares, absolutely): the two add the same shares in another order.
RASTER_RTOL = 1e-12


@_jit
def _clip(px, py, n, axis, bound, below, qx, qy):
    m = 0
    for k in range(n):
        k1 = k + 1 if k + 1 < n else 0
        a = px[k] if axis == 0 else py[k]
        b = px[k1] if axis == 0 else py[k1]
        sa = (bound - a) if below else (a - bound)
        sb = (bound - b) if below else (b - bound)
        if sa >= 0:
            qx[m] = px[k]
            qy[m] = py[k]
            m += 1
        if (sa >= 0) != (sb >= 0):
            f = sa / (sa - sb)
            if axis == 0:
                qx[m] = bound
                qy[m] = py[k] + f * (py[k1] - py[k])
            else:
                qx[m] = px[k] + f * (px[k1] - px[k])
                qy[m] = bound
            m += 1
    return m


@_jit
def _rasterise(u, v, flux, n_u, n_v, out, kept):
    T, C = flux.shape
    ax = np.empty(MAX_VERTICES)
    ay = np.empty(MAX_VERTICES)
    bx = np.empty(MAX_VERTICES)
    by = np.empty(MAX_VERTICES)
    for t in range(T):
        area = 0.5 * abs((u[t, 1] - u[t, 0]) * (v[t, 2] - v[t, 0]) - (u[t, 2] - u[t, 0]) * (v[t, 1] - v[t, 0]))
        umin = min(u[t, 0], min(u[t, 1], u[t, 2]))
        umax = max(u[t, 0], max(u[t, 1], u[t, 2]))
        vmin = min(v[t, 0], min(v[t, 1], v[t, 2]))
        vmax = max(v[t, 0], max(v[t, 1], v[t, 2]))
        cu = (u[t, 0] + u[t, 1] + u[t, 2]) / 3.0
        cv = (v[t, 0] + v[t, 1] + v[t, 2]) / 3.0
        inside = vmin >= 0 and vmax <= n_v
        i0 = int(math.floor(umin))
        i1 = int(math.floor(umax))
        j0 = max(int(math.floor(vmin)), 0)
        j1 = min(int(math.floor(vmax)), n_v - 1)
        centroid = not area > 0
        if not centroid and j1 >= j0:
            total = 0.0
            for pass_ in range(2):          # first the areas' sum, then the shares
                for i in range(i0, i1 + 1):
                    for j in range(j0, j1 + 1):
                        for k in range(3):
                            ax[k] = u[t, k] - i
                            ay[k] = v[t, k] - j
                        n = _clip(ax, ay, 3, 0, 0.0, False, bx, by)
                        n = _clip(bx, by, n, 0, 1.0, True, ax, ay)
                        n = _clip(ax, ay, n, 1, 0.0, False, bx, by)
                        n = _clip(bx, by, n, 1, 1.0, True, ax, ay)
                        cover = 0.0
                        for k in range(1, n - 1):
                            cover += ((ax[k] - ax[0]) * (ay[k + 1] - ay[0])
                                      - (ax[k + 1] - ax[0]) * (ay[k] - ay[0]))
                        cover = 0.5 * abs(cover)
                        if pass_ == 0:
                            total += cover
                        elif cover > 0:
                            norm = total if inside else area
                            share = cover / norm
                            row = j * n_u + (i % n_u)
                            for c in range(C):
                                out[row, c] += share * flux[t, c]
                if pass_ == 0:
                    if inside:
                        kept[t] = 1.0
                        if not total > 0:
                            centroid = True
                            break
                    else:
                        kept[t] = min(total / area, 1.0)
        if centroid:
            if cv >= 0 and cv < n_v:
                kept[t] = 1.0
                row = int(math.floor(cv)) * n_u + (int(math.floor(cu)) % n_u)
                for c in range(C):
                    out[row, c] += flux[t, c]


def rasterise(u, v, flux, n_u: int, n_v: int):
    """:func:`sunset.light.raster.rasterise` compiled."""
    flux = np.ascontiguousarray(flux, dtype=np.float64)
    out = np.zeros((n_v * n_u, flux.shape[1]))
    kept = np.zeros(flux.shape[0])
    _rasterise(np.ascontiguousarray(u, dtype=np.float64), np.ascontiguousarray(v, dtype=np.float64), flux,
               int(n_u), int(n_v), out, kept)
    return out.reshape(n_v, n_u, flux.shape[1]), kept
