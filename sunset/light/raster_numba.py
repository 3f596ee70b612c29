"""Numba twin of :func:`sunset.light.raster.rasterise`: one triangle at a time, one row of its box at a time.

A landing triangle can cover hundreds of texels (a beam from far out at sea
spread over an island's cliff), so the twin does not clip it against every
texel: it clips it to each row's strip (Sutherland–Hodgman against the
row's two edges), and the strip's convex polygon's area in each column is the
integral of its vertical chord, which is linear between the polygon's
vertices' abscissae: exact, as the reference's clipped areas are. The texels'
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
from .raster import FLAT, MAX_VERTICES

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
def _columns(px, py, n, i0, cover, row0):
    """Add to ``cover[row0 + i - i0]`` the area of the convex polygon (px, py)[:n] in each column [i, i + 1]:
    the integral of its vertical chord, linear between its vertices' abscissae."""
    xs = np.empty(MAX_VERTICES)
    ch = np.empty(MAX_VERTICES)
    for k in range(n):
        xs[k] = px[k]
    xs[:n].sort()
    for k in range(n):                       # the chord at each vertex's abscissa
        lo, hi = math.inf, -math.inf
        for e in range(n):
            e1 = e + 1 if e + 1 < n else 0
            xa, xb = px[e], px[e1]
            if (xa <= xs[k] <= xb) or (xb <= xs[k] <= xa):
                if xa == xb:
                    ya, yb = py[e], py[e1]
                else:
                    ya = yb = py[e] + (xs[k] - xa) / (xb - xa) * (py[e1] - py[e])
                lo, hi = min(lo, ya, yb), max(hi, ya, yb)
        ch[k] = hi - lo if hi > lo else 0.0
    # walk the columns and the vertices together, integrating the chord
    k = 0
    x = xs[0]
    i = int(math.floor(x))
    acc = 0.0
    while k < n - 1:
        nxt = min(xs[k + 1], i + 1.0)
        if nxt > x:
            w = xs[k + 1] - xs[k]
            fa = (x - xs[k]) / w if w > 0 else 0.0
            fb = (nxt - xs[k]) / w if w > 0 else 1.0
            la = ch[k] + fa * (ch[k + 1] - ch[k])
            lb = ch[k] + fb * (ch[k + 1] - ch[k])
            acc += 0.5 * (la + lb) * (nxt - x)
            x = nxt
        if x >= i + 1.0:
            cover[row0 + i - i0] += acc
            acc = 0.0
            i += 1
        if x >= xs[k + 1]:
            k += 1
    cover[row0 + i - i0] += acc


@_jit
def _rasterise(u, v, flux, n_u, n_v, out, kept, cover):
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
        ni = int(math.floor(umax)) - i0 + 1
        j0 = max(int(math.floor(vmin)), 0)
        j1 = min(int(math.floor(vmax)), n_v - 1)
        extent = max(umax - umin, vmax - vmin)
        centroid = not area > FLAT * extent * extent
        if not centroid and j1 >= j0:
            # each row's strip of the triangle, in coordinates from (i0, j), and its columns' areas
            total = 0.0
            for j in range(j0, j1 + 1):
                row0 = (j - j0) * ni
                for q in range(ni):
                    cover[row0 + q] = 0.0
                for k in range(3):
                    ax[k] = u[t, k] - i0
                    ay[k] = v[t, k] - j
                n = _clip(ax, ay, 3, 1, 0.0, False, bx, by)
                n = _clip(bx, by, n, 1, 1.0, True, ax, ay)
                if n >= 3:
                    _columns(ax, ay, n, 0, cover, row0)
                for q in range(ni):
                    total += cover[row0 + q]
            if inside:
                kept[t] = 1.0
                if not total > 0:
                    centroid = True
            else:
                kept[t] = min(total / area, 1.0)
            if not centroid:
                norm = total if inside else area
                for j in range(j0, j1 + 1):
                    row0 = (j - j0) * ni
                    for q in range(ni):
                        if cover[row0 + q] > 0:
                            share = cover[row0 + q] / norm
                            row = j * n_u + ((i0 + q) % n_u)
                            for c in range(C):
                                out[row, c] += share * flux[t, c]
        if centroid:
            if cv >= 0 and cv < n_v:
                kept[t] = 1.0
                row = int(math.floor(cv)) * n_u + (int(math.floor(cu)) % n_u)
                for c in range(C):
                    out[row, c] += flux[t, c]


def rasterise(u, v, flux, n_u: int, n_v: int):
    """:func:`sunset.light.raster.rasterise` compiled."""
    u = np.ascontiguousarray(u, dtype=np.float64)
    v = np.ascontiguousarray(v, dtype=np.float64)
    flux = np.ascontiguousarray(flux, dtype=np.float64)
    out = np.zeros((n_v * n_u, flux.shape[1]))
    kept = np.zeros(flux.shape[0])
    if len(u):
        cols = np.floor(u.max(axis=1)) - np.floor(u.min(axis=1)) + 1
        rows = np.clip(np.floor(v.max(axis=1)), None, n_v - 1) - np.clip(np.floor(v.min(axis=1)), 0, None) + 1
        size = int(np.max(np.where(np.isfinite(cols * rows), cols * np.maximum(rows, 1), 1)))
    else:
        size = 1
    _rasterise(u, v, flux, int(n_u), int(n_v), out, kept, np.empty(max(size, 1)))
    return out.reshape(n_v, n_u, flux.shape[1]), kept
