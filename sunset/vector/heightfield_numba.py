"""Numba twins of :func:`sunset.vector.heightfield.sea_scan` (the scan line, the far tail and the depth buffer in one
compiled loop) and of :func:`sunset.vector.heightfield.sea_profile` (each train's phase, and Horner's rule summed into
the profile, in one pass each).

:func:`scan_columns` is the paper's scan-line loop
(:func:`sunset.vector.heightfield.scan_line_reference`) with the arithmetic of
the vectorized :func:`sunset.vector.heightfield.scan_convert` (same pixel units
in the profile's precision, same interpolation), over many scan lines of
ragged length; :func:`scan_merge` adds the sea's far tail and the
per-scan-line depth buffer. The same operations in the same order as the
NumPy reference, one element at a time: the frames are identical (tests).
:func:`sea_profile` leaves the cosines to NumPy: its float32 ``cos`` is
NumPy's own vectorised one, which a compiled loop (the C library's
``cosf``) does not reproduce bit for bit. Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import numpy as np

from ..constants import SEA
from ..kernels import jit as _jit
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
                n_pixels, tail, u_far, best_u, best_surf, code, ties):
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
            if row[k] > best_u[c, k] or (ties and row[k] > 0 and row[k] == best_u[c, k]):
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
               tail_u_far: float | None = None, ties: bool = False) -> int:
    """:func:`scan_columns` merged into a depth buffer: where the new 1/yp is larger, it and ``code`` win.

    With ``ties`` they also win where the new 1/yp is positive and equal
    (the sea, merged after the islands, wins ties).

    ``best_u`` (C, K) float64 and ``best_surf`` (C, K) int8 are updated in
    place (C-contiguous). With ``tail_u_far`` the sea's far tail of
    :func:`sunset.vector.direct.trace_direct` is applied first (pixels below
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


@_jit
def _phase(b, y, c, phase):
    """phase[i, j] = b[i] y[j] + c, in float32 (the reference's multiply, then add)."""
    for i in range(phase.shape[0]):
        bi = b[i]
        for j in range(phase.shape[1]):
            phase[i, j] = bi * y[j] + c


@_jit
def _horner_into(cos_theta, p, elev, first):
    """elev (+)= Σ_(j>=1) p_j cos^j θ by Horner's rule, float32, as the reference's passes.

    ``first``: the first train writes the profile instead of adding to it
    (0 + x is not x when x is −0).
    """
    n = p.shape[0]
    for i in range(elev.shape[0]):
        for j in range(elev.shape[1]):
            x = cos_theta[i, j]
            acc = x * p[n - 1]
            for k in range(n - 2, 0, -1):
                acc = acc + p[k]
                acc = acc * x
            if first:
                elev[i, j] = acc
            else:
                elev[i, j] = elev[i, j] + acc


@_jit
def _finish_profile(elev, const, u32):
    """g = (elevation + (Σ p_0 − h))·u, float32."""
    for i in range(elev.shape[0]):
        for j in range(elev.shape[1]):
            elev[i, j] = (elev[i, j] + const) * u32[j]


def sea_profile(sea, s, u, h: float, t: float = 0.0):
    """:func:`sunset.vector.heightfield.sea_profile` compiled, but for NumPy's cosines: the same float32 bits."""
    s, u, y, elev = _profile_arrays(s, u)
    if u.size == 0:
        return elev
    phase = np.empty_like(elev)
    const = 0.0
    first = True
    for _l, _m, b, c, amps in _sea_terms(sea, s, t):
        _phase(np.ascontiguousarray(b, dtype=_F32), y, _F32(c), phase)
        np.cos(phase, out=phase)
        p = _chebyshev_power(amps)
        const += p[0]
        _horner_into(phase, p.astype(_F32), elev, first)
        first = False
    _finish_profile(elev, _F32(const - h), u.astype(_F32))
    return elev
