"""Numba twins of :mod:`sunset.vector.direct`: the direct frame's geometry in one pass.

:func:`assemble_geometry` builds directions, points, distances and the
compressed lists of sea and island pixels in one pass over the depth buffer;
:func:`put_unit_normals` writes the sea's unit normals. The arithmetic of the
NumPy reference, element by element. Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import SEA, SKY
from ..kernels import jit as _jit


@_jit
def _assemble(best_u, best_surf, s_all, zeta, sky_code, sea_code, start, surf, direction, point, distance, normal,
              hit_flat, hit_s, hit_y):
    W, H = best_u.shape
    pos = start.copy()
    for row in range(H):
        k = H - 1 - row
        z = zeta[k]
        for c in range(W):
            sc = best_surf[c, k]
            surf[row, c] = sc
            s = s_all[c]
            length = math.sqrt(1.0 + s * s + z * z)
            inv = 1.0 / length
            direction[row, c, 0] = s * inv
            direction[row, c, 1] = inv
            direction[row, c, 2] = z * inv
            if sc != sky_code:
                yv = 1.0 / best_u[c, k]
                dist = yv * length
                # the compressed list of the pixels of surface sc, in row-major order
                j = pos[sc - sea_code]
                pos[sc - sea_code] = j + 1
                hit_flat[j] = row * W + c
                hit_s[j] = s
                hit_y[j] = yv
            else:
                yv = np.nan
                dist = np.inf
            point[row, c, 0] = s * yv
            point[row, c, 1] = yv
            point[row, c, 2] = z * yv
            distance[row, c] = dist
            if sc != sea_code:
                normal[row, c, 0] = np.nan
                normal[row, c, 1] = np.nan
                normal[row, c, 2] = np.nan


@_jit
def _count(best_surf, sea_code, n):
    """Pixels of each surface sea_code … sea_code + n − 1 in the depth buffer."""
    out = np.zeros(n, np.int64)
    W, K = best_surf.shape
    for c in range(W):
        for k in range(K):
            i = best_surf[c, k] - sea_code
            if 0 <= i < n:
                out[i] += 1
    return out


def assemble(best_u, best_surf, s_all, zeta, sky_code: int, sea_code: int, n_islands: int, out):
    """The geometry of :func:`sunset.vector.direct.assemble_geometry` in one pass.

    From 1/yp and the winning surface per (scan line, pixel from the bottom),
    into ``out`` = (``surf`` (H, W) int8, ``direction``, ``point`` (H, W, 3)
    float32, ``distance`` (H, W) float32, ``normal`` (H, W, 3) float32: NaN
    except on the sea, left for the caller to fill); returns for surface
    ``sea_code + i`` (i = 0 the sea, i = k island k) the compressed list
    ``hits[i] = (flat pixel index, s, y)`` in row-major order
    (``np.flatnonzero`` order).
    """
    surf, direction, point, distance, normal = out
    per = _count(best_surf, sea_code, n_islands + 1)
    start = np.concatenate([[0], np.cumsum(per)[:-1]]).astype(np.int64)
    total = int(per.sum())
    hit_flat = np.empty(total, np.intp)
    hit_s = np.empty(total)
    hit_y = np.empty(total)
    _assemble(best_u, best_surf, np.ascontiguousarray(s_all, np.float64),
              np.ascontiguousarray(zeta, np.float64), sky_code, sea_code, start, surf, direction, point, distance,
              normal, hit_flat, hit_s, hit_y)
    return [(hit_flat[a:a + n], hit_s[a:a + n], hit_y[a:a + n]) for a, n in zip(start, per)]


@_jit
def _put_unit_normals(flat, fx, fy, one, normal):
    for j in range(flat.shape[0]):
        gx = fx[j]
        gy = fy[j]
        zb = one / np.sqrt(gx * gx + gy * gy + one)
        i = flat[j]
        normal[i, 0] = -zb * gx
        normal[i, 1] = -zb * gy
        normal[i, 2] = zb


def put_unit_normals(normal, flat, fx, fy) -> None:
    """Write (−f_x, −f_y, 1)/√(f_x² + f_y² + 1) into rows ``flat`` of ``normal`` (…, 3), in place.

    The arithmetic of :func:`sunset.model.waves.unit_normal` in the dtype of ``fx``.
    """
    if len(flat) == 0:
        return
    _put_unit_normals(np.ascontiguousarray(flat, np.intp), np.ascontiguousarray(fx), np.ascontiguousarray(fy),
                      fx.dtype.type(1.0), normal.reshape(-1, 3))


def assemble_geometry(best_u, best_surf, s_all, zeta, n_islands: int, out):
    """:func:`sunset.vector.direct.assemble_geometry` in one compiled pass (:func:`assemble`)."""
    return assemble(best_u, best_surf, s_all, zeta, SKY, SEA, n_islands, out)
