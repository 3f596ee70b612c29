"""Numba twin of :func:`sunset.vector.reflect.trace_sea_rays`: the reflected rays' per-ray loops compiled.

* :func:`reflect_sea` gathers the sea pixels of a frame and reflects their
  rays (R = D − 2(D·N)N, :func:`sunset.vector.pierce.reflect`).
* :func:`crest_hits` pierces each ray's crest cylinder
  (:func:`sunset.vector.crests.crest_candidates`, :func:`sunset.vector.crests.crest_cylinder`,
  :func:`sunset.vector.crests.cylinder_coefficients`, :func:`sunset.vector.pierce.quadratic_interval`).
* :func:`pierce_islands` is :func:`sunset.vector.pierce.pierce_islands`: the
  bounding test compresses each island's candidates, then its three
  quadratics and the nearest-hit selection, in two compiled passes.
* :func:`write_back` scatters the traced rays into the frame.

The same operations in the same order as the NumPy reference: the frames are
identical (tests). Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from ..kernels import jit as _jit
from .crests import crest_curvature, crest_lift, largest_train
from .frame import Frame
from .pierce import gather, island_normal, reflect, scatter
from .reflect import record_bounces


@_jit
def _reflect_sea(surface, point, direction, normal, sea_code, idx, q, r):
    H, W = surface.shape
    j = 0
    for y in range(H):
        for x in range(W):
            if surface[y, x] != sea_code:
                continue
            idx[j] = y * W + x
            dx = np.float64(direction[y, x, 0])
            dy = np.float64(direction[y, x, 1])
            dz = np.float64(direction[y, x, 2])
            nx = np.float64(normal[y, x, 0])
            ny = np.float64(normal[y, x, 1])
            nz = np.float64(normal[y, x, 2])
            dot = dx * nx + dy * ny + dz * nz
            two = 2.0 * dot
            q[j, 0] = np.float64(point[y, x, 0])
            q[j, 1] = np.float64(point[y, x, 1])
            q[j, 2] = np.float64(point[y, x, 2])
            r[j, 0] = dx - two * nx
            r[j, 1] = dy - two * ny
            r[j, 2] = dz - two * nz
            j += 1
    return j


def reflect_sea(frame, sea_code: int):
    """Gather the pixels whose direct ray met the sea and reflect their rays.

    Returns ``(idx, q, r)``: flat pixel indices (row-major, the order of a
    boolean mask), hit points and reflected directions, float64; as
    ``frame.point[mask]`` and :func:`sunset.vector.pierce.reflect` of the direction
    and normal there.
    """
    n = int(np.count_nonzero(frame.surface == sea_code))
    idx = np.empty(n, np.intp)
    q = np.empty((n, 3))
    r = np.empty((n, 3))
    _reflect_sea(np.ascontiguousarray(frame.surface), np.ascontiguousarray(frame.point),
                 np.ascontiguousarray(frame.direction), np.ascontiguousarray(frame.normal), sea_code, idx, q, r)
    return idx, q, r


@_jit
def _quadratic(a, b, c):
    """(t_in, t_out, meets) as sunset.vector.pierce.quadratic_interval, for one ray."""
    d = b * b - 4.0 * a * c
    root = math.sqrt(abs(d))
    qq = -0.5 * (b + math.copysign(root, b))
    if a < 0.0:
        r1 = qq / a
        r2 = c / qq
        # np.fmin / np.fmax: a NaN gives way to the other value
        if r1 != r1:
            t_in = r2
            t_out = r2
        elif r2 != r2:
            t_in = r1
            t_out = r1
        else:
            t_in = min(r1, r2)
            t_out = max(r1, r2)
        return t_in, t_out, d >= 0.0
    lin = -c / b
    t_in = lin if b > 0.0 else -np.inf
    t_out = lin if b < 0.0 else np.inf
    return t_in, t_out, (b != 0.0) or (c >= 0.0)


@_jit
def _phase_ahead(rate, ps):
    """Phase from a ray's start to the next crest ahead of it (as sunset.vector.pierce.crest_phase), radians."""
    two_pi = 2.0 * math.pi
    if rate >= 0.0:
        return two_pi - ps
    if ps > 0.0:
        return -ps
    return -two_pi


@_jit
def _crest_phase(q, r, l, m, omega_t, phase, k, lift, half, psi, cand):
    two_pi = 2.0 * math.pi
    n = 0
    for j in range(q.shape[0]):
        theta = l * q[j, 0] + m * q[j, 1] - omega_t + phase
        ps = theta % two_pi
        psi[j] = ps
        rate = l * r[j, 0] + m * r[j, 1]
        rz = r[j, 2]
        keep = True
        if rz > 0.0:
            # the bounding test of sunset.vector.crests.crest_candidates
            ahead = _phase_ahead(rate, ps)
            u0 = -ahead / k
            w = rate / k
            u_end = u0 + w * (lift / rz)
            if (u0 > half and u_end > half) or (u0 < -half and u_end < -half):
                keep = False
        if keep:
            cand[n] = j
            n += 1
    return n


@_jit
def _crest_hits(q, r, cand, psi, cos_psi, l, m, k, amps, amp_sum, kappa, out):
    for j in range(cand.shape[0]):
        i = cand[j]
        qz = q[i, 2]
        rx, ry, rz = r[i, 0], r[i, 1], r[i, 2]
        rate = l * rx + m * ry
        ps = psi[j]
        ahead = _phase_ahead(rate, ps)
        u0 = -ahead / k
        # Σ a_n cos nθ by the Chebyshev recurrence (sunset.vector.pierce.harmonic_sum)
        c1 = cos_psi[j]
        elev = amps[0] * c1
        t_prev = 1.0
        t_cur = c1
        for n in range(1, amps.shape[0]):
            t_next = 2.0 * c1 * t_cur - t_prev
            t_prev = t_cur
            t_cur = t_next
            elev = elev + amps[n] * t_cur
        top = qz + amp_sum - elev
        w = rate / k
        a = -0.5 * kappa * w * w
        b = -kappa * u0 * w - rz
        c = top - 0.5 * kappa * u0 * u0 - qz
        t_in, _, meets = _quadratic(a, b, c)
        out[i] = t_in if (meets and t_in > 0.0) else np.inf


def crest_hits(train, t: float, q, r) -> np.ndarray:
    """Distance along each ray to its crest cylinder, +inf where it clears the crest.

    :func:`sunset.vector.pierce.first_entry` of the cylinder of
    :func:`sunset.vector.crests.crest_cylinder`, for rays (N, 3), after the bounding
    test of :func:`sunset.vector.crests.crest_candidates`. A first pass reduces the
    phase to ψ = θ mod 2π and compresses the candidates; NumPy takes cos ψ on
    them (the reference's cosine); a second pass does the rest.
    """
    l, m = train.wave_vector
    amps = np.ascontiguousarray(train.harmonic_amplitudes(), dtype=np.float64)
    q = np.ascontiguousarray(q, dtype=np.float64)
    r = np.ascontiguousarray(r, dtype=np.float64)
    kappa = float(crest_curvature(train))
    lift = crest_lift(train)
    psi = np.empty(len(q))
    cand = np.empty(len(q), np.intp)
    n = _crest_phase(q, r, float(l), float(m), float(train.omega * t), float(train.phase), float(train.k), lift,
                     math.sqrt(2.0 * lift / kappa), psi, cand)
    cand = cand[:n]
    psi = np.take(psi, cand)
    out = np.full(len(q), np.inf)
    _crest_hits(q, r, cand, psi, np.cos(psi), float(l), float(m), float(train.k), amps, float(np.sum(amps)), kappa,
                out)
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
def _is_candidate(qx, qy, qz, rx, ry, rz, X, Y, rho, top_h):
    """The bounding test of sunset.vector.pierce.island_candidates for one ray and one island."""
    cx = X - qx
    cy = Y - qy
    horiz = math.sqrt(rx * rx + ry * ry)
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
    c_in, c_out, c_meets = _quadratic(-A, -B - rz, (c_top - h) - C - qz)
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
    a_b = -(be * rx * rx + bf * rx * ry + bg * ry * ry)
    b_b = -(2.0 * be * u * rx + bf * (u * ry + v * rx) + 2.0 * bg * v * ry) - rz
    c_b = (b_top - h) - (be * u * u + bf * u * v + bg * v * v) - qz
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


@_jit
def _pierce_all(q, r, table, h, part_beach, part_cliff, part_hill, best, which, part):
    """Every ray against every island in turn, in one pass: bounding test, quadratics, nearest hit so far.

    The reference's island-by-island passes (candidates, then their
    quadratics) with the loops swapped: each ray keeps the same nearest hit,
    first island among equals, with everything in registers.
    """
    for j in range(q.shape[0]):
        qx, qy, qz = q[j, 0], q[j, 1], q[j, 2]
        rx, ry, rz = r[j, 0], r[j, 1], r[j, 2]
        for i in range(table.shape[0]):
            row = table[i]
            if _is_candidate(qx, qy, qz, rx, ry, rz, row[0], row[1], row[12], row[13]):
                t, p = _pierce_one(qx, qy, qz, rx, ry, rz, row, h, part_beach, part_cliff, part_hill)
                if t < best[j]:
                    best[j] = t
                    which[j] = i + 1
                    part[j] = p


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


@_jit
def _write_back(flat, bounces, r, final, part, normal, f_bounces, f_ray, f_surface, f_part, f_normal):
    for j in range(flat.shape[0]):
        i = flat[j]
        f_bounces[i] = bounces[j]
        f_surface[i] = final[j]
        f_part[i] = part[j]
        for a in range(3):
            f_ray[i, a] = r[j, a]
            f_normal[i, a] = normal[j, a]


def write_back(frame, flat, bounces, r, final, part, normal) -> None:
    """Scatter the traced sea pixels' final fields into the frame (rows ``flat`` of the flattened fields)."""
    fields = (frame.bounces, frame.ray, frame.final_surface, frame.final_part, frame.final_normal)
    if not all(f.flags.c_contiguous for f in fields):  # reshape would copy: index by (row, column) instead
        at = np.unravel_index(flat, frame.surface.shape)
        frame.bounces[at] = bounces
        frame.ray[at] = r
        frame.final_surface[at] = final
        frame.final_part[at] = part
        frame.final_normal[at] = normal
        return
    _write_back(np.ascontiguousarray(flat, np.intp), bounces, np.ascontiguousarray(r), final, part,
                np.ascontiguousarray(normal), frame.bounces.reshape(-1), frame.ray.reshape(-1, 3),
                frame.final_surface.reshape(-1), frame.final_part.reshape(-1), frame.final_normal.reshape(-1, 3))


def trace_sea_rays(scene, frame: Frame, reflections: int) -> Frame:
    """:func:`sunset.vector.reflect.trace_sea_rays` with the per-ray loops compiled.

    The same steps in the same arithmetic: gather and reflect the sea pixels,
    pierce the crest cylinders, reflect the hits again off the true wave
    normal (NumPy, on the compressed subset), |R_z|, pierce the islands, and
    shade the island hits (NumPy, compressed). Gives the frame the NumPy path gives.
    """
    h = scene.camera.eye_height
    flat, q, r = reflect_sea(frame, SEA)
    r1 = r.copy() if frame.incidence is not None else None
    bounces = np.ones(len(q), np.uint8)
    idx = ray2 = None
    if reflections == 2:
        train = largest_train(scene.sea)
        if train is not None:
            hit = crest_hits(train, frame.t, q, r)
            idx, (q2, r2, t2) = gather(np.isfinite(hit), q, r, hit)
            point = q2 + t2[:, None] * r2
            normal = scene.sea.normal(point[:, 0], point[:, 1], frame.t)
            ray2 = reflect(r2, normal)
            scatter(idx, point, q)
            scatter(idx, ray2, r)
            scatter(idx, 2, bounces)
    if frame.incidence is not None:           # the RGB back end's record; the 8-bit tape needs none
        d = frame.direction.reshape(-1, 3)[flat].astype(np.float64)
        n = frame.normal.reshape(-1, 3)[flat].astype(np.float64)
        record_bounces(frame, flat, -np.sum(d * n, axis=-1), r1, idx, ray2)
    np.abs(r[:, 2], out=r[:, 2])
    final = np.full(len(q), SKY, np.int8)
    part = np.zeros(len(q), np.int8)
    normal = None
    if reflections >= 1 and scene.islands:
        dist, final, part = pierce_islands(scene.islands, h, q, r)
        normal = np.full((len(q), 3), np.nan)
        # compress once to the rays that hit an island, then split by island
        any_idx, (qa, ra, ta, pa, fa) = gather(final > 0, q, r, dist, part, final)
        for k, island in enumerate(scene.islands, start=1):
            sel, (qk, rk, tk, pk) = gather(fa == k, qa, ra, ta, pa)
            if len(sel):
                hit = qk + tk[:, None] * rk
                scatter(any_idx[sel], island_normal(island, hit[:, 0], hit[:, 1], pk), normal)
    if normal is None:
        normal = np.full((len(q), 3), np.nan)
    write_back(frame, flat, bounces, r, final, part, normal)
    return frame
