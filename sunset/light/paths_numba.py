"""Numba twin of :mod:`sunset.light.paths`: the same formulas, one pixel at a time.

Within :data:`PATHS_RTOL` of the reference (``tests/light/test_kernels.py``).
"""

from __future__ import annotations

import numpy as np

from ..constants import CLOUD, PART_CLIFF, POST, SEA, SKY
from ..kernels import jit

__all__ = ["trace_paths", "lookups", "PATHS_RTOL"]

#: The paths' float fields (the water's directions and weights, the throughput, the tables' fractions),
#: relative to the field's largest value. Measured: no difference on the packaged scenes' frames (the same
#: formulas in IEEE's correctly rounded +, −, ×, ÷ and √); allowed: one float32 ulp.
PATHS_RTOL = 2.0**-23


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
    # the reflectance in float64 from the float32 cosine (sunset.light.fresnel.reflectance)
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


@jit
def _lookups(ray, final_surface, bounces, point, kind, normal, offset, depth, has_depth, scale, g_max):
    count = kind.shape[0]
    n_sky = 0
    n_isl = 0
    for i in range(count):
        if kind[i] == SKY:
            n_sky += 1
        elif kind[i] > 0:
            n_isl += 1
    sky_index = np.empty(n_sky, np.intp)
    sky_dir = np.empty((n_sky, 3), np.float32)
    sky_cloud = np.empty(n_sky if has_depth else 0, np.float32)
    isl_index = np.empty(n_isl, np.intp)
    isl_normal = np.empty((n_isl, 3), np.float32)
    isl_g = np.empty((n_isl, 2), np.int32)
    isl_f = np.empty((n_isl, 2), np.float32)
    isl_point = np.empty((n_isl, 3), np.float32)
    nan32 = np.float32(np.nan)
    js = 0
    ji = 0
    for i in range(count):
        if kind[i] == SKY:
            sky_index[js] = i + offset
            for c in range(3):
                sky_dir[js, c] = ray[i, c]
            if has_depth:
                sky_cloud[js] = np.float32(depth[i]) if final_surface[i] == CLOUD else nan32
            js += 1
        elif kind[i] > 0:
            isl_index[ji] = i + offset
            for c in range(3):
                isl_normal[ji, c] = normal[i, c]
                isl_point[ji, c] = np.float32(point[i, c]) if bounces[i] == 0 else nan32
            for c in range(2):
                v = np.float64(normal[i, c])
                if v < -1.0:
                    v = -1.0
                if v > 1.0:
                    v = 1.0
                g = (v + 1.0) * scale
                g0 = np.int32(g)
                if g0 > g_max:
                    g0 = np.int32(g_max)
                isl_g[ji, c] = g0
                isl_f[ji, c] = np.float32(g - g0)
            ji += 1
    return sky_index, sky_dir, sky_cloud, isl_index, isl_normal, isl_g, isl_f, isl_point


def lookups(ray, final_surface, bounces, point, kind, normal, offset: int, depth=None) -> dict:
    """:func:`sunset.light.paths.lookups`, compiled: one pass, the arcsine and arctangent NumPy's."""
    from .lighting import NORMAL_GRID, SKY_REFINE, SKY_ROWS, sky_row

    c = np.ascontiguousarray
    has_depth = depth is not None
    sky_index, fd, cloud, isl_index, isl_normal, g0, f, pt = _lookups(
        c(ray), c(final_surface), c(bounces), c(point), c(kind), c(normal), int(offset),
        c(depth) if has_depth else np.zeros(1, np.float32), has_depth, 0.5 * (NORMAL_GRID - 1), NORMAL_GRID - 2)
    r_max = (SKY_ROWS - 1) * SKY_REFINE[0]
    rows = np.clip(sky_row(fd[:, 2]) * SKY_REFINE[0], 0, r_max)
    r0 = np.minimum(rows.astype(np.int32), r_max - 1)
    out = {"sky_index": sky_index, "sky_dir": fd, "sky_r0": r0, "sky_fr": (rows - r0).astype(np.float32),
           "sky_azimuth": np.arctan2(fd[:, 1], fd[:, 0]), "island_index": isl_index,
           "island_normal": isl_normal, "island_g": g0, "island_f": f, "island_point": pt}
    if has_depth:
        out["sky_cloud"] = cloud
    return out
