"""Numba twin of :mod:`sunset.light.paths`: the same float32 operations, one pixel at a time."""

from __future__ import annotations

import numpy as np

from ..constants import CLOUD, PART_CLIFF, POST, SEA, SKY
from ..kernels import jit

__all__ = ["trace_paths"]


@jit
def _layer(i0, i1, i2, m0, m1, m2, cos_i, before, n, up, weight, j):
    """One bounce's water into row j of ``up``/``weight``; returns the bounce's reflectance (float32)."""
    one = np.float32(1)
    zero = np.float32(0)
    n32 = np.float32(n)
    c = cos_i
    if c < zero:
        c = zero
    if c > one:
        c = one
    ct = np.sqrt(one - (one - c * c) / (n32 * n32))
    k = c / n32 - ct
    t0 = i0 / n32 + k * m0
    t1 = i1 / n32 + k * m1
    t2 = i2 / n32 + k * m2
    length = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    up[j, 0] = -t0 / length
    up[j, 1] = -t1 / length
    up[j, 2] = -t2 / length
    # the reflectance in float64 from the float32 cosine (reflectance64)
    c64 = np.float64(cos_i)
    if c64 < 0.0:
        c64 = 0.0
    if c64 > 1.0:
        c64 = 1.0
    ct64 = np.sqrt(1.0 - (1.0 - c64 * c64) / (n * n))
    s = (c64 - n * ct64) / (c64 + n * ct64)
    p = (n * c64 - ct64) / (n * c64 + ct64)
    r = 0.5 * (s * s + p * p)
    weight[j] = before * np.float32((1.0 - r) / (n * n))
    return np.float32(r)


@jit
def _paths(surface, final_surface, final_part, final_normal, direction, normal, incidence, sea_rays, n):
    count = surface.shape[0]
    kind = np.empty(count, np.int8)
    nrm = np.empty((count, 3), np.float32)
    throughput = np.empty(count, np.float32)
    n_sea = 0
    n_two = 0
    n_down = 0
    zero = np.float32(0)
    for i in range(count):
        fs = final_surface[i]
        if fs == SKY or fs == CLOUD:
            kind[i] = SKY
        elif fs == POST:
            kind[i] = PART_CLIFF
        else:
            kind[i] = final_part[i]
        for c in range(3):
            v = final_normal[i, c]
            nrm[i, c] = zero if np.isnan(v) else v
        throughput[i] = np.float32(1)
        if surface[i] == SEA:
            n_sea += 1
            two = np.isfinite(incidence[i, 1])
            if two:
                n_two += 1
            if sea_rays[i, 1 if two else 0, 2] < zero:
                n_down += 1
    index1 = np.empty(n_sea, np.intp)
    index2 = np.empty(n_two, np.intp)
    index3 = np.empty(n_down, np.intp)
    up1 = np.empty((n_sea, 3), np.float32)
    up2 = np.empty((n_two, 3), np.float32)
    up3 = np.empty((n_down, 3), np.float32)
    w1 = np.empty(n_sea, np.float32)
    w2 = np.empty(n_two, np.float32)
    w3 = np.empty(n_down, np.float32)
    j1 = 0
    j2 = 0
    j3 = 0
    for i in range(count):
        if surface[i] != SEA:
            continue
        index1[j1] = i
        tau = _layer(direction[i, 0], direction[i, 1], direction[i, 2], normal[i, 0], normal[i, 1], normal[i, 2],
                     incidence[i, 0], np.float32(1), n, up1, w1, j1)
        j1 += 1
        two = np.isfinite(incidence[i, 1])
        if two:
            a0 = sea_rays[i, 0, 0]
            a1 = sea_rays[i, 0, 1]
            a2 = sea_rays[i, 0, 2]
            d0 = sea_rays[i, 1, 0] - a0
            d1 = sea_rays[i, 1, 1] - a1
            d2 = sea_rays[i, 1, 2] - a2
            length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            if length < np.float32(1e-30):
                length = np.float32(1e-30)
            index2[j2] = i
            r = _layer(a0, a1, a2, d0 / length, d1 / length, d2 / length, incidence[i, 1], tau, n, up2, w2, j2)
            tau = tau * r
            j2 += 1
        last = 1 if two else 0
        lz = sea_rays[i, last, 2]
        if lz < zero:
            index3[j3] = i
            r = _layer(sea_rays[i, last, 0], sea_rays[i, last, 1], lz, zero, zero, np.float32(1), -lz, tau, n,
                       up3, w3, j3)
            tau = tau * r
            j3 += 1
        throughput[i] = tau
    return kind, nrm, throughput, index1, up1, w1, index2, up2, w2, index3, up3, w3


def trace_paths(surface, final_surface, final_part, final_normal, direction, normal, incidence, sea_rays, n: float):
    """:func:`sunset.light.paths.trace_paths`, compiled."""
    c = np.ascontiguousarray
    kind, nrm, tau, i1, u1, w1, i2, u2, w2, i3, u3, w3 = _paths(
        c(surface), c(final_surface), c(final_part), c(final_normal), c(direction), c(normal), c(incidence),
        c(sea_rays), float(n))
    return kind, nrm, tau, ((i1, u1, w1), (i2, u2, w2), (i3, u3, w3))
