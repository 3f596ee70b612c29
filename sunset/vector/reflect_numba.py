"""Numba twin of :func:`sunset.vector.reflect.trace_sea_rays`: the reflected rays of a strip in two compiled passes.

* :func:`sunset.vector.crests_numba.sea_rays` gathers the sea pixels of the
  strip and reflects their rays (R = D − 2(D·N)N, :func:`sunset.vector.pierce.reflect`);
  with two reflections it pierces each ray's crest cylinder and reflects the
  hits again off the true wave normal, all in the same loop, with the crest's
  cosine and the wave normal's sines and cosines taken there (float64, the C
  library's, as NumPy's); it records the bounces for the RGB back end and
  folds R_z up.
* :func:`pierce_write` is :func:`sunset.vector.pierce.pierce_islands` (each
  ray against every island's bounding circle, then the three quadratics, the
  nearest hit kept) with the final fields written straight into the frame.
* :func:`pierce_islands` and :func:`crest_hits` are the compiled island and
  crest piercing on their own (the tests hold them against the reference's).

The island normals of the rays that hit are taken in the same loop
(:func:`_island_normal`, :func:`sunset.vector.pierce.island_normal`'s operations). The same
operations in the same order as the NumPy reference: the frames are
identical (tests). Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from ..kernels import jit as _jit
from .crests_numba import _quadratic, crest_constants, crest_distance, sea_rays, second_bounce_constants
from .frame import Frame


@_jit
def _crest_all(q, r, crest, amps, out):
    for j in range(q.shape[0]):
        out[j] = crest_distance(q[j, 0], q[j, 1], q[j, 2], r[j, 0], r[j, 1], r[j, 2], crest, amps)


def crest_hits(train, t: float, q, r) -> np.ndarray:
    """Distance along each ray (N, 3) to its crest cylinder, +inf where it clears the crest.

    :func:`sunset.vector.pierce.first_entry` of the cylinder of
    :func:`sunset.vector.crests.crest_cylinder` after the bounding test of
    :func:`sunset.vector.crests.crest_candidates`, one compiled loop
    (:func:`sunset.vector.crests_numba.crest_distance`).
    """
    q = np.ascontiguousarray(q, dtype=np.float64)
    r = np.ascontiguousarray(r, dtype=np.float64)
    out = np.empty(len(q))
    crest, amps = crest_constants(train, t)
    _crest_all(q, r, crest, amps, out)
    return out


#: Columns of :func:`island_table`.
_ISLAND_COLUMNS = ("x", "y", "ce", "cf", "cg", "c_top", "ct", "k", "be", "bf", "bg", "b_top", "rho", "top_h")


def island_table(islands, eye_height: float, z0: float) -> np.ndarray:
    """The islands' parameters as rows of a float64 table for :func:`pierce_islands`.

    Heights are turned into eye coordinates exactly as :func:`sunset.vector.pierce.island_intervals`
    does; ``rho`` and ``top_h`` are the bounding circle of
    :func:`sunset.vector.pierce.island_candidates` for origins no lower than ``z0``.
    """
    h = float(eye_height)
    rows = []
    for isl in islands:
        rho, top = isl.smooth_radius(h + z0), isl.smooth_height
        cl, bc = isl.cliff, isl.beach
        rows.append([isl.x, isl.y, cl.e, cl.f, cl.g, cl.height, isl.cliff_top, isl.hill_factor,
                     bc.e, bc.f, bc.g, bc.height, rho, top - h])
    return np.array(rows, dtype=np.float64).reshape(len(rows), len(_ISLAND_COLUMNS))


@_jit
def _is_candidate(qx, qy, qz, rx, ry, rz, horiz, X, Y, rho, top_h):
    """The bounding test of sunset.vector.pierce.island_candidates for one ray and one island.

    ``horiz`` = √(R_x² + R_y²), the same for every island (taken once per ray).
    """
    cx = X - qx
    cy = Y - qy
    along = rx * cx + ry * cy
    near_line = (abs(rx * cy - ry * cx) <= rho * horiz) & (along > -rho * horiz)
    low_enough = (along - rho * horiz) * rz <= (top_h - qz) * horiz * horiz
    return (rz < 0.0) | (near_line & low_enough) | (cx * cx + cy * cy <= rho * rho)


@_jit
def _pierce_one(qx, qy, qz, rx, ry, rz, row, h, part_beach, part_cliff, part_hill):
    """sunset.vector.pierce.pierce_island for one ray: (distance, part), +inf where it misses."""
    X, Y = row[0], row[1]
    e, f, g = row[2], row[3], row[4]
    c_top, ct, kf = row[5], row[6], row[7]
    be, bf, bg, b_top = row[8], row[9], row[10], row[11]
    u = qx - X
    v = qy - Y
    A = e * rx * rx + f * rx * ry + g * ry * ry
    B = 2.0 * e * u * rx + f * (u * ry + v * rx) + 2.0 * g * v * ry
    C = e * u * u + f * u * v + g * v * v
    a_c = -A
    b_c = -B - rz
    c_c = (c_top - h) - C - qz
    a_b = -(be * rx * rx + bf * rx * ry + bg * ry * ry)
    b_b = -(2.0 * be * u * rx + bf * (u * ry + v * rx) + 2.0 * bg * v * ry) - rz
    c_b = (b_top - h) - (be * u * u + bf * u * v + bg * v * v) - qz
    if a_c < 0.0 and not b_c * b_c - 4.0 * a_c * c_c >= 0.0:
        # the ray misses the cliff (no real root: _quadratic's "meets" is false), so it cannot
        # enter cliff ∩ hill: only the beach can be hit, and a miss is +inf whatever its part
        if a_b < 0.0 and not b_b * b_b - 4.0 * a_b * c_b >= 0.0:
            return np.inf, part_beach
        b_in, _, b_meets = _quadratic(a_b, b_b, c_b)
        if b_meets and b_in > 0.0:
            return b_in, part_beach
        return np.inf, part_beach
    c_in, c_out, c_meets = _quadratic(a_c, b_c, c_c)
    h_in, h_out, h_meets = _quadratic(-kf * A, -kf * B - rz, (ct - h) + kf * (c_top - ct - C) - qz)
    # np.maximum / np.minimum propagate NaN
    if c_in != c_in or h_in != h_in:
        up_in = np.nan
    else:
        up_in = max(c_in, h_in)
    if c_out != c_out or h_out != h_out:
        up_out = np.nan
    else:
        up_out = min(c_out, h_out)
    up_meets = c_meets and h_meets and up_in <= up_out
    b_in, b_out, b_meets = _quadratic(a_b, b_b, c_b)
    beach_t = np.inf
    if b_meets and b_in > 0.0 and not (up_meets and up_in < b_in and b_in <= up_out):
        beach_t = b_in
    upper_t = np.inf
    if up_meets and up_in > 0.0 and not (b_meets and b_in < up_in and up_in <= b_out):
        upper_t = up_in
    if upper_t <= beach_t:
        return upper_t, (part_hill if h_in > c_in else part_cliff)
    return beach_t, part_beach


#: Rays per block of the candidate pass: its flags stay in the cache.
_BLOCK = 512


@_jit
def _pierce_all(q, r, table, h, part_beach, part_cliff, part_hill, best, which, part):
    """Every ray against every island in turn: bounding test, quadratics, nearest hit so far.

    The reference's island-by-island passes (candidates, then their
    quadratics) with the loops swapped: each ray keeps the same nearest hit,
    first island among equals. Block by block of rays, the bounding tests of
    every island come first, in a loop without branches (vectorised), then
    each ray's quadratics where its flag is set.
    """
    n = q.shape[0]
    n_isl = table.shape[0]
    flags = np.empty((max(n_isl, 1), _BLOCK), np.bool_)
    # the block's rays component by component (in the cache), for the vectorised bounding tests
    qx, qy, qz = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    rx, ry, rz = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    horiz = np.empty(_BLOCK)
    for a in range(0, n, _BLOCK):
        m = min(n, a + _BLOCK) - a
        for j in range(m):
            qx[j], qy[j], qz[j] = q[a + j, 0], q[a + j, 1], q[a + j, 2]
            rx[j], ry[j], rz[j] = r[a + j, 0], r[a + j, 1], r[a + j, 2]
        for j in range(m):
            horiz[j] = math.sqrt(rx[j] * rx[j] + ry[j] * ry[j])
        for i in range(n_isl):
            X, Y, rho, top_h = table[i, 0], table[i, 1], table[i, 12], table[i, 13]
            for j in range(m):
                flags[i, j] = _is_candidate(qx[j], qy[j], qz[j], rx[j], ry[j], rz[j], horiz[j], X, Y, rho, top_h)
        for j in range(m):
            k = a + j
            for i in range(n_isl):
                if flags[i, j]:
                    t, p = _pierce_one(q[k, 0], q[k, 1], q[k, 2], r[k, 0], r[k, 1], r[k, 2], table[i], h,
                                       part_beach, part_cliff, part_hill)
                    if t < best[k]:
                        best[k] = t
                        which[k] = i + 1
                        part[k] = p


@_jit
def _lowest_upward_origin(q, r):
    z0 = np.inf
    for j in range(q.shape[0]):
        if r[j, 2] >= 0.0 and q[j, 2] < z0:
            z0 = q[j, 2]
    return z0


def pierce_islands(islands, eye_height: float, q, r):
    """:func:`sunset.vector.pierce.pierce_islands` compiled: (t, which, part) for rays (N, 3).

    One compiled pass over the rays (:func:`_pierce_all`): each ray is
    tested against every island's bounding circle in island order and, where
    it may hit, the three quadratics are solved and the nearest hit kept,
    exactly as the reference's island-by-island passes keep it.
    """
    q = np.ascontiguousarray(q, dtype=np.float64)
    r = np.ascontiguousarray(r, dtype=np.float64)
    n = len(q)
    best = np.empty(n)
    which = np.empty(n, np.int8)
    part = np.empty(n, np.int8)
    z0 = _lowest_upward_origin(q, r)
    table = island_table(islands, eye_height, z0 if z0 < np.inf else 0.0)
    best.fill(np.inf)
    which.fill(-1)
    part.fill(0)
    _pierce_all(q, r, table, float(eye_height), PART_BEACH, PART_CLIFF, PART_HILL, best, which, part)
    return best, which, part



#: Columns of :func:`normal_table`.
_NORMAL_COLUMNS = ("x", "y", "ce", "cf", "cg", "be", "bf", "bg", "k", "first", "stop")


def normal_table(islands):
    """The islands' normal parameters as float64 tables for :func:`_island_normal`.

    One row per island (apex, cliff and beach forms, hill factor and the
    range of its cosine terms in the second table), and one row
    (ℓ, m, φ, amplitude) per cosine term, island by island.
    """
    rows, terms = [], []
    for isl in islands:
        first = len(terms)
        terms += [[c.l, c.m, c.phase, c.amplitude] for c in isl.cosines]
        cl, bc = isl.cliff, isl.beach
        rows.append([isl.x, isl.y, cl.e, cl.f, cl.g, bc.e, bc.f, bc.g, isl.hill_factor, first, len(terms)])
    return (np.array(rows, dtype=np.float64).reshape(len(rows), len(_NORMAL_COLUMNS)),
            np.array(terms, dtype=np.float64).reshape(len(terms), 4))


@_jit
def _island_normal(x, y, part, row, terms, part_beach, part_hill):
    """:func:`sunset.vector.pierce.island_normal` at one point (float64): (n_x, n_y, n_z).

    The same operations in the same order: the cliff's gradient with each
    cosine term's sine (the C library's, as NumPy's float64 ``np.sin``), or
    the beach's; the hill factor on the hill; then
    :func:`sunset.model.waves.unit_normal`.
    """
    dx = x - row[0]
    dy = y - row[1]
    if part == part_beach:
        gx = -(2.0 * row[5] * dx + row[6] * dy)
        gy = -(row[6] * dx + 2.0 * row[7] * dy)
    else:
        gx = -(2.0 * row[2] * dx + row[3] * dy)
        gy = -(row[3] * dx + 2.0 * row[4] * dy)
        for c in range(int(row[9]), int(row[10])):
            ph = terms[c, 0] * x + terms[c, 1] * y
            if terms[c, 2] != 0.0:
                ph = ph + terms[c, 2]
            sn = terms[c, 3] * math.sin(ph)
            gx = gx - terms[c, 0] * sn
            gy = gy - terms[c, 1] * sn
        if part == part_hill:
            gx = row[8] * gx
            gy = row[8] * gy
    zb = 1.0 / math.sqrt(gx * gx + gy * gy + 1.0)
    return -zb * gx, -zb * gy, zb


@_jit
def _normals_all(x, y, part, which, table, terms, part_beach, part_hill, out):
    for j in range(x.shape[0]):
        out[j, 0], out[j, 1], out[j, 2] = _island_normal(x[j], y[j], part[j], table[which[j] - 1], terms,
                                                         part_beach, part_hill)


def island_normals(islands, x, y, part, which) -> np.ndarray:
    """:func:`sunset.vector.pierce.island_normal` compiled, for points on several islands: (N, 3) float64.

    ``which`` (1, 2, …) names each point's island in ``islands``; ``part``
    the part its ray entered.
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    y = np.ascontiguousarray(y, dtype=np.float64)
    part = np.ascontiguousarray(part, dtype=np.int8)
    which = np.ascontiguousarray(which, dtype=np.int64)
    out = np.empty((len(x), 3))
    table, terms = normal_table(islands)
    _normals_all(x, y, part, which, table, terms, PART_BEACH, PART_HILL, out)
    return out


@_jit
def pierce_write(flat, q, r, bounces, table, normals, terms, h, part_beach, part_cliff, part_hill, sky_code,
                 f_bounces, f_ray, f_surface, f_part, f_normal):
    """Pierce the islands (:func:`_pierce_all`) and write each ray's final fields into the frame's pixels.

    ``flat`` are row-major pixel indices of the (H, W) frame fields (ascending); the
    final normal is the island's (:func:`_island_normal` at the hit, the
    point Q + tR), NaN where the ray ends in the sky. Returns the number of
    rays that hit an island.
    """
    n = q.shape[0]
    best = np.full(n, np.inf)
    which = np.full(n, sky_code, np.int8)
    part = np.zeros(n, np.int8)
    _pierce_all(q, r, table, h, part_beach, part_cliff, part_hill, best, which, part)
    W = f_surface.shape[1]
    n_hit = 0
    yy = 0
    row_start = 0       # flat is ascending: the row is found by stepping, not by a division
    for j in range(n):
        while flat[j] - row_start >= W:
            row_start += W
            yy += 1
        xx = flat[j] - row_start
        f_bounces[yy, xx] = bounces[j]
        f_ray[yy, xx, 0] = r[j, 0]
        f_ray[yy, xx, 1] = r[j, 1]
        f_ray[yy, xx, 2] = r[j, 2]
        f_surface[yy, xx] = which[j]
        f_part[yy, xx] = part[j]
        if which[j] > 0:
            t = best[j]
            nx, ny, nz = _island_normal(q[j, 0] + t * r[j, 0], q[j, 1] + t * r[j, 1], part[j],
                                        normals[which[j] - 1], terms, part_beach, part_hill)
            f_normal[yy, xx, 0] = nx
            f_normal[yy, xx, 1] = ny
            f_normal[yy, xx, 2] = nz
            n_hit += 1
        else:
            f_normal[yy, xx, 0] = np.nan
            f_normal[yy, xx, 1] = np.nan
            f_normal[yy, xx, 2] = np.nan
    return n_hit


_NO_RECORD = (np.zeros((1, 1, 2), np.float32), np.zeros((1, 1, 2, 3), np.float32))


def trace_sea_rays(scene, frame: Frame, reflections: int) -> Frame:
    """:func:`sunset.vector.reflect.trace_sea_rays` compiled: the same frame, in two passes over the strip.

    :func:`sunset.vector.crests_numba.sea_rays` (reflect, pierce the crest,
    reflect again, record, |R_z|), then :func:`pierce_write` (the islands, their
    normals at the hits and the frame's final fields).
    """
    h = float(scene.camera.eye_height)
    n = int(np.count_nonzero(frame.surface == SEA))
    flat = np.empty(n, np.intp)
    q = np.empty((n, 3))
    r = np.empty((n, 3))
    bounces = np.empty(n, np.uint8)
    second = second_bounce_constants(scene.sea, frame.t) if reflections == 2 else None
    if second is None:
        second = (crest_constants_dummy(), np.zeros(1), np.zeros((0, 4)), np.zeros((0, 1)), np.zeros(0, np.int64))
        do_second = False
    else:
        do_second = True
    record = frame.incidence is not None
    inc, rays = (frame.incidence, frame.sea_rays) if record else _NO_RECORD
    z0 = sea_rays(frame.surface, frame.point, frame.direction, frame.normal, SEA, do_second, *second, record, inc,
                  rays, flat, q, r, bounces)
    islands = scene.islands if reflections >= 1 else ()
    table = island_table(islands, h, z0 if z0 < np.inf else 0.0)
    normals, terms = normal_table(islands)
    pierce_write(flat, q, r, bounces, table, normals, terms, h, PART_BEACH, PART_CLIFF, PART_HILL, SKY,
                 frame.bounces, frame.ray, frame.final_surface, frame.final_part, frame.final_normal)
    return frame


def crest_constants_dummy():
    """Crest constants for a pass with one reflection (never read)."""
    return (0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0)
