"""The compiled twin of :func:`sunset.pipeline.frame.code_strip`: a strip of rows coded in one fused pass.

The Cray-1 chained its vector instructions: the result of one flowed into the
next in the registers, 64 elements at a time, and never went back to memory
between them. This is the same for a strip of rows of a frame. The stages'
NumPy references run one after the other over the strip's arrays (the
direct rays' geometry, the reflected rays, the codes: what the book shows);
here every pixel of the strip goes through all of them at once:

* a pixel of sky or island is coded where it is met in the depth buffer: its
  direction (:func:`sunset.vector.direct_numba.assemble`'s arithmetic), on an
  island its part and normal (:func:`sunset.vector.direct_numba.island_surface32`),
  then its code (:func:`sunset.tape.codes_numba.sky_code`, :func:`sunset.tape.codes_numba.island_code`);
* a sea pixel's direction and hit point are gathered into a block of
  :data:`BLOCK` rays; a full block gets its normals (the slopes' block of
  :func:`sunset.vector.slopes_numba._normals_block`), its reflections, the
  crests and the islands (:func:`sunset.vector.reflect_numba.bounce_block`),
  and each ray its code.

No field of the strip is written to memory but the codes. The operations are
the stage twins' own, in the same order, with the same float32 roundings
where their fields are stored (a direction, a point, a normal, a final ray,
a final normal): the codes are the same bytes as those twins' one after the
other (tests), and so within the tolerances of chapter 10 of the NumPy
reference's. Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from ..errors import SunsetError
from ..kernels import jit as _jit
from ..tape.codes_numba import _dither_at, code_constants, island_code, sky_code
from ..vector.direct_numba import island_constants, island_surface32
from ..vector.reflect_numba import _island_normal, bounce_block, reflect_constants
from ..vector.slopes_numba import _normals_block, _scratch, slope_terms

__all__ = ["BLOCK", "TILE_COLUMNS", "code_strip", "frame_constants"]

#: Sea rays per block: the block's directions, points, normals, phases and rays stay in a core's cache.
BLOCK = 512
#: Scan lines per tile: the depth buffer is read by scan lines (columns) and the codes written by rows, so a
#: strip goes tile by tile, each tile's pieces of both in the cache.
TILE_COLUMNS = 64

_F32 = np.float32
#: Scan lines ahead of the one being read whose pieces of the depth buffer are fetched into the cache.
PREFETCH_AHEAD = 4


@intrinsic
def _prefetch(typingctx, address):
    """Ask the processor to bring the cache line at ``address`` (an integer) into its caches (``llvm.prefetch``)."""
    sig = types.void(types.intp)

    def codegen(context, builder, signature, args):
        i8p = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        fn = builder.module.declare_intrinsic("llvm.prefetch", [i8p], ir.FunctionType(ir.VoidType(),
                                                                                        [i8p, i32, i32, i32]))
        builder.call(fn, [builder.inttoptr(args[0], i8p), i32(0), i32(3), i32(1)])
        return context.get_dummy_value()
    return sig, codegen


@_jit
def _prefetch_rows(base, start, stop):
    """Prefetch the bytes ``start:stop`` after the address ``base``, line by line (64 bytes)."""
    for off in range(start - start % 64, stop, 64):
        _prefetch(base + off)


@_jit
def _sea_block(m, r0, W, ys, xs, s32, y32, flat, dirs, pnts, nrm, l, mm, c, lx, my, q, nq, th, sn, cs, acc, fx, fy,
               qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps, waves, coef, count, inc,
               rays, h2, flags, table, normals, nterms, h, best, which, part, seed, U, V, Wv, part_codes,
               island_start, island_size, sky_start, sky_size, track_start, track_size, halo_start, halo_size,
               dither, sin_d, sin_halo, e_max, codes):
    """A block of ``m`` gathered sea pixels: their normals, their rays to the end of their path, their codes."""
    _normals_block(s32[:m], y32[:m], flat[:m], l, mm, c, lx, my, q, nq, th, sn, cs, acc, fx, fy, nrm)
    for j in range(m):
        # the reflected ray R = D − 2(D·N)N, float64 from the float32
        # fields (as sunset.vector.reflect_numba.trace_strip)
        dx = np.float64(dirs[j, 0])
        dy = np.float64(dirs[j, 1])
        dz = np.float64(dirs[j, 2])
        nx = np.float64(nrm[j, 0])
        ny = np.float64(nrm[j, 1])
        nz = np.float64(nrm[j, 2])
        two = 2.0 * (dx * nx + dy * ny + dz * nz)
        qx[j] = np.float64(pnts[j, 0])
        qy[j] = np.float64(pnts[j, 1])
        qz[j] = np.float64(pnts[j, 2])
        rx[j] = dx - two * nx
        ry[j] = dy - two * ny
        rz[j] = dz - two * nz
        bounces[j] = 1
    bounce_block(m, ys, xs, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps, waves, coef,
                 count, False, inc, rays, h2, flags, table, h, PART_BEACH, PART_CLIFF, PART_HILL, SKY, best, which,
                 part)
    for j in range(m):
        n = ys[j] * W + xs[j]
        uu = _dither_at(seed, n, 0)
        if which[j] > 0:
            t = best[j]
            ax, ay, az = _island_normal(qx[j] + t * rx[j], qy[j] + t * ry[j], part[j], normals[which[j] - 1], nterms,
                                        PART_BEACH, PART_HILL)
            code = island_code(np.float64(np.float32(ax)), np.float64(np.float32(ay)), np.float64(np.float32(az)),
                               part[j], uu, U, V, part_codes, island_start, island_size)
        else:
            code = sky_code(np.float64(np.float32(rx[j])), np.float64(np.float32(ry[j])),
                            np.float64(np.float32(rz[j])), bounces[j] > 0, seed, n, uu, Wv[0], Wv[1], Wv[2],
                            sky_start, sky_size, track_start, track_size, halo_start, halo_size, dither, sin_d,
                            sin_halo, e_max)
        codes[ys[j] - r0, xs[j]] = code


@_jit
def _code_strip(best_u, best_surf, s_all, zeta, r0, r1, use_still, still, l, mm, c, lx, my, q, nq, isl_c, isl_terms,
                isl_first, second, crest, amps, waves, coef, count, table, normals, nterms, h, seed, U, V, Wv,
                part_codes, island_start, island_size, sky_start, sky_size, track_start, track_size, halo_start,
                halo_size, dither, sin_d, sin_halo, e_max, codes, tile_columns):
    """The codes of the rows ``r0:r1`` (top down) into ``codes`` (r1 − r0, W), tile by tile of scan lines; the first
    unknown island part met (0: none)."""
    W, H = best_u.shape
    B = BLOCK
    ys = np.empty(B, np.int64)
    xs = np.empty(B, np.int64)
    flat = np.arange(B)
    s32 = np.empty(B, np.float32)
    y32 = np.empty(B, np.float32)
    dirs = np.empty((B, 3), np.float32)
    pnts = np.empty((B, 3), np.float32)
    nrm = np.empty((B, 3), np.float32)
    th, sn, cs, acc, fx, fy = _scratch(B)
    qx, qy, qz = np.empty(B), np.empty(B), np.empty(B)
    rx, ry, rz = np.empty(B), np.empty(B), np.empty(B)
    h2, best, psi = np.empty(B), np.empty(B), np.empty(B)
    bounces = np.empty(B, np.uint8)
    which = np.empty(B, np.int8)
    part = np.empty(B, np.int8)
    keep = np.empty(B, np.bool_)
    scratch = np.empty((5, B))
    flags = np.empty((max(table.shape[0], 1), B), np.bool_)
    inc = np.zeros((1, 1, 2), np.float32)
    rays = np.zeros((1, 1, 2, 3), np.float32)
    m = 0
    # the strip's rows are the scan lines' pixels k_lo..k_hi; each scan line's piece of the depth buffer is
    # a short run (the buffer is stored by scan lines), fetched a few scan lines ahead
    k_lo, k_hi = H - r1, H - r0
    u_base, s_base = best_u.ctypes.data, best_surf.ctypes.data
    for c0 in range(0, W, tile_columns):
        for col in range(c0, min(W, c0 + tile_columns)):
            ahead = col + PREFETCH_AHEAD
            if ahead < W:
                _prefetch_rows(u_base + ahead * H * 8, k_lo * 8, k_hi * 8)
                _prefetch_rows(s_base + ahead * H, k_lo, k_hi)
            s = s_all[col]
            for row in range(r0, r1):
                k = H - 1 - row
                sc = best_surf[col, k]
                if use_still and sc != SEA:
                    codes[row - r0, col] = still[row - r0, col]
                    continue
                z = zeta[k]
                # the direction, as sunset.vector.direct_numba's
                length = math.sqrt(1.0 + s * s + z * z)
                inv = 1.0 / length
                if sc == SEA:
                    yv = 1.0 / best_u[col, k]
                    ys[m] = row
                    xs[m] = col
                    dirs[m, 0] = s * inv
                    dirs[m, 1] = inv
                    dirs[m, 2] = z * inv
                    pnts[m, 0] = s * yv
                    pnts[m, 1] = yv
                    pnts[m, 2] = z * yv
                    s32[m] = np.float32(s)
                    y32[m] = np.float32(yv)
                    m += 1
                    if m == B:
                        _sea_block(m, r0, W, ys, xs, s32, y32, flat, dirs, pnts, nrm, l, mm, c, lx, my, q, nq, th, sn,
                                   cs, acc, fx, fy, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch,
                                   crest, amps, waves, coef, count, inc, rays, h2, flags, table, normals, nterms, h,
                                   best, which, part, seed, U, V, Wv, part_codes, island_start, island_size,
                                   sky_start, sky_size, track_start, track_size, halo_start, halo_size, dither, sin_d,
                                   sin_halo, e_max, codes)
                        m = 0
                    continue
                n = row * W + col
                uu = _dither_at(seed, n, 0)
                if sc == SKY:
                    code = sky_code(np.float64(np.float32(s * inv)), np.float64(np.float32(inv)),
                                    np.float64(np.float32(z * inv)), False, seed, n, uu, Wv[0], Wv[1], Wv[2],
                                    sky_start, sky_size, track_start, track_size, halo_start, halo_size, dither,
                                    sin_d, sin_halo, e_max)
                else:
                    yv = 1.0 / best_u[col, k]
                    i = sc - 1
                    p, n0, n1, n2 = island_surface32(isl_c[i], isl_terms[isl_first[i]:isl_first[i + 1]],
                                                     np.float32(s * yv), np.float32(yv), PART_BEACH, PART_CLIFF,
                                                     PART_HILL)
                    code = island_code(np.float64(n0), np.float64(n1), np.float64(n2), p, uu, U, V, part_codes,
                                       island_start, island_size)
                    if code < 0:
                        return p
                codes[row - r0, col] = code
    if m:
        _sea_block(m, r0, W, ys, xs, s32, y32, flat, dirs, pnts, nrm, l, mm, c, lx, my, q, nq, th, sn, cs, acc, fx,
                   fy, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps, waves, coef, count,
                   inc, rays, h2, flags, table, normals, nterms, h, best, which, part, seed, U, V, Wv, part_codes,
                   island_start, island_size, sky_start, sky_size, track_start, track_size, halo_start, halo_size,
                   dither, sin_d, sin_halo, e_max, codes)
    return 0


@functools.lru_cache(maxsize=16)
def _island_tables(islands) -> tuple:
    """Every island's float32 constants for :func:`sunset.vector.direct_numba.island_surface32`, stacked: (rows
    (K, 16), cosine terms (T, 4), where island k's terms start (K + 1,))."""
    rows, terms, first = [], [], [0]
    for island in islands:
        cst, trm = island_constants(island)
        rows.append(cst)
        terms.append(trm)
        first.append(first[-1] + len(trm))
    return (np.array(rows, np.float32).reshape(len(rows), 16),
            np.concatenate(terms).astype(np.float32) if terms else np.zeros((0, 4), np.float32),
            np.array(first, np.int64))


_NO_STILL = np.zeros((1, 1), np.uint8)

#: The last frame's constants: (scene, code map, (t, sign of t, reflections), constants). A frame's strips
#: all ask for the same; taking them again per strip (the islands' tables, hashing the scene) cost about as
#: much as a strip of a cycle's frame.
_LAST: list = [None]


def frame_constants(scene, t: float, reflections: int, cmap) -> tuple:
    """What :func:`_code_strip` needs of the scene at ``t`` besides the strip: the reflections'
    (:func:`sunset.vector.reflect_numba.reflect_constants`), the islands' (:func:`_island_tables`), the
    slopes' (:func:`sunset.vector.slopes_numba.slope_terms`) and the codes' (:func:`sunset.tape.codes_numba.code_constants`).

    Kept for the last (scene, t, reflections, code map), the same objects (a scene is frozen): the strips
    of a frame, on any thread, share them (they are only read).
    """
    key = (float(t), math.copysign(1.0, t), int(reflections))
    last = _LAST[0]
    if last is not None and last[0] is scene and last[1] is cmap and last[2] == key:
        return last[3]
    do_second, second, table, normals, nterms, h = reflect_constants(scene, float(t), reflections)
    consts = ((do_second, *second, table, normals, nterms, h), _island_tables(scene.islands),
              slope_terms(scene.sea, t), code_constants(scene.sun, cmap))
    _LAST[0] = (scene, cmap, key, consts)
    return consts


def code_strip(scene, t: float, reflections: int, seed: int, depth, r0: int, r1: int, cmap, codes,
               still=None) -> None:
    """:func:`sunset.pipeline.frame.code_strip` in one compiled pass over the strip (:func:`_code_strip`)."""
    best_u, best_surf, s_all, zeta = depth
    bounce, (isl_c, isl_terms, isl_first), slopes, code_consts = frame_constants(scene, t, reflections, cmap)
    bad = _code_strip(best_u, best_surf, np.ascontiguousarray(s_all, np.float64),
                      np.ascontiguousarray(zeta, np.float64), int(r0), int(r1), still is not None,
                      _NO_STILL if still is None else still.codes[r0:r1], *slopes, isl_c,
                      isl_terms, isl_first, *bounce, int(seed),
                      *code_consts, codes, TILE_COLUMNS)
    if bad:
        raise SunsetError(f"frame.final_part must be 1 (beach), 2 (cliff) or 3 (hill) on islands, got {bad}")
