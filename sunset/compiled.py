"""Compiled kernels (Numba) for the renderer's hot loops, and the switch that selects them.

The NumPy vector kernels in :mod:`sunset.heightfield` and :mod:`sunset.pierce`
are the reference: they are what the book shows, written as whole-array
operations in the manner of the Cray's vector loops. On a scalar CPU with a
few cores, though, a vector loop that makes one pass over memory per
arithmetic operation spends most of its time moving temporaries. The kernels
here do the same arithmetic, operation for operation and in the same order,
one element at a time with everything in registers:

* :func:`scan_columns` is the paper's scan-line loop
  (:func:`sunset.heightfield.scan_line_reference`) with the arithmetic of the
  vectorized :func:`sunset.heightfield.scan_convert` (same pixel units in the
  profile's precision, same interpolation), over many scan lines of ragged
  length; :func:`scan_merge` adds the sea's far tail and the per-scan-line
  depth buffer of :func:`sunset.heightfield.trace_direct`.
* :func:`expand_intervals` cuts an island's probe intervals into its samples.
* :func:`assemble` and :func:`put_unit_normals` build the direct frame's
  geometry in one pass, with the compressed lists of sea and island pixels.
* :func:`reflect_sea` gathers the sea pixels of a frame and reflects their
  rays (R = D − 2(D·N)N, :func:`sunset.pierce.reflect`).
* :func:`crest_hits` pierces each ray's crest cylinder
  (:func:`sunset.pierce.crest_candidates`, :func:`sunset.pierce.crest_cylinder`,
  :func:`sunset.pierce.cylinder_coefficients`, :func:`sunset.pierce.quadratic_interval`).
* :func:`pierce_islands` is :func:`sunset.pierce.pierce_islands`: the
  bounding test compresses each island's candidates, then its three
  quadratics and the nearest-hit selection, in two compiled passes.
* :func:`write_back` scatters the traced rays into the frame.

Everything else (the sea's profile and normals with NumPy's SIMD cosines,
the normals on compressed subsets, the codes) stays NumPy. The tests check
that both paths give the same frames and the same codes.

The compiled path is used when Numba can be imported and the environment
variable ``SUNSET_COMPILED`` is not ``0``; :func:`use_compiled` switches it
for a block of code (the tests run both paths).
"""

from __future__ import annotations

import contextlib
import math
import os

import numpy as np

try:  # pragma: no cover - exercised by whichever environment runs the tests
    import numba as _numba
except ImportError:  # pragma: no cover
    _numba = None

__all__ = ["AVAILABLE", "enabled", "use_compiled", "scan_columns", "scan_merge", "reflect_sea", "crest_hits",
           "pierce_islands", "island_table", "assemble", "put_unit_normals", "write_back",
           "expand_intervals"]

#: True when Numba is importable (the compiled kernels exist).
AVAILABLE = _numba is not None

_state = {"on": AVAILABLE and os.environ.get("SUNSET_COMPILED", "1") != "0"}


def enabled() -> bool:
    """Whether the renderer uses the compiled kernels now."""
    return _state["on"]


@contextlib.contextmanager
def use_compiled(flag: bool):
    """Use (True) or avoid (False) the compiled kernels inside a ``with`` block.

    Asking for them where Numba is missing leaves the NumPy path on.
    """
    old = _state["on"]
    _state["on"] = bool(flag) and AVAILABLE
    try:
        yield _state["on"]
    finally:
        _state["on"] = old


def _jit(fn):
    """Compile with NumPy's float semantics (x/0 gives ±inf or NaN, no exception), cached on disk."""
    if _numba is None:
        return fn
    return _numba.njit(cache=True, nogil=True, error_model="numpy")(fn)


# --------------------------------------------------------------------------- scan conversion
@_jit
def _scan_row(u, us, g, gs, n, zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t, zero_t, K, out):
    """One scan line: out[k] = 1/yp of pixel k (bottom up), 0 where no sample rises above it."""
    prof = neg_inf_t
    k = 0
    i = 0
    while i < n and k < K:
        gi = g[gs + i]
        if not gi > prof:  # np.maximum.accumulate: the profile did not rise, no pixel is reached here
            i += 1
            continue
        prof = gi
        # the pixel units of scan_convert: ⌈(M_i − ζ0)/Δζ⌉ in g's dtype, clipped to 0..K
        r = np.ceil((prof - zeta0_t) * inv_dzeta_t)
        if r < zero_t:
            r = zero_t
        elif r > kf_t:
            r = kf_t
        b = int(r)
        # pixels k < b have their first sample above them at i
        while k < b:
            if i > 0:
                g0 = np.float64(g[gs + i - 1])
                g1 = np.float64(gi)
                u0 = u[us + i - 1]
                u1 = u[us + i]
                den = g1 - g0
                if den > 0:
                    f = ((zeta0 + dzeta * k) - g0) / den
                    if f < 0.0:
                        f = 0.0
                    elif f > 1.0:
                        f = 1.0
                else:
                    f = 0.0
                out[k] = u0 + f * (u1 - u0)
            else:
                u0 = u[us]
                out[k] = u0 + 0.0 * (u0 - u0)
            k += 1
        i += 1
    while k < K:
        out[k] = 0.0
        k += 1


@_jit
def _scan_columns(u, u_start, g, g_start, counts, zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t, zero_t,
                  n_pixels, out):
    # *_t arguments have g's dtype, so that the pixel units are computed in it, as scan_convert does
    for c in range(counts.shape[0]):
        _scan_row(u, u_start[c], g, g_start[c], counts[c], zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t,
                  zero_t, n_pixels, out[c])


@_jit
def _scan_merge(u, u_start, g, g_start, counts, zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t, zero_t,
                n_pixels, tail, u_far, best_u, best_surf, code):
    K = n_pixels
    row = np.empty(K)
    n_tail = 0
    for c in range(counts.shape[0]):
        _scan_row(u, u_start[c], g, g_start[c], counts[c], zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t,
                  zero_t, K, row)
        if tail and counts[c] > 0:
            # the far tail: the plane at the farthest sample's height (as trace_direct)
            g_far = np.float64(g[g_start[c] + counts[c] - 1])
            for k in range(K):
                zk = zeta0 + dzeta * k
                if row[k] == 0 and zk < 0:
                    n_tail += 1
                    if g_far < 0:
                        ut = zk * u_far / min(g_far, -1e-30)
                    else:
                        ut = 0.0
                    if ut < 0.0:
                        ut = 0.0
                    elif ut > u_far:
                        ut = u_far
                    row[k] = ut
        for k in range(K):
            if row[k] > best_u[c, k]:
                best_u[c, k] = row[k]
                best_surf[c, k] = code
    return n_tail


def _scan_args(u, g, counts, zeta0, dzeta, n_pixels):
    g = np.ascontiguousarray(g)
    if g.dtype not in (np.float32, np.float64):
        g = g.astype(np.float64)
    u = np.ascontiguousarray(u, dtype=np.float64)
    counts = np.ascontiguousarray(counts, dtype=np.int64)
    C = counts.shape[0]
    if g.ndim == 2:
        g_start = np.arange(C, dtype=np.int64) * g.shape[1]
        u_start = np.zeros(C, np.int64) if u.ndim == 1 else g_start
    else:
        g_start = np.cumsum(counts) - counts
        u_start = g_start
    dt = g.dtype.type
    return (u.reshape(-1), u_start, g.reshape(-1), g_start, counts, float(zeta0), float(dzeta), dt(1.0 / dzeta),
            dt(zeta0), dt(-np.inf), dt(n_pixels), dt(0.0), int(n_pixels))


def scan_merge(u, g, counts, zeta0: float, dzeta: float, n_pixels: int, best_u, best_surf, code: int,
               tail_u_far: float | None = None) -> int:
    """:func:`scan_columns` merged into a depth buffer: where the new 1/yp is larger, it and ``code`` win.

    ``best_u`` (C, K) float64 and ``best_surf`` (C, K) int8 are updated in
    place (C-contiguous). With ``tail_u_far`` the sea's far tail of
    :func:`sunset.heightfield.trace_direct` is applied first (pixels below
    the horizon that no sample reached meet the plane at the farthest
    sample's height, whose 1/y is ``tail_u_far``). Returns the number of tail pixels.
    """
    if not (best_u.flags.c_contiguous and best_surf.flags.c_contiguous):
        raise ValueError("best_u and best_surf must be C-contiguous")
    args = _scan_args(u, g, counts, zeta0, dzeta, n_pixels)
    tail = tail_u_far is not None
    return int(_scan_merge(*args, tail, float(tail_u_far) if tail else 0.0, best_u, best_surf, int(code)))


def scan_columns(u, g, counts, zeta0: float, dzeta: float, n_pixels: int) -> np.ndarray:
    """The scan conversion of :func:`sunset.heightfield.scan_convert`, one scan line at a time.

    Parameters
    ----------
    u : ndarray float64
        1/y of the samples, near to far: (N,) shared by all rows, (C, N) per
        row, or flat (S,) in the layout of a flat ``g``.
    g : ndarray float32 or float64
        Projected heights: (C, N), of which row c's first ``counts[c]`` are
        read, or flat (S,): row c is the next ``counts[c]`` values.
    counts : ndarray (C,) int
        Samples in each row.
    zeta0, dzeta, n_pixels
        As :func:`sunset.heightfield.scan_convert`.

    Returns
    -------
    ndarray (C, K) float64
        1/yp bottom up, 0 where the ray passes over every sample; equal to
        ``scan_convert`` (same pixel units in g's dtype, same float64 interpolation).
    """
    args = _scan_args(u, g, counts, zeta0, dzeta, n_pixels)
    out = np.empty((args[4].shape[0], int(n_pixels)))
    _scan_columns(*args, out)
    return out


# --------------------------------------------------------------------------- reflections
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
    ``frame.point[mask]`` and :func:`sunset.pierce.reflect` of the direction
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
    """(t_in, t_out, meets) as sunset.pierce.quadratic_interval, for one ray."""
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
    """Phase from a ray's start to the next crest ahead of it (as sunset.pierce.crest_phase), radians."""
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
            # the bounding test of sunset.pierce.crest_candidates
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
        # Σ a_n cos nθ by the Chebyshev recurrence (sunset.pierce.harmonic_sum)
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

    :func:`sunset.pierce.first_entry` of the cylinder of
    :func:`sunset.pierce.crest_cylinder`, for rays (N, 3), after the bounding
    test of :func:`sunset.pierce.crest_candidates`. A first pass reduces the
    phase to ψ = θ mod 2π and compresses the candidates; NumPy takes cos ψ on
    them (the reference's cosine); a second pass does the rest.
    """
    from .pierce import crest_curvature, crest_lift

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

    Heights are turned into eye coordinates exactly as :func:`sunset.pierce.island_intervals`
    does; ``rho`` and ``top_h`` are the bounding circle of
    :func:`sunset.pierce.island_candidates` for origins no lower than ``z0``.
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
def _island_candidates(q, r, X, Y, rho, top_h, cand):
    """The bounding test of sunset.pierce.island_candidates for one island; candidates' indices into cand."""
    n = 0
    rr = rho * rho
    for j in range(q.shape[0]):
        qx, qy, qz = q[j, 0], q[j, 1], q[j, 2]
        rx, ry, rz = r[j, 0], r[j, 1], r[j, 2]
        cx = X - qx
        cy = Y - qy
        horiz = math.sqrt(rx * rx + ry * ry)
        along = rx * cx + ry * cy
        near_line = (abs(rx * cy - ry * cx) <= rho * horiz) & (along > -rho * horiz)
        low_enough = (along - rho * horiz) * rz <= (top_h - qz) * horiz * horiz
        keep = (rz < 0.0) | (near_line & low_enough) | (cx * cx + cy * cy <= rr)
        cand[n] = j
        n += keep  # branch-free compress
    return n


@_jit
def _pierce_island(q, r, cand, row, h, k, part_beach, part_cliff, part_hill, best, which, part):
    """sunset.pierce.pierce_island for the candidate rays of one island, keeping the nearest hit so far."""
    X, Y = row[0], row[1]
    e, f, g = row[2], row[3], row[4]
    c_top, ct, kf = row[5], row[6], row[7]
    be, bf, bg, b_top = row[8], row[9], row[10], row[11]
    for jj in range(cand.shape[0]):
        j = cand[jj]
        qx, qy, qz = q[j, 0], q[j, 1], q[j, 2]
        rx, ry, rz = r[j, 0], r[j, 1], r[j, 2]
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
            t = upper_t
            p = part_hill if h_in > c_in else part_cliff
        else:
            t = beach_t
            p = part_beach
        if t < best[j]:
            best[j] = t
            which[j] = k
            part[j] = p


@_jit
def _lowest_upward_origin(q, r):
    z0 = np.inf
    for j in range(q.shape[0]):
        if r[j, 2] >= 0.0 and q[j, 2] < z0:
            z0 = q[j, 2]
    return z0


def pierce_islands(islands, eye_height: float, q, r):
    """:func:`sunset.pierce.pierce_islands` compiled: (t, which, part) for rays (N, 3).

    Island by island, as the reference: a branch-free pass of the bounding
    test compresses the candidates, and a second pass solves the three
    quadratics for them and keeps the nearest hit.
    """
    from .constants import PART_BEACH, PART_CLIFF, PART_HILL

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
    cand = np.empty(n, np.intp)
    for i, row in enumerate(table):
        m = _island_candidates(q, r, row[0], row[1], row[12], row[13], cand)
        _pierce_island(q, r, cand[:m], row, float(eye_height), i + 1, PART_BEACH, PART_CLIFF, PART_HILL, best,
                       which, part)
    return best, which, part


# --------------------------------------------------------------------------- the direct frame
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


def assemble(best_u, best_surf, s_all, zeta, sky_code: int, sea_code: int, n_islands: int):
    """The geometry of :func:`sunset.heightfield._assemble` in one pass.

    From 1/yp and the winning surface per (scan line, pixel from the bottom):
    ``surf`` (H, W) int8, ``direction``, ``point`` (H, W, 3) float32,
    ``distance`` (H, W) float32 and ``normal`` (H, W, 3) float32 (NaN except
    on the sea, left for the caller to fill), and for surface ``sea_code + i``
    (i = 0 the sea, i = k island k) the compressed list ``hits[i] = (flat
    pixel index, s, y)`` in row-major order (``np.flatnonzero`` order).
    """
    W, H = best_u.shape
    best_surf = np.ascontiguousarray(best_surf)
    counts = np.bincount(best_surf.reshape(-1).view(np.uint8), minlength=256)
    # int8 codes sea_code … sea_code + n_islands as uint8 bins (all >= 0)
    per = counts[sea_code:sea_code + n_islands + 1].astype(np.int64)
    start = np.concatenate([[0], np.cumsum(per)[:-1]]).astype(np.int64)
    total = int(per.sum())
    surf = np.empty((H, W), np.int8)
    direction = np.empty((H, W, 3), np.float32)
    point = np.empty((H, W, 3), np.float32)
    distance = np.empty((H, W), np.float32)
    normal = np.empty((H, W, 3), np.float32)
    hit_flat = np.empty(total, np.intp)
    hit_s = np.empty(total)
    hit_y = np.empty(total)
    _assemble(np.ascontiguousarray(best_u), best_surf, np.ascontiguousarray(s_all, np.float64),
              np.ascontiguousarray(zeta, np.float64), sky_code, sea_code, start, surf, direction, point, distance,
              normal, hit_flat, hit_s, hit_y)
    hits = [(hit_flat[a:a + n], hit_s[a:a + n], hit_y[a:a + n]) for a, n in zip(start, per)]
    return surf, direction, point, distance, normal, hits


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

    The arithmetic of :func:`sunset.heightfield._unit_normal` in the dtype of ``fx``.
    """
    if len(flat) == 0:
        return
    _put_unit_normals(np.ascontiguousarray(flat, np.intp), np.ascontiguousarray(fx), np.ascontiguousarray(fy),
                      fx.dtype.type(1.0), normal.reshape(-1, 3))


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


# --------------------------------------------------------------------------- island samples
@_jit
def _expand_intervals(up, n, count, last_valid, out):
    C, P1 = n.shape
    pos = 0
    for c in range(C):
        if count[c] == 0:
            continue
        for j in range(P1):
            nj = n[c, j]
            ua = up[c, j]
            ub = up[c, j + 1]
            for q in range(nj):
                out[pos] = ua + (ub - ua) * (q / nj)
                pos += 1
        out[pos] = up[c, last_valid[c]]
        pos += 1


def expand_intervals(up, n, count, last_valid) -> np.ndarray:
    """The flat island samples of :func:`sunset.heightfield._island_samples_flat` from its probe.

    Row c: each probe interval j cut into ``n[c, j]`` equal parts in u
    (u_j + (u_(j+1) − u_j) q/n), then the row's far end ``up[c, last_valid[c]]``;
    rows with ``count[c] == 0`` are skipped.
    """
    out = np.empty(int(np.sum(count)))
    _expand_intervals(np.ascontiguousarray(up, np.float64), np.ascontiguousarray(n, np.int64),
                      np.ascontiguousarray(count, np.int64), np.ascontiguousarray(last_valid, np.int64), out)
    return out


# --------------------------------------------------------------------------- codes
@_jit
def _encode_pixels(codes, surf, part, normal, ray, bounces, u, v, U, V, W, part_codes, island_start, island_size,
                   sky_start, sky_size, track_start, track_size, halo_start, halo_size, dither, sin_d, sin_halo,
                   e_max):
    H, Wd = surf.shape
    for y in range(H):
        for x in range(Wd):
            s = surf[y, x]
            uu = u[y, x]
            if s >= 1:
                # ρ̂(N) (sunset.codes.rho_hat) and the island offset (sunset.codes.island_offsets)
                n0 = np.float64(normal[y, x, 0])
                n1 = np.float64(normal[y, x, 1])
                n2 = np.float64(normal[y, x, 2])
                a = n0 * U[0] + n1 * U[1] + n2 * U[2]
                b = n0 * V[0] + n1 * V[1] + n2 * V[2]
                r = math.hypot(a, b)
                rho = -a / r if r > 1e-12 else 1.0
                if rho < -1.0:
                    rho = -1.0
                elif rho > 1.0:
                    rho = 1.0
                rh = rho if b > 0 else 2.0 - rho
                if rh >= 3.0:
                    rh = rh - 4.0
                p = part[y, x]
                j = -1
                for i in range(part_codes.shape[0]):
                    if part_codes[i] == p:
                        j = i
                if j < 0:
                    return p
                size = island_size[j]
                off = np.int64(np.floor((rh + 1.0) * (size / 4.0) + uu)) % size
                codes[y, x] = island_start[j] + off
            elif s == -1:
                z = np.float64(ray[y, x, 2])
                zc = min(max(z, 0.0), 1.0)
                k = np.int64(np.floor(math.sqrt(zc) * sky_size + uu))
                code = sky_start + min(max(k, 0), sky_size - 1)
                if bounces[y, x] > 0:
                    dot = np.float64(ray[y, x, 0]) * W[0] + np.float64(ray[y, x, 1]) * W[1] + z * W[2]
                    wr = abs(dot) + (v[y, x] - 0.5) * dither
                    if wr < sin_d:
                        k = np.int64(np.floor(math.asin(zc) * (track_size / e_max) + uu))
                        code = track_start + min(max(k, 0), track_size - 1)
                    elif wr < sin_halo:
                        k = np.int64(np.floor(math.asin(zc) * (halo_size / e_max) + uu))
                        code = halo_start + min(max(k, 0), halo_size - 1)
                codes[y, x] = code
    return -1


def encode_pixels(codes, frame, u, v, sun, cmap, part_ids, dither: float, sin_d: float, sin_halo: float,
                  e_max: float):
    """The codes of :func:`sunset.codes.encode` in one pass over the pixels, into ``codes`` (uint8, in place).

    ``u`` and ``v`` are encode's dither arrays; ``part_ids`` the island parts
    in the order of their code ranges. Returns -1, or the first unknown island
    part met (the caller raises).
    """
    ranges = [cmap.for_part(p) for p in part_ids]
    return int(_encode_pixels(
        codes, np.ascontiguousarray(frame.final_surface), np.ascontiguousarray(frame.final_part),
        np.ascontiguousarray(frame.final_normal), np.ascontiguousarray(frame.ray),
        np.ascontiguousarray(frame.bounces), u, v, np.asarray(sun.U, float), np.asarray(sun.V, float),
        np.asarray(sun.W, float), np.asarray(part_ids, np.int64), np.array([r.start for r in ranges], np.int64),
        np.array([r.size for r in ranges], np.int64), cmap.sky.start, cmap.sky.size, cmap.track.start,
        cmap.track.size, cmap.halo.start, cmap.halo.size, float(dither), float(sin_d), float(sin_halo),
        float(e_max)))
