"""Numba twin of :func:`sunset.vector.reflect.trace_sea_rays`: the reflected rays of a strip in one compiled pass.

:func:`trace_strip` walks the strip's pixels and gathers the sea pixels' rays,
reflected (R = D − 2(D·N)N, :func:`sunset.vector.pierce.reflect`), into
blocks of :data:`_BLOCK` rays that stay in the cache; :func:`_finish_block`
then does, block by block:

* with two reflections, the crests' bounding test for the whole block in
  loops the compiler vectorises (:func:`sunset.vector.crests_numba.crest_block`),
  then each candidate's crest cylinder and, where it is hit, the second
  reflection off the true wave normal (float64 sines and cosines, the C
  library's); the bounces recorded for the RGB back end; R_z folded up;
* :func:`_pierce_block`: :func:`sunset.vector.pierce.pierce_islands`, the
  bounding paraboloids of every island for the whole block (vectorised),
  then the three quadratics where a ray may hit, the nearest hit kept;
* the frame's final fields written at each ray's pixel, with the island's
  normal at the hit (:func:`_island_normal`, :func:`sunset.vector.pierce.island_normal`'s operations).

No ray is written to memory outside its block. :func:`pierce_islands` and
:func:`crest_hits` are the compiled island and crest piercing on their own
(the tests hold them against the reference's). The bounding tests only skip
rays that miss; the frames agree with the NumPy reference's within the
tolerances of chapter 10 (tests). Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from ..errors import SunsetError
from ..kernels import jit as _jit
from .crests_numba import (_quadratic, crest_block, crest_constants, crest_distance, crest_entry,
                           sea_normals_into, second_bounce_constants)
from .frame import Frame
from .heightfield import WIND_REFUSED
from .pierce import island_bounds


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


#: Columns of :func:`island_table`: the apex, the three quadratics' constants, then (λ, lo, hi, grace) of the
#: beach's and the upper part's bounding paraboloids (:func:`sunset.vector.pierce.island_bounds`).
_ISLAND_COLUMNS = ("x", "y", "ce", "cf", "cg", "c_top", "ct", "k", "be", "bf", "bg", "b_top",
                   "b_lam", "b_lo", "b_hi", "b_grace", "u_lam", "u_lo", "u_hi", "u_grace")


def island_table(islands, eye_height: float) -> np.ndarray:
    """The islands' parameters as rows of a float64 table for :func:`pierce_islands` and :func:`trace_strip`.

    The bounding paraboloids are :func:`sunset.vector.pierce.island_bounds`' (the same numbers).
    """
    rows = []
    for isl in islands:
        cl, bc = isl.cliff, isl.beach
        bounds = [v for part in island_bounds(isl, eye_height) for v in part]
        rows.append([isl.x, isl.y, cl.e, cl.f, cl.g, cl.height, isl.cliff_top, isl.hill_factor,
                     bc.e, bc.f, bc.g, bc.height] + bounds)
    return np.array(rows, dtype=np.float64).reshape(len(rows), len(_ISLAND_COLUMNS))


@_jit
def _under(c2, along, h2, qz, rz, lam, lo, hi, grace):
    """May the ray reach a point under a bounding paraboloid (sunset.vector.pierce.island_candidates)."""
    slack = lo * c2 + (qz - grace * abs(qz)) - hi
    k = 2.0 * lam * along - rz
    return (slack <= 0.0) | ((k > 0.0) & (k * k >= 4.0 * lam * h2 * slack))


@_jit
def _is_candidate(qx, qy, qz, rx, ry, rz, h2, row):
    """The bounding test of sunset.vector.pierce.island_candidates for one ray and one island (a table row).

    ``h2`` = R_x² + R_y², the same for every island (taken once per ray).
    """
    cx = row[0] - qx
    cy = row[1] - qy
    c2 = cx * cx + cy * cy
    along = rx * cx + ry * cy
    return (_under(c2, along, h2, qz, rz, row[12], row[13], row[14], row[15])
            | _under(c2, along, h2, qz, rz, row[16], row[17], row[18], row[19]))


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


#: Rays per block: a block's rays, flags and hits stay in the cache.
_BLOCK = 512


@_jit
def _pierce_block(m, qx, qy, qz, rx, ry, rz, h2, flags, table, h, part_beach, part_cliff, part_hill,
                  best, which, part):
    """The first ``m`` rays of a block against every island: bounding tests, quadratics, nearest hit.

    The reference's island-by-island passes (candidates, then their
    quadratics) with the loops swapped: each ray keeps the same nearest hit,
    first island among equals. The bounding tests of every island come
    first, in a loop without branches (vectorised), then each ray's
    quadratics where its flag is set. ``best``, ``which`` and ``part`` are
    written for the ``m`` rays (+inf, ``which``'s value as given, 0 where none is hit).
    """
    n_isl = table.shape[0]
    for j in range(m):
        h2[j] = rx[j] * rx[j] + ry[j] * ry[j]
    for i in range(n_isl):
        row = table[i]
        for j in range(m):
            flags[i, j] = _is_candidate(qx[j], qy[j], qz[j], rx[j], ry[j], rz[j], h2[j], row)
    for j in range(m):
        for i in range(n_isl):
            if flags[i, j]:
                t, p = _pierce_one(qx[j], qy[j], qz[j], rx[j], ry[j], rz[j], table[i], h,
                                   part_beach, part_cliff, part_hill)
                if t < best[j]:
                    best[j] = t
                    which[j] = i + 1
                    part[j] = p


@_jit
def _pierce_all(q, r, table, h, part_beach, part_cliff, part_hill, best, which, part):
    """Every ray (N, 3) against every island, block by block (:func:`_pierce_block`)."""
    n = q.shape[0]
    flags = np.empty((max(table.shape[0], 1), _BLOCK), np.bool_)
    qx, qy, qz = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    rx, ry, rz = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    h2 = np.empty(_BLOCK)
    for a in range(0, n, _BLOCK):
        m = min(n, a + _BLOCK) - a
        for j in range(m):
            qx[j], qy[j], qz[j] = q[a + j, 0], q[a + j, 1], q[a + j, 2]
            rx[j], ry[j], rz[j] = r[a + j, 0], r[a + j, 1], r[a + j, 2]
        _pierce_block(m, qx, qy, qz, rx, ry, rz, h2, flags, table, h, part_beach, part_cliff, part_hill,
                      best[a:a + m], which[a:a + m], part[a:a + m])


def pierce_islands(islands, eye_height: float, q, r):
    """:func:`sunset.vector.pierce.pierce_islands` compiled: (t, which, part) for rays (N, 3).

    One compiled pass over the rays (:func:`_pierce_all`): each ray is
    tested against every island's bounding paraboloids in island order and, where
    it may hit, the three quadratics are solved and the nearest hit kept,
    exactly as the reference's island-by-island passes keep it.
    """
    q = np.ascontiguousarray(q, dtype=np.float64)
    r = np.ascontiguousarray(r, dtype=np.float64)
    n = len(q)
    best = np.full(n, np.inf)
    which = np.full(n, -1, np.int8)
    part = np.zeros(n, np.int8)
    table = island_table(islands, eye_height)
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

    The cliff's gradient with each cosine term's sine (the C library's), or
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
            ph = terms[c, 0] * x + terms[c, 1] * y + terms[c, 2]
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
def bounce_block(m, ys, xs, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps, waves, coef,
                 count, record, incidence, sea_rays_out, h2, flags, table, h, part_beach, part_cliff, part_hill,
                 sky_code, best, which, part):
    """A block of sea rays, reflected once, to the end of their path: the crests, |R_z|, the islands.

    With ``second``, the crests' bounding tests (:func:`sunset.vector.crests_numba.crest_block`),
    then the candidates' cylinders are pierced and the hits reflected again
    off the true wave normal (recorded with ``record``); every ray's R_z is
    folded up; :func:`_pierce_block` finds the islands. Leaves each ray's
    last point and direction in (q, r), its bounces, and its nearest island
    hit in ``best``, ``which`` (``sky_code`` where none) and ``part``.
    """
    if second:
        crest_block(m, qx, qy, qz, rx, ry, rz, crest, amps, psi, keep, scratch)
        # the candidates' crest hits, gathered; the sea's normals there in loops over the hits
        hit = np.empty(m, np.int64)
        work = np.empty((12, m))
        px, py, pz, mx, my, mz = work[0], work[1], work[2], work[3], work[4], work[5]
        nh = 0
        for j in range(m):
            if keep[j]:
                t = crest_entry(qx[j], qy[j], qz[j], rx[j], ry[j], rz[j], psi[j], crest, amps)
                if t < np.inf:
                    hit[nh] = j
                    px[nh] = qx[j] + t * rx[j]
                    py[nh] = qy[j] + t * ry[j]
                    pz[nh] = qz[j] + t * rz[j]
                    nh += 1
        sea_normals_into(nh, px, py, waves, coef, count, work[6:], mx, my, mz)
        for k in range(nh):
            j = hit[k]
            two = 2.0 * (rx[j] * mx[k] + ry[j] * my[k] + rz[j] * mz[k])
            sx = rx[j] - two * mx[k]
            sy = ry[j] - two * my[k]
            sz = rz[j] - two * mz[k]
            if record:
                ex = sx - rx[j]
                ey = sy - ry[j]
                ez = sz - rz[j]
                incidence[ys[j], xs[j], 1] = 0.5 * math.sqrt(ex * ex + ey * ey + ez * ez)
                sea_rays_out[ys[j], xs[j], 1, 0] = sx
                sea_rays_out[ys[j], xs[j], 1, 1] = sy
                sea_rays_out[ys[j], xs[j], 1, 2] = sz
            qx[j], qy[j], qz[j] = px[k], py[k], pz[k]
            rx[j], ry[j], rz[j] = sx, sy, sz
            bounces[j] = 2
    for j in range(m):
        rz[j] = abs(rz[j])
        best[j] = np.inf
        which[j] = sky_code
        part[j] = 0
    _pierce_block(m, qx, qy, qz, rx, ry, rz, h2, flags, table, h, part_beach, part_cliff, part_hill,
                  best, which, part)


@_jit
def _finish_block(m, ys, xs, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps, waves, coef,
                  count, record, incidence, sea_rays_out, h2, flags, table, normals, terms, h, part_beach, part_cliff,
                  part_hill, sky_code, best, which, part, f_bounces, f_ray, f_surface, f_part, f_normal):
    """The rest of a block of sea rays (:func:`bounce_block`), then the frame's final fields.

    The final fields are written at each ray's pixel, with the island's normal at the hit
    (:func:`_island_normal` at Q + tR), NaN where the ray ends in the sky.
    """
    bounce_block(m, ys, xs, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps, waves, coef,
                 count, record, incidence, sea_rays_out, h2, flags, table, h, part_beach, part_cliff, part_hill,
                 sky_code, best, which, part)
    for j in range(m):
        yy, xx = ys[j], xs[j]
        f_bounces[yy, xx] = bounces[j]
        f_ray[yy, xx, 0] = rx[j]
        f_ray[yy, xx, 1] = ry[j]
        f_ray[yy, xx, 2] = rz[j]
        f_surface[yy, xx] = which[j]
        f_part[yy, xx] = part[j]
        if which[j] > 0:
            t = best[j]
            nx, ny, nz = _island_normal(qx[j] + t * rx[j], qy[j] + t * ry[j], part[j],
                                        normals[which[j] - 1], terms, part_beach, part_hill)
            f_normal[yy, xx, 0] = nx
            f_normal[yy, xx, 1] = ny
            f_normal[yy, xx, 2] = nz
        else:
            f_normal[yy, xx, 0] = np.nan
            f_normal[yy, xx, 1] = np.nan
            f_normal[yy, xx, 2] = np.nan


@_jit
def trace_strip(surface, point, direction, normal, sea_code, second, crest, amps, waves, coef, count,
                record, incidence, sea_rays_out, table, normals, terms, h, part_beach, part_cliff, part_hill,
                sky_code, f_bounces, f_ray, f_surface, f_part, f_normal):
    """Every sea pixel's ray of a strip, in one pass over its pixels, block by block of rays.

    Each sea pixel's ray is reflected (R = D − 2(D·N)N, float64 from the
    float32 fields), recorded with ``record`` and, with ``second``, given
    when :data:`_BLOCK` rays are gathered, :func:`_finish_block` does the
    rest and writes the frame's final fields. No ray is written to memory
    outside its block.
    """
    H, W = surface.shape
    ys = np.empty(_BLOCK, np.int64)
    xs = np.empty(_BLOCK, np.int64)
    qx, qy, qz = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    rx, ry, rz = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    h2, best, psi = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    bounces = np.empty(_BLOCK, np.uint8)
    which = np.empty(_BLOCK, np.int8)
    part = np.empty(_BLOCK, np.int8)
    keep = np.empty(_BLOCK, np.bool_)
    scratch = np.empty((5, _BLOCK))
    flags = np.empty((max(table.shape[0], 1), _BLOCK), np.bool_)
    m = 0
    for yy in range(H):
        for xx in range(W):
            if surface[yy, xx] != sea_code:
                continue
            dx = np.float64(direction[yy, xx, 0])
            dy = np.float64(direction[yy, xx, 1])
            dz = np.float64(direction[yy, xx, 2])
            nx = np.float64(normal[yy, xx, 0])
            ny = np.float64(normal[yy, xx, 1])
            nz = np.float64(normal[yy, xx, 2])
            dot = dx * nx + dy * ny + dz * nz
            two = 2.0 * dot
            ys[m] = yy
            xs[m] = xx
            qx[m] = np.float64(point[yy, xx, 0])
            qy[m] = np.float64(point[yy, xx, 1])
            qz[m] = np.float64(point[yy, xx, 2])
            rx[m] = dx - two * nx
            ry[m] = dy - two * ny
            rz[m] = dz - two * nz
            bounces[m] = 1
            if record:
                incidence[yy, xx, 0] = -dot
                sea_rays_out[yy, xx, 0, 0] = rx[m]
                sea_rays_out[yy, xx, 0, 1] = ry[m]
                sea_rays_out[yy, xx, 0, 2] = rz[m]
            m += 1
            if m == _BLOCK:
                _finish_block(m, ys, xs, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps,
                              waves, coef, count, record, incidence, sea_rays_out, h2, flags, table, normals, terms, h,
                              part_beach, part_cliff, part_hill, sky_code, best, which, part,
                              f_bounces, f_ray, f_surface, f_part, f_normal)
                m = 0
    if m:
        _finish_block(m, ys, xs, qx, qy, qz, rx, ry, rz, bounces, second, keep, psi, scratch, crest, amps, waves,
                      coef, count, record, incidence, sea_rays_out, h2, flags, table, normals, terms, h,
                      part_beach, part_cliff, part_hill, sky_code, best, which, part,
                      f_bounces, f_ray, f_surface, f_part, f_normal)


_NO_RECORD = (np.zeros((1, 1, 2), np.float32), np.zeros((1, 1, 2, 3), np.float32))


def reflect_constants(scene, t: float, reflections: int) -> tuple:
    """What :func:`trace_strip` and :func:`bounce_block` need of the scene at ``t``: (second reflections?, their
    constants, the islands' table, their normals' tables, the eye height)."""
    h = float(scene.camera.eye_height)
    second = second_bounce_constants(scene.sea, t) if reflections == 2 else None
    if second is None:
        second = (crest_constants_dummy(), np.zeros(1), np.zeros((0, 4)), np.zeros((0, 1)), np.zeros(0, np.int64))
        do_second = False
    else:
        do_second = True
    islands = scene.islands if reflections >= 1 else ()
    table = island_table(islands, h)
    normals, terms = normal_table(islands)
    return do_second, second, table, normals, terms, h


def trace_sea_rays(scene, frame: Frame, reflections: int) -> Frame:
    """:func:`sunset.vector.reflect.trace_sea_rays` compiled, in one pass over the strip.

    :func:`trace_strip`: reflect, pierce the crest, reflect again, record,
    |R_z|, the islands, their normals at the hits and the frame's final
    fields, block by block of rays. A sea of trains only: a wind sea is refused
    (:data:`~sunset.vector.heightfield.WIND_REFUSED`), as by the reference.
    """
    if scene.sea.wind is not None:
        raise SunsetError(WIND_REFUSED)
    return strip_pass(scene, frame, reflections)


def strip_pass(scene, frame: Frame, reflections: int) -> Frame:
    """:func:`trace_strip` over the strip: the second reflections off the trains' crest (``reflections`` = 2), or
    none, when nothing of the sea is read but the frame's normals (also a wind sea's one bounce)."""
    do_second, second, table, normals, terms, h = reflect_constants(scene, frame.t, reflections)
    record = frame.incidence is not None
    inc, rays = (frame.incidence, frame.sea_rays) if record else _NO_RECORD
    trace_strip(frame.surface, frame.point, frame.direction, frame.normal, SEA, do_second, *second, record, inc,
                rays, table, normals, terms, h, PART_BEACH, PART_CLIFF, PART_HILL, SKY,
                frame.bounces, frame.ray, frame.final_surface, frame.final_part, frame.final_normal)
    return frame


def crest_constants_dummy():
    """Crest constants for a pass with one reflection (never read)."""
    return (0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0)
