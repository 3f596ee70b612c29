"""Numba twins of :mod:`sunset.light.kernel`: the same float32 operations, one pixel at a time."""

from __future__ import annotations

import math

import numpy as np

from ..kernels import jit
from .kernel import PHASE_NORM
from .water import PHASE_ANISOTROPY

__all__ = ["sky_pixels", "island_pixels", "combine"]


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
def _linear_rgb(xyz, scale, m, lin, y):
    for i in range(xyz.shape[0]):
        x0 = np.float64(xyz[i, 0]) / scale
        x1 = np.float64(xyz[i, 1]) / scale
        x2 = np.float64(xyz[i, 2]) / scale
        for c in range(3):
            v = x0 * m[0, c] + x1 * m[1, c] + x2 * m[2, c]
            lin[i, c] = max(v, 0.0)
        y[i] = max(x1, 0.0)


@jit
def _respond(lin, y, a, s_n, out):
    for i in range(lin.shape[0]):
        resp = a[i] / (a[i] + s_n)
        yi = y[i]
        k = resp / yi if yi > 1e-12 else 0.0
        r0 = lin[i, 0] * k
        r1 = lin[i, 1] * k
        r2 = lin[i, 2] * k
        top = max(max(r0, r1), r2)
        t = (top - 1.0) / (top - resp) if top > 1.0 else 0.0
        for c, r in enumerate((r0, r1, r2)):
            v = (1.0 - t) * r + t * resp
            out[i, c] = min(max(v, 0.0), 1.0)


def display_pixels(xyz, scale, m, exponent, semi_saturation) -> np.ndarray:
    """:func:`sunset.light.kernel.display_pixels`, compiled (the power yⁿ stays NumPy's)."""
    xyz = np.ascontiguousarray(xyz)
    n = xyz.shape[0]
    lin = np.empty((n, 3))
    y = np.empty(n)
    _linear_rgb(xyz, float(scale), np.ascontiguousarray(m, np.float64), lin, y)
    a = np.power(y, exponent)
    out = np.empty((n, 3))
    _respond(lin, y, a, semi_saturation ** exponent, out)
    return out
