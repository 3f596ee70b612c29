"""Numba twins of :mod:`sunset.light.kernel`: the same formulas, one pixel at a time.

Not the references' bits (NumPy's matrix products, its ``pow`` and its means
take their own order and kernels); within, measured on the packaged scenes'
frames and on hostile values (``tests/light/test_kernels.py``):
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels import jit
from .kernel import PHASE_NORM
from .water import PHASE_ANISOTROPY

__all__ = ["sky_pixels", "island_pixels", "combine", "display_pixels", "display_box", "RADIANCE_RTOL",
           "DISPLAY_ATOL"]

#: The shaded radiances (float32, :func:`sky_pixels`, :func:`island_pixels`, :func:`combine`), relative to each
#: pixel's largest channel. Measured: no difference, on the packaged scenes' frames (0–2 reflections, two times,
#: four hours); allowed: four float32 ulps, for a dot product that another processor's BLAS takes with fused
#: multiply-adds.
RADIANCE_RTOL = 4 * 2.0**-23
#: The display values in [0, 1] (float64, :func:`display_pixels`, :func:`display_box`), absolute. Measured on the
#: same frames: 3.3e-16 (the matrix product's and the box's order of addition, and ``pow``); on hostile values
#: 3.2e-15, where a pixel past full scale bleaches, (top − 1)/(top − response) with top near the response.
DISPLAY_ATOL = 1e-14


@jit
def _sky(r0, fr, az, dirs, table, saz, cscale, s0, s1, s2, cos_delta, sun_xyz, out):
    c_max = table.shape[1] - 1
    pi = np.float32(math.pi)
    two_pi = np.float32(2 * math.pi)
    inv_pi = np.float32(1 / math.pi)
    one = np.float32(1)
    zero = np.float32(0)
    for i in range(az.shape[0]):
        d = az[i] - saz
        if d > pi:
            d = d - two_pi
        if d < -pi:
            d = d + two_pi
        col = np.sqrt(np.abs(d) * inv_pi) * cscale
        if col > np.float32(c_max):
            col = np.float32(c_max)
        c0 = np.int32(col)
        if c0 > c_max - 1:
            c0 = c_max - 1
        fc = col - np.float32(c0)
        r = r0[i]
        f = fr[i]
        dot = dirs[i, 0] * s0 + dirs[i, 1] * s1 + dirs[i, 2] * s2
        inside = (dot > cos_delta) and (dirs[i, 2] >= zero)
        for k in range(3):
            top = table[r, c0, k] * (one - fc) + table[r, c0 + 1, k] * fc
            bottom = table[r + 1, c0, k] * (one - fc) + table[r + 1, c0 + 1, k] * fc
            v = top * (one - f) + bottom * f
            if inside:
                v = v + sun_xyz[k]
            out[i, k] = v


def sky_pixels(r0, fr, az, dirs, table, sun_azimuth, col_scale, sun_dir, cos_delta, sun_xyz) -> np.ndarray:
    """:func:`sunset.light.kernel.sky_pixels`, compiled."""
    s = np.asarray(sun_dir, np.float32)
    out = np.empty((len(az), 3), np.float32)
    _sky(r0, fr, az, dirs, table, np.float32(sun_azimuth), np.float32(col_scale), s[0], s[1], s[2],
         np.float32(cos_delta), np.asarray(sun_xyz, np.float32), out)
    return out


@jit
def _island(normals, part, g0, g1, fx, fy, s0, s1, s2, direct, table, out):
    one = np.float32(1)
    zero = np.float32(0)
    for i in range(part.shape[0]):
        cos = normals[i, 0] * s0 + normals[i, 1] * s1 + normals[i, 2] * s2
        if cos < zero:
            cos = zero
        p = part[i]
        a = g0[i]
        b = g1[i]
        x = fx[i]
        y = fy[i]
        for k in range(3):
            top = table[p, a, b, k] * (one - y) + table[p, a, b + 1, k] * y
            bottom = table[p, a + 1, b, k] * (one - y) + table[p, a + 1, b + 1, k] * y
            out[i, k] = cos * direct[p, k] + (top * (one - x) + bottom * x)


def island_pixels(normals, part, g0, g1, fx, fy, sun_dir, direct, table) -> np.ndarray:
    """:func:`sunset.light.kernel.island_pixels`, compiled."""
    s = np.asarray(sun_dir, np.float32)
    out = np.empty((len(part), 3), np.float32)
    _island(normals, part, g0, g1, fx, fy, s[0], s[1], s[2], direct, table, out)
    return out


@jit
def _combine(throughput, sky_index, sky, island_index, island, w_index, w_up, w_mu, w_weight, w_sky,
             b0, b1, b2, mu_beam, ws, wk, out):
    for j in range(sky_index.shape[0]):
        i = sky_index[j]
        for k in range(3):
            out[i, k] = sky[j, k]
    for j in range(island_index.shape[0]):
        i = island_index[j]
        for k in range(3):
            out[i, k] = island[j, k]
    for i in range(out.shape[0]):
        t = throughput[i]
        for k in range(3):
            out[i, k] = out[i, k] * t
    one = np.float32(1)
    aniso = np.float32(PHASE_ANISOTROPY)
    norm = np.float32(PHASE_NORM)
    for j in range(w_index.shape[0]):
        i = w_index[j]
        c = w_up[j, 0] * b0 + w_up[j, 1] * b1 + w_up[j, 2] * b2
        phase = (one + aniso * c * c) * norm
        f_sun = phase / (mu_beam + w_mu[j]) * w_weight[j]
        for k in range(3):
            out[i, k] = out[i, k] + (f_sun * ws[k] + w_sky[j] * wk[k])


def combine(n_pixels, throughput, sky_index, sky, island_index, island, layer_starts, w_index, w_up, w_mu, w_weight,
            w_sky, beam, mu_beam, water_sun, water_sky) -> np.ndarray:
    """:func:`sunset.light.kernel.combine`, compiled (the layers' entries in order)."""
    b = np.asarray(beam, np.float32)
    out = np.zeros((n_pixels, 3), np.float32)
    _combine(throughput, sky_index, sky, island_index, island, w_index, w_up, w_mu, w_weight, w_sky,
             b[0], b[1], b[2], np.float32(mu_beam), np.asarray(water_sun, np.float32),
             np.asarray(water_sky, np.float32), out)
    return out


@jit
def _respond_one(l0, l1, l2, yi, ai, s_n):
    resp = ai / (ai + s_n)
    k = resp / yi if yi > 1e-12 else 0.0
    r0 = l0 * k
    r1 = l1 * k
    r2 = l2 * k
    top = max(max(r0, r1), r2)
    t = (top - 1.0) / (top - resp) if top > 1.0 else 0.0
    v0 = min(max((1.0 - t) * r0 + t * resp, 0.0), 1.0)
    v1 = min(max((1.0 - t) * r1 + t * resp, 0.0), 1.0)
    v2 = min(max((1.0 - t) * r2 + t * resp, 0.0), 1.0)
    return v0, v1, v2


@jit
def _box_into(lin, y, a, s_n, row0, wk, c, k, out):
    """out[:] = the mean response of the k × k input pixels of output column ``c``, the first of
    whose k rows starts at ``row0`` (k rows of ``wk`` pixels), summed in row order."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(k):
        for j in range(k):
            p = row0 + i * wk + c * k + j
            v0, v1, v2 = _respond_one(lin[p, 0], lin[p, 1], lin[p, 2], y[p], a[p], s_n)
            s0 += v0
            s1 += v1
            s2 += v2
    kk = k * k
    out[0] = s0 / kk
    out[1] = s1 / kk
    out[2] = s2 / kk


@jit
def _display_fused(flat, scale, m, e, s_n, k, wk, out):
    """The linear RGB (x·m), yⁿ, the response and the k × k box, one row of output pixels at a time: the k
    input rows' linear RGB and Y, their powers in one tight loop, then the response and the box."""
    n_row = k * wk
    lin = np.empty((n_row, 3))
    y = np.empty(n_row)
    a = np.empty(n_row)
    for r in range(out.shape[0]):
        base = r * n_row
        for q in range(n_row):
            x0 = np.float64(flat[base + q, 0]) / scale
            x1 = np.float64(flat[base + q, 1]) / scale
            x2 = np.float64(flat[base + q, 2]) / scale
            for c in range(3):
                lin[q, c] = max(x0 * m[0, c] + x1 * m[1, c] + x2 * m[2, c], 0.0)
            y[q] = max(x1, 0.0)
        for q in range(n_row):
            a[q] = y[q] ** e
        for c in range(out.shape[1]):
            _box_into(lin, y, a, s_n, 0, wk, c, k, out[r, c])


def display_pixels(xyz, scale, m, exponent, semi_saturation) -> np.ndarray:
    """:func:`sunset.light.kernel.display_pixels`, compiled: one pass."""
    xyz = np.ascontiguousarray(xyz)
    n = xyz.shape[0]
    out = np.empty((1, n, 3))
    _display_fused(xyz, float(scale), np.ascontiguousarray(m, np.float64), float(exponent),
                   semi_saturation ** exponent, 1, n, out)
    return out.reshape(n, 3)


def display_box(xyz, scale, m, exponent, semi_saturation, k: int) -> np.ndarray:
    """:func:`sunset.light.kernel.display_box`, compiled: one pass, the k × k samples added in row order."""
    hk, wk = xyz.shape[:2]
    out = np.empty((hk // k, wk // k, 3))
    _display_fused(np.ascontiguousarray(xyz).reshape(-1, 3), float(scale), np.ascontiguousarray(m, np.float64),
                   float(exponent), semi_saturation ** exponent, int(k), wk, out)
    return out
