"""Numba twins of :func:`sunset.vector.heightfield.sea_scan` (the scan line, the far tail and the depth buffer in one
compiled loop), of :func:`sunset.vector.heightfield.sea_profile` (the phases, the cosines and Horner's rule,
compiled) and of :func:`sunset.vector.heightfield.sea_columns` (both, one scan line at a time).

:func:`scan_columns` is the paper's scan-line loop
(:func:`sunset.vector.heightfield.scan_line_reference`) with the arithmetic of
the vectorized :func:`sunset.vector.heightfield.scan_convert` (the pixel units
in the profile's precision, the interpolation in float64), over many scan
lines of ragged length; :func:`scan_merge` adds the sea's far tail and the
per-scan-line depth buffer. The profile's cosines are our own vectorised
float32 cosine (:mod:`sunset.vector.sincos_numba`), not NumPy's, so the
profile agrees with the reference to a float32 rounding or two and the
frames within the tolerances of chapter 10 (tests).
:func:`sea_columns` computes a scan line's profile into a buffer of one scan
line and scan-converts it while it is in cache: no (C, n) profile at all. Its
scan line is :func:`_scan_row_b`, the same result as :func:`_scan_row`
without the walk's data-dependent branches, which the sea's long, mostly
rising profiles mispredict.
Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import numpy as np

from ..constants import SEA
from ..kernels import jit as _jit
from .sincos_numba import LIMIT, cos_into, cos_of, parts
from . import heightfield as _reference
from .heightfield import _F32, _chebyshev_power, _profile_arrays, _sea_terms


@_jit
def _scan_row(u, us, g, gs, n, zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t,
              zero_t, K, out):
    """One scan line: out[k] = 1/yp of pixel k (bottom up).

    0 where no sample rises above it.
    """
    prof = neg_inf_t
    k = 0
    i = 0
    while i < n and k < K:
        gi = g[gs + i]
        # np.maximum.accumulate: the profile did not rise, no pixel is reached here
        if not gi > prof:
            i += 1
            continue
        prof = gi
        # the pixel units of scan_convert: ⌈(M_i − ζ0)/Δζ⌉ in g's dtype, clipped
        # to 0..K
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
                out[k] = u[us]
            k += 1
        i += 1
    while k < K:
        out[k] = 0.0
        k += 1


@_jit
def _scan_row_b(u, us, g, gs, n, zeta0, dzeta, inv_dzeta_t, zeta0_t, kf_t, zero_t, K, out, bins, first):
    """:func:`_scan_row` without its data-dependent branches; ``bins`` (n) and ``first`` (K + 1): scratch.

    The pixel units b_i = clip(⌈(g_i − ζ0)/Δζ⌉, 0, K) rise with g_i, so the
    running maximum B_i of the b_i is the profile's; pixel k's first sample
    above it is the first i with B_i > k, which is the last i with
    B_(i−1) = k (B_(−1) = 0), or n for k = B_(n−1); the pixels between are
    filled from the one below.
    """
    for i in range(n):                       # vectorised: no branch
        r = np.ceil((g[gs + i] - zeta0_t) * inv_dzeta_t)
        r = r if r > zero_t else zero_t      # NaN and −∞ to 0, as never rising
        r = r if r < kf_t else kf_t
        bins[i] = np.int32(r)
    for k in range(K + 1):
        first[k] = -1
    top = 0
    for i in range(n):
        first[top] = i
        top = max(top, bins[i])
    first[top] = n
    last = first[0]
    for k in range(K):
        i = first[k]
        if i < 0:
            i = last
        last = i
        if i >= n:
            out[k] = 0.0
        elif i > 0:
            g0 = np.float64(g[gs + i - 1])
            g1 = np.float64(g[gs + i])
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
            out[k] = u[us]


@_jit
def _scan_columns(u, u_start, g, g_start, counts, zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t, zero_t,
                  n_pixels, out):
    # *_t arguments have g's dtype, so that the pixel units are computed in it, as scan_convert does
    for c in range(counts.shape[0]):
        _scan_row(u, u_start[c], g, g_start[c], counts[c], zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t,
                  zero_t, n_pixels, out[c])


@_jit
def _merge_row(row, g_far, u_far, zeta0, dzeta, tail, best_u, best_surf, code, ties):
    """One scan line's 1/yp ``row`` into its depth buffer (best_u, best_surf rows); the far tail first if ``tail``."""
    K = row.shape[0]
    n_tail = 0
    if tail:
        # the far tail: the plane at the farthest sample's height (as trace_direct)
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
        if row[k] > best_u[k] or (ties and row[k] > 0 and row[k] == best_u[k]):
            best_u[k] = row[k]
            best_surf[k] = code
    return n_tail


@_jit
def _scan_merge(u, u_start, g, g_start, counts, zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t, zero_t,
                n_pixels, tail, u_far, best_u, best_surf, code, ties):
    row = np.empty(n_pixels)
    n_tail = 0
    for c in range(counts.shape[0]):
        _scan_row(u, u_start[c], g, g_start[c], counts[c], zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t,
                  zero_t, n_pixels, row)
        g_far = np.float64(g[g_start[c] + counts[c] - 1]) if counts[c] > 0 else 0.0
        n_tail += _merge_row(row, g_far, u_far, zeta0, dzeta, tail and counts[c] > 0, best_u[c], best_surf[c],
                             code, ties)
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
               tail_u_far: float | None = None, ties: bool = False) -> int:
    """:func:`scan_columns` merged into a depth buffer: where the new 1/yp is larger, it and ``code`` win.

    With ``ties`` they also win where the new 1/yp is positive and equal
    (the sea, merged after the islands, wins ties).

    ``best_u`` (C, K) float64 and ``best_surf`` (C, K) int8 are updated in
    place (C-contiguous). With ``tail_u_far`` the sea's far tail of
    :func:`sunset.pipeline.frame.trace_direct` is applied first (pixels below
    the horizon that no sample reached meet the plane at the farthest
    sample's height, whose 1/y is ``tail_u_far``). Returns the number of tail pixels.
    """
    if not (best_u.flags.c_contiguous and best_surf.flags.c_contiguous):
        raise ValueError("best_u and best_surf must be C-contiguous")
    args = _scan_args(u, g, counts, zeta0, dzeta, n_pixels)
    tail = tail_u_far is not None
    return int(_scan_merge(*args, tail, float(tail_u_far) if tail else 0.0, best_u, best_surf, int(code),
                           bool(ties)))


def scan_columns(u, g, counts, zeta0: float, dzeta: float, n_pixels: int) -> np.ndarray:
    """The scan conversion of :func:`sunset.vector.heightfield.scan_convert`, one scan line at a time.

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
        As :func:`sunset.vector.heightfield.scan_convert`.

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


def sea_scan(u, g, zeta0: float, dzeta: float, n_pixels: int, best_u, best_surf) -> int:
    """:func:`sunset.vector.heightfield.sea_scan`: the scan line, the far tail and the depth buffer in one pass."""
    return scan_merge(u, g, np.full(len(g), len(u)), zeta0, dzeta, n_pixels, best_u, best_surf, SEA, tail_u_far=u[-1],
                      ties=True)


def _sea_coefficients(sea, s, t: float, h: float):
    """The profile's inputs for the compiled loops, in float32.

    Per train j: b_j = ℓ_j s + m_j per scan line (T, C), c_j (T,), the
    Chebyshev power coefficients p_0 … p_(n−1) padded with zeros (T, D) and
    their count n (T,); and Σ_j p_j0 − h, summed in float64 in train order.
    """
    terms = _sea_terms(sea, np.asarray(s, dtype=np.float64), t)
    powers = [_chebyshev_power(amps) for *_, amps in terms]
    b = np.empty((len(terms), np.size(s)), dtype=_F32)
    c = np.empty(len(terms), dtype=_F32)
    p = np.zeros((len(terms), max([len(q) for q in powers] + [1])), dtype=_F32)
    n = np.empty(len(terms), dtype=np.int64)
    const = 0.0
    for j, ((_l, _m, bj, cj, _amps), q) in enumerate(zip(terms, powers)):
        b[j], c[j], p[j, :len(q)], n[j] = bj, cj, q, len(q)
        const += q[0]
    return b, c, p, n, _F32(const - h)


@_jit
def _cos_phase_into(b, y, c, x, w):
    """x = b·y + c and w = cos x, float32 (:func:`sunset.vector.sincos_numba.cos_into`)."""
    for i in range(y.shape[0]):
        x[i] = b * y[i] + c
    cos_into(x, w)


@_jit
def _train_into(bj, cj, top, p1, degree, last, y, u32, const, g, first):
    """One train's share of a scan line's profile in one pass, for a Horner polynomial of ``degree`` 1 or 2.

    The operations of :func:`_profile_row` element by element (θ = b y + c,
    cos θ, Horner's rule, the profile written or added to, and for the
    ``last`` train (g + Σ p_0 − h)·u), with no arrays in between. Every
    phase must be within the cosine's fast range (:func:`_profile_row_fast` checks).
    """
    for i in range(y.shape[0]):
        q, s, cs = parts(bj * y[i] + cj)
        w = cos_of(q, s, cs)
        acc = w * top
        if degree == 2:
            acc = (acc + p1) * w
        v = acc if first else g[i] + acc
        g[i] = (v + const) * u32[i] if last else v


@_jit
def _profile_row_fast(col, b, c, p, n, y, u32, const, x, w, g):
    """:func:`_profile_row` with one pass for each train whose polynomial is of degree 1 or 2 and whose phases are all
    within the cosine's fast range (the others as there). ``y`` must be non-decreasing.

    Rounding is monotone, so the phases fl(fl(b y_i) + c) of sorted y_i are
    sorted too: the first and the last bound them all.
    """
    N = y.shape[0]
    T = b.shape[0]
    for j in range(T):
        bj, cj, d = b[j, col], c[j], n[j] - 1
        top = p[j, d]
        first, last = j == 0, j == T - 1
        if (d == 1 or d == 2) and N and abs(bj * y[0] + cj) <= LIMIT and abs(bj * y[N - 1] + cj) <= LIMIT:
            _train_into(bj, cj, top, p[j, 1], d, last, y, u32, const, g, first)
            continue
        _cos_phase_into(bj, y, cj, x, w)
        acc = g if first else x
        for i in range(N):
            acc[i] = w[i] * top
        for k in range(d - 1, 0, -1):
            pk = p[j, k]
            for i in range(N):
                acc[i] = (acc[i] + pk) * w[i]
        if not first:
            for i in range(N):
                g[i] = g[i] + acc[i]
        if last:
            for i in range(N):
                g[i] = (g[i] + const) * u32[i]
    if T == 0:
        for i in range(N):
            g[i] = (np.float32(0.0) + const) * u32[i]


# sea-profile-row-begin
@_jit
def _profile_row(col, b, c, p, n, y, u32, const, x, w, g):
    """g = sea_profile's scan line ``col`` in float32 (x, w: scratch)."""
    N = y.shape[0]
    for j in range(b.shape[0]):
        bj, cj, top = b[j, col], c[j], p[j, n[j] - 1]
        # θ = b_j y + c_j and cos θ
        _cos_phase_into(bj, y, cj, x, w)
        # Horner's rule in cos θ (p_0 is added at the end); the first
        # train writes the profile, the others add
        acc = g if j == 0 else x
        for i in range(N):
            acc[i] = w[i] * top
        for k in range(n[j] - 2, 0, -1):
            pk = p[j, k]
            for i in range(N):
                acc[i] = (acc[i] + pk) * w[i]
        if j > 0:
            for i in range(N):
                g[i] = g[i] + acc[i]
    if b.shape[0] == 0:
        g[:] = 0
    for i in range(N):
        g[i] = (g[i] + const) * u32[i]   # (elevation + Σ p_0 − h) · u


@_jit
def _sea_columns(b, c, p, n, y, u32, const, u, zeta0, dzeta, inv_dz_t, zeta0_t,
                 kf_t, zero_t, K, best_u, best_surf, code, monotone):
    """Each scan line's profile, then its scan line while it is in cache."""
    N = y.shape[0]
    x, w, g = np.empty(N, _F32), np.empty(N, _F32), np.empty(N, _F32)
    bins = np.empty(N, dtype=np.int32)
    first = np.empty(K + 1, dtype=np.int64)
    row = np.empty(K)
    n_tail = 0
    for col in range(b.shape[1]):
        if monotone:
            _profile_row_fast(col, b, c, p, n, y, u32, const, x, w, g)
        else:
            _profile_row(col, b, c, p, n, y, u32, const, x, w, g)
        _scan_row_b(u, 0, g, 0, N, zeta0, dzeta, inv_dz_t, zeta0_t, kf_t,
                    zero_t, K, row, bins, first)
        # the far tail, and the depth buffer (the sea wins ties)
        n_tail += _merge_row(row, np.float64(g[N - 1]), u[N - 1], zeta0, dzeta,
                             True, best_u[col], best_surf[col], code, True)
    return n_tail
# sea-profile-row-end


@_jit
def _profile_rows(b, c, p, n, y, u32, const, g, monotone):
    x = np.empty(y.shape[0], dtype=np.float32)
    w = np.empty(y.shape[0], dtype=np.float32)
    for col in range(g.shape[0]):
        if monotone:
            _profile_row_fast(col, b, c, p, n, y, u32, const, x, w, g[col])
        else:
            _profile_row(col, b, c, p, n, y, u32, const, x, w, g[col])


def _monotone(y) -> bool:
    """Whether y never decreases (no NaN): :func:`_profile_row_fast` bounds a train's phases by the first and the last."""
    return bool(np.all(y[1:] >= y[:-1]))


def sea_profile(sea, s, u, h: float, t: float = 0.0):
    """:func:`sunset.vector.heightfield.sea_profile` compiled, cosines included (float32)."""
    s, u, y, elev = _profile_arrays(s, u)
    if u.size:
        b, c, p, n, const = _sea_coefficients(sea, s, t, h)
        _profile_rows(b, c, p, n, y, u.astype(_F32), const, elev, _monotone(y))
    return elev


def sea_columns(sea, s, u, h: float, t: float, zeta0: float, dzeta: float, n_pixels: int, best_u, best_surf) -> int:
    """:func:`sunset.vector.heightfield.sea_columns`: each scan line's profile, scan line, far tail and depth buffer.

    No (C, n) profile is made: a scan line's profile is scan-converted
    while it is in cache. ``best_u`` and ``best_surf`` are updated in place.
    """
    u = np.ascontiguousarray(u, dtype=np.float64)
    if u.size == 0:
        return _reference.sea_columns.reference(sea, s, u, h, t, zeta0, dzeta, n_pixels, best_u, best_surf)
    b, c, p, n, const = _sea_coefficients(sea, s, t, h)
    y = (1.0 / u).astype(_F32)
    bu, bs = np.ascontiguousarray(best_u), np.ascontiguousarray(best_surf)
    f = _F32
    tail = int(_sea_columns(b, c, p, n, y, u.astype(_F32), const, u, float(zeta0), float(dzeta), f(1.0 / dzeta),
                            f(zeta0), f(n_pixels), f(0.0), int(n_pixels), bu, bs, SEA, _monotone(y)))
    if bu is not best_u:
        best_u[...] = bu
    if bs is not best_surf:
        best_surf[...] = bs
    return tail
