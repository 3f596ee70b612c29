"""Numba twins of :mod:`sunset.vector.direct`: the direct frame's geometry in one pass.

:func:`assemble_geometry` builds directions, points, distances and the
compressed lists of sea and island pixels in one pass over the depth buffer;
:func:`put_unit_normals` writes the sea's unit normals, :func:`put_island_normals`
an island's parts and normals, element by element, with our own float32
sine and cosine (:mod:`sunset.vector.sincos_numba`). Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from ..kernels import jit as _jit
from .sincos_numba import cos32, sin32
from .slopes_numba import BLOCK, _normals_block, _scratch, slope_terms


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


def island_constants(island):
    """The island's constants for :func:`island_surface32`, float32.

    (X, Y, cliff height, 2e, e, f, g, 2g, cliff top, hill factor, beach
    height, e, f, g, 2e, 2g) and one row (ℓ, m, φ, a) per cosine term.
    """
    cl, bc = island.cliff, island.beach
    c = np.array([island.x, island.y, cl.height, 2.0 * cl.e, cl.e, cl.f, cl.g, 2.0 * cl.g, island.cliff_top,
                  island.hill_factor, bc.height, bc.e, bc.f, bc.g, 2.0 * bc.e, 2.0 * bc.g], np.float32)
    terms = np.array([[t.l, t.m, t.phase, t.amplitude] for t in island.cosines],
                     np.float32).reshape(len(island.cosines), 4)
    return c, terms


@_jit
def island_surface32(c, terms, x, yy, part_beach, part_cliff, part_hill):
    """An island's part and unit normal at (x, yy), float32: (part, n_x, n_y, n_z).

    :meth:`sunset.model.islands.Island.surface` and :func:`sunset.model.waves.unit_normal`
    in float32 with our own sine and cosine; ``c`` and ``terms`` are :func:`island_constants`'.
    """
    one = np.float32(1.0)
    dx = x - c[0]
    dy = yy - c[1]
    q = c[2] - (c[4] * dx * dx + c[5] * dx * dy + c[6] * dy * dy)
    qx = -(c[3] * dx + c[5] * dy)
    qy = -(c[5] * dx + c[7] * dy)
    for k in range(terms.shape[0]):
        ph = terms[k, 0] * x + terms[k, 1] * yy + terms[k, 2]
        q = q + terms[k, 3] * cos32(ph)
        sn = terms[k, 3] * sin32(ph)
        qx = qx - terms[k, 0] * sn
        qy = qy - terms[k, 1] * sn
    ct, phi = c[8], c[9]
    hill = q > ct
    upper = ct + phi * (q - ct) if hill else q
    beach = c[10] - (c[11] * dx * dx + c[12] * dx * dy + c[13] * dy * dy)
    if beach >= upper:
        p = part_beach
        gx = -(c[14] * dx + c[12] * dy)
        gy = -(c[12] * dx + c[15] * dy)
    else:
        p = part_hill if hill else part_cliff
        scale = phi if hill else one
        gx = scale * qx
        gy = scale * qy
    zb = one / np.sqrt(gx * gx + gy * gy + one)
    return p, -zb * gx, -zb * gy, zb


@_jit
def _island_normals(c, terms, normal, part, idx, s, y, part_beach, part_cliff, part_hill):
    for j in range(idx.shape[0]):
        p, n0, n1, n2 = island_surface32(c, terms, np.float32(s[j] * y[j]), np.float32(y[j]), part_beach, part_cliff,
                                         part_hill)
        at = idx[j]
        part[at] = p
        normal[at, 0] = n0
        normal[at, 1] = n1
        normal[at, 2] = n2


def put_island_normals(island, normal, part, idx, s, y) -> None:
    """:func:`sunset.vector.direct.put_island_normals` compiled: the island's surface at each pixel, in one loop.

    The float32 operations of :meth:`sunset.model.islands.Island.surface`
    (with the cosines and sines of :mod:`sunset.vector.sincos_numba`) and of
    :func:`sunset.model.waves.unit_normal`, pixel by pixel.
    """
    c, terms = island_constants(island)
    _island_normals(c, terms, normal.reshape(-1, 3), part.reshape(-1), idx, s, y, PART_BEACH, PART_CLIFF, PART_HILL)


#: Rows and columns of a tile of :func:`sea_geometry`: the depth buffer is read by scan lines (columns) and the
#: frame written by rows, so both go tile by tile, each tile's pieces of both in the cache.
TILE_ROWS, TILE_COLUMNS = 32, 64


@_jit
def _sea_geometry(best_u, best_surf, s_all, zeta, sea_code, surface, point, normal, l, m, c, lx, my, q, nq, block,
                  tile_rows, tile_columns):
    W, H = best_u.shape
    bflat = np.empty(block, np.intp)
    bs32 = np.empty(block, np.float32)
    by32 = np.empty(block, np.float32)
    th, sn, cs, acc, fx, fy = _scratch(block)
    n = 0
    for r0 in range(0, H, tile_rows):
        r1 = min(H, r0 + tile_rows)
        for c0 in range(0, W, tile_columns):
            c1 = min(W, c0 + tile_columns)
            for col in range(c0, c1):
                s = s_all[col]
                for row in range(r0, r1):
                    k = H - 1 - row
                    sc = best_surf[col, k]
                    surface[row, col] = sc
                    if sc == sea_code:
                        yv = 1.0 / best_u[col, k]
                        point[row, col, 0] = s * yv
                        point[row, col, 1] = yv
                        point[row, col, 2] = zeta[k] * yv
                        # gathered for the slopes, which run over a block at a time
                        bflat[n] = row * W + col
                        bs32[n] = np.float32(s)
                        by32[n] = np.float32(yv)
                        n += 1
                        if n == block:
                            _normals_block(bs32, by32, bflat, l, m, c, lx, my, q, nq, th, sn, cs, acc, fx, fy,
                                           normal)
                            n = 0
    if n:
        _normals_block(bs32[:n], by32[:n], bflat[:n], l, m, c, lx, my, q, nq, th, sn, cs, acc, fx, fy, normal)


def sea_geometry(best_u, best_surf, s_all, zeta, sea, t: float, surface, point, normal) -> None:
    """:func:`sunset.vector.direct.sea_geometry` in one compiled pass, tile by tile.

    The points as :func:`assemble`, the normals as
    :func:`sunset.vector.slopes_numba.put_sea_normals` (the slopes over
    blocks of the tile's sea pixels, gathered as they are met). A sea of
    trains: a wind sea is refused (:func:`sunset.vector.slopes_numba.slope_terms`);
    its kernel is :func:`sunset.vector.windsea_scan_numba.wind_sea_geometry`.
    """
    _sea_geometry(best_u, best_surf, np.ascontiguousarray(s_all, np.float64), np.ascontiguousarray(zeta, np.float64),
                  SEA, surface, point, normal.reshape(-1, 3), *slope_terms(sea, t), BLOCK, TILE_ROWS, TILE_COLUMNS)
