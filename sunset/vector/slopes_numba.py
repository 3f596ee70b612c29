"""Numba twins of the sea's slopes on the scan lines and of the sea pixels' unit normals.

:func:`sea_gradient_on_scanlines` is :func:`sunset.vector.heightfield.sea_gradient_on_scanlines`
compiled: per train, the phase b_j y + c_j in float32, its sine and cosine
from one reduction (our own vectorised float32 sine and cosine,
:func:`sunset.vector.sincos_numba.sincos_into`), Horner's rule for
q(cos θ) and the slopes subtracted, one pass each over a block of points
that stays in the cache. :func:`put_sea_normals` is
:func:`sunset.vector.direct.put_sea_normals`: the same slopes turned into
unit normals (:func:`sunset.model.waves.unit_normal` in float32) and written
into the frame's pixels in the same loop, with no slope arrays in between.
They agree with the NumPy reference within the tolerances of chapter 10
(tests). Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..kernels import jit as _jit
from .sincos_numba import sincos_into
from .heightfield import _F32, _chebyshev_power, _sea_terms

#: Points per block: the block's phases, sines, cosines and slopes stay in the cache.
BLOCK = 2048


def slope_terms(sea, t: float):
    """Each moving train's float32 constants: ℓ, m, c, the slope factors ℓ·scale, m·scale, and q's coefficients.

    Returns ``(l, m, c, lx, my, q, nq)``: arrays over the trains (q (trains,
    max len) float32, nq its lengths): q = p′, the derivative of
    Σ_n a_n T_n in powers of cos θ; with one coefficient the slope is
    sin θ and the scale q₀ goes into the factors. Kept for the
    last few (sea, t): every strip of a frame asks for the same (the arrays
    are only read).
    """
    return _slope_terms(sea, float(t), math.copysign(1.0, t))


@functools.lru_cache(maxsize=16)
def _slope_terms(sea, t: float, sign: float):
    """:func:`slope_terms`, cached; ``sign`` tells −0.0 from 0.0 (equal as keys, not always in the result)."""
    rows = []
    for l, m, _b, c, amps in _sea_terms(sea, np.zeros(0), t):
        q = np.polynomial.polynomial.polyder(_chebyshev_power(amps))
        scale = 1.0 if len(q) > 1 else q[0]
        rows.append((_F32(l), _F32(m), _F32(c), _F32(l * scale), _F32(m * scale), q))
    n = len(rows)
    width = max([len(r[5]) for r in rows] + [1])
    coef = np.zeros((n, width), _F32)
    nq = np.zeros(n, np.int64)
    for j, r in enumerate(rows):
        coef[j, :len(r[5])] = r[5].astype(_F32)
        nq[j] = len(r[5])
    cols = [np.array([r[i] for r in rows], _F32) for i in range(5)]
    return (*cols, coef, nq)


@_jit
def _slopes_block(s32, y32, l, m, c, lx, my, q, nq, th, sn, cs, acc, fx, fy):
    """fx, fy[0 : n] = the slopes at the n points (s32, y32), float32, one pass per train and step."""
    n = y32.shape[0]
    zero = np.float32(0.0)
    for i in range(n):
        fx[i] = zero
        fy[i] = zero
    for j in range(l.shape[0]):
        lj, mj, cj = l[j], m[j], c[j]
        for i in range(n):
            v = s32[i] * lj
            v = v + mj
            v = v * y32[i]
            th[i] = v + cj
        sincos_into(th[:n], sn[:n], cs[:n])
        k = nq[j]
        if k > 1:
            top = q[j, k - 1]
            for i in range(n):
                acc[i] = cs[i] * top
            for p in range(k - 2, 0, -1):
                qp = q[j, p]
                for i in range(n):
                    acc[i] = (acc[i] + qp) * cs[i]
            q0 = q[j, 0]
            for i in range(n):
                sn[i] = sn[i] * (acc[i] + q0)
        fl, fm = lx[j], my[j]
        for i in range(n):
            fx[i] = fx[i] - sn[i] * fl
            fy[i] = fy[i] - sn[i] * fm


@_jit
def _scratch(n):
    return (np.empty(n, np.float32), np.empty(n, np.float32), np.empty(n, np.float32), np.empty(n, np.float32),
            np.empty(n, np.float32), np.empty(n, np.float32))


@_jit
def _slopes(s32, y32, l, m, c, lx, my, q, nq, block, out_x, out_y):
    n = y32.shape[0]
    th, sn, cs, acc, fx, fy = _scratch(min(n, block))
    for a in range(0, n, block):
        b = min(n, a + block)
        _slopes_block(s32[a:b], y32[a:b], l, m, c, lx, my, q, nq, th, sn, cs, acc, fx, fy)
        for i in range(b - a):
            out_x[a + i] = fx[i]
            out_y[a + i] = fy[i]


@_jit
def _normals_block(s32, y32, flat, l, m, c, lx, my, q, nq, th, sn, cs, acc, fx, fy, normal):
    """The unit normals (−f_x, −f_y, 1)/|·| at the points (s32, y32) into the rows ``flat`` of ``normal`` (…, 3)."""
    _slopes_block(s32, y32, l, m, c, lx, my, q, nq, th, sn, cs, acc, fx, fy)
    one = np.float32(1.0)
    for i in range(y32.shape[0]):            # vectorised: z̄ into th, no scatter in this loop
        gx = fx[i]
        gy = fy[i]
        th[i] = one / np.sqrt(gx * gx + gy * gy + one)
    for i in range(y32.shape[0]):
        zb = th[i]
        at = flat[i]
        normal[at, 0] = -zb * fx[i]
        normal[at, 1] = -zb * fy[i]
        normal[at, 2] = zb


@_jit
def _normals(s32, y32, l, m, c, lx, my, q, nq, block, flat, normal):
    n = y32.shape[0]
    th, sn, cs, acc, fx, fy = _scratch(min(n, block))
    for a in range(0, n, block):
        b = min(n, a + block)
        _normals_block(s32[a:b], y32[a:b], flat[a:b], l, m, c, lx, my, q, nq, th, sn, cs, acc, fx, fy, normal)


def _points(s, y):
    s32 = np.ascontiguousarray(np.asarray(s, dtype=np.float64).astype(_F32).reshape(-1))
    y32 = np.ascontiguousarray(np.asarray(y, dtype=_F32).reshape(-1))
    return s32, y32


def sea_gradient_on_scanlines(sea, s, y, t: float = 0.0):
    """:func:`sunset.vector.heightfield.sea_gradient_on_scanlines` compiled (float32)."""
    shape = np.shape(y)
    s32, y32 = _points(s, y)
    fx = np.empty(y32.shape, _F32)
    fy = np.empty(y32.shape, _F32)
    if y32.size:
        _slopes(s32, y32, *slope_terms(sea, t), BLOCK, fx, fy)
    return fx.reshape(shape), fy.reshape(shape)


def put_sea_normals(sea, t: float, normal, idx, s, y) -> None:
    """:func:`sunset.vector.direct.put_sea_normals` compiled: the slopes and the unit normals in one pass.

    A sea of trains: a wind sea is refused (:func:`slope_terms`); its normals are
    :func:`sunset.vector.windsea_scan_numba.wind_normals`'.
    """
    if len(idx) == 0:
        return
    s32, y32 = _points(s, y)
    _normals(s32, y32, *slope_terms(sea, t), BLOCK, np.ascontiguousarray(idx, np.intp), normal.reshape(-1, 3))
