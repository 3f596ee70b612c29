"""Numba twins of :mod:`sunset.vector.island_samples`: the islands' samples kept compressed.

:func:`island_scan` samples an island on its scan lines as the reference
does but keeps the samples as one flat array (no padding to evaluate or scan),
cuts the probe intervals with :func:`expand_intervals`, and merges them into
the depth buffer with :func:`sunset.vector.heightfield_numba.scan_merge`.
Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import functools

import numpy as np

from ..kernels import jit as _jit
from .sincos_numba import cos_into
from .heightfield_numba import _scan_row, scan_merge
from .island_samples import _island_lattice, _island_profile, _island_profile_flat, _island_samples_flat


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
    """The flat island samples of :func:`sunset.vector.island_samples._island_samples_flat` from its probe.

    Row c: each probe interval j cut into ``n[c, j]`` equal parts in u
    (u_j + (u_(j+1) − u_j) q/n), then the row's far end ``up[c, last_valid[c]]``;
    rows with ``count[c] == 0`` are skipped.
    """
    out = np.empty(int(np.sum(count)))
    _expand_intervals(np.ascontiguousarray(up, np.float64), np.ascontiguousarray(n, np.int64),
                      np.ascontiguousarray(count, np.int64), np.ascontiguousarray(last_valid, np.int64), out)
    return out


def island_scan(island, s, samp, d: float, h: float, m0: int, zeta0: float, dzeta: float, K: int, sigma: float,
                budget: int, refine: bool, best_u, best_surf, code: int) -> int:
    """:func:`sunset.vector.island_samples.island_scan` with the samples kept compressed (no padding)."""
    if refine:
        lat = _island_samples_flat(island, s, samp, d, h, m0, zeta0, dzeta, K, sigma, budget)
        if lat is None:
            return 0
        u, counts = lat
        g = _island_profile_flat(island, np.repeat(s, counts), u, h)
    else:
        lat = _island_lattice(island, s, samp, d, min(m0, 1))
        if lat is None:
            return 0
        u, valid = lat
        counts = valid.sum(axis=1)
        g = _island_profile(island, s, u, valid, h)
    scan_merge(u, g, counts, zeta0, dzeta, K, best_u, best_surf, code)
    return int(counts.sum())


# --------------------------------------------------------------------------- every island of a strip in one call
# The islands' whole pass on a strip of scan lines, compiled: the chords of the bounding ellipses, the probe
# lattice, its profile, the adaptive cut of the probe intervals, the samples' profile, the scan line and the
# depth buffer, one scan line at a time with the GIL released, so that the strips of
# :func:`sunset.pipeline.frame.island_pass` run on all cores. The NumPy reference is
# :func:`sunset.vector.island_samples.islands_scan`: float64 where it computes in float64, float32 where it
# computes in float32, with our own float32 cosine (:mod:`sunset.vector.sincos_numba`).

#: Columns of the packed float32 island parameters (:func:`_pack`).
_X, _Y, _CH, _CE, _CF, _CG, _BH, _BE, _BF, _BG, _CT, _PHI = range(12)


@_jit
def _profile_into(p, cos_p, c0, c1, s, uu, n, h32, xb, yb, pb, cb, g):
    """g[i] = (H − h)·u at the samples uu[i] (1/y), i < n, of scan line s, float32 (:func:`_island_profile_flat`).

    ``xb``, ``yb``, ``pb``, ``cb`` (≥ n) float32 are scratch. The island's surface
    (:meth:`sunset.model.islands.Island.surface`) term by term over the
    samples, so that the cosines run vectorised (:func:`sunset.vector.sincos_numba.cos_into`).
    """
    x = xb[:n]
    y = yb[:n]
    ph = pb[:n]
    cs = cb[:n]                 # apart from ph: LLVM vectorises the cosines only where they do not overlap
    for i in range(n):
        yi = np.float32(1.0 / uu[i])
        y[i] = yi
        x[i] = np.float32(s * np.float64(yi))
    X, Y = p[_X], p[_Y]
    he, e, f, gg = p[_CH], p[_CE], p[_CF], p[_CG]
    for i in range(n):
        dx = x[i] - X
        dy = y[i] - Y
        g[i] = he - (e * dx * dx + f * dx * dy + gg * dy * dy)
    for j in range(c0, c1):
        a, l, m, phase = cos_p[j, 0], cos_p[j, 1], cos_p[j, 2], cos_p[j, 3]
        for i in range(n):
            ph[i] = l * x[i] + m * y[i] + phase
        cos_into(ph, cs)
        for i in range(n):
            g[i] = g[i] + a * cs[i]
    ct, phi = p[_CT], p[_PHI]
    bh, be, bf, bg = p[_BH], p[_BE], p[_BF], p[_BG]
    for i in range(n):
        q = g[i]
        upper = ct + phi * (q - ct) if q > ct else q
        dx = x[i] - X
        dy = y[i] - Y
        beach = bh - (be * dx * dx + bf * dx * dy + bg * dy * dy)
        hgt = beach if beach >= upper else upper
        g[i] = (hgt - h32) * np.float32(uu[i])


@_jit
def _min_nan(a, b):
    if a != a:
        return a
    if b != b:
        return b
    return a if a <= b else b


@_jit
def _max_nan(a, b):
    if a != a:
        return a
    if b != b:
        return b
    return a if a >= b else b


@_jit
def _chord(ch, s):
    """The chord (y_near, y_far) of scan line s through one ellipse (:meth:`Paraboloid.chord`), float64.

    ``ch`` = (e, f, g, X, Y, 2e, 2gY, C − (height − level)).
    """
    e, f, g, X, Y, two_e, two_gy, c = ch[0], ch[1], ch[2], ch[3], ch[4], ch[5], ch[6], ch[7]
    a = e * s * s + f * s + g
    b = two_e * s * X + f * (X + s * Y) + two_gy
    disc = b * b - 4.0 * a * c
    if not disc >= 0:
        return np.nan, np.nan
    root = np.sqrt(disc)
    q = 0.5 * (b + np.copysign(root, b))
    r1 = q / a
    r2 = c / q if q != 0 else r1
    return _min_nan(r1, r2), _max_nan(r1, r2)


@_jit
def _fmin(a, b):
    if a != a:
        return b
    if b != b:
        return a
    return a if a <= b else b


@_jit
def _fmax(a, b):
    if a != a:
        return b
    if b != b:
        return a
    return a if a >= b else b


@_jit
def _islands_strip(s_all, c_lo, c_hi, params, cos_p, cos_start, chords, m0s, y_clip, du_sea, zeta0,
                   dzeta, K, sigma, budget, refine, h, best_u, best_surf, row0):
    """Scan lines c_lo..c_hi − 1 of every island, merged into ``best_u``/``best_surf`` rows c − row0; samples."""
    h32 = np.float32(h)
    inv_dzeta_t = np.float32(1.0 / dzeta)
    zeta0_t = np.float32(zeta0)
    neg_inf_t = np.float32(-np.inf)
    kf_t = np.float32(K)
    zero_t = np.float32(0.0)
    row = np.empty(K)
    up = np.empty(64)            # the probe lattice of one scan line (grown when needed)
    rr = np.empty(64)
    nn = np.empty(64, np.int64)
    uu = np.empty(256)           # the island's samples on one scan line
    gg = np.empty(256, np.float32)
    xb, yb, pb, cb = (np.empty(256, np.float32), np.empty(256, np.float32), np.empty(256, np.float32),
                      np.empty(256, np.float32))
    samples = 0
    for k in range(m0s.shape[0]):
        m0 = m0s[k]
        if m0 <= 0:
            continue
        p = params[k]
        c0, c1 = cos_start[k], cos_start[k + 1]
        du = du_sea / (m0 if refine else min(m0, 1.0))
        for c in range(c_lo, c_hi):
            s = s_all[c]
            a0, a1 = _chord(chords[k, 0], s)
            b0, b1 = _chord(chords[k, 1], s)
            y0 = _fmin(a0, b0)
            y1 = _fmax(a1, b1)
            if not (np.isfinite(y0) and y1 > y_clip):
                continue
            ua = 1.0 / max(y0, y_clip)
            ub = 1.0 / y1
            j_top = np.int64(np.floor(ua / du - 1e-9))
            j_bot = np.int64(np.ceil(ub / du + 1e-9))
            m = max(j_top - j_bot + 1, 0) + 2      # the probe's samples: chord ends and the lattice between
            if m > up.shape[0]:
                up = np.empty(2 * m)
                rr = np.empty(2 * m)
                nn = np.empty(2 * m, np.int64)
            if m > gg.shape[0]:
                uu = np.empty(2 * m)
                gg = np.empty(2 * m, np.float32)
                xb, yb, pb, cb = (np.empty(2 * m, np.float32), np.empty(2 * m, np.float32), np.empty(2 * m, np.float32),
                                  np.empty(2 * m, np.float32))
            up[0] = ua
            for i in range(1, m - 1):
                up[i] = (j_top - (i - 1)) * du
            up[m - 1] = ub
            if not refine:
                total = m
                for i in range(m):
                    uu[i] = up[i]
            else:
                # the probe's profile in pixel units
                _profile_into(p, cos_p, c0, c1, s, up, m, h32, xb, yb, pb, cb, gg)
                for i in range(m):
                    r = (np.float64(gg[i]) - zeta0) / dzeta
                    if r < -1.0:
                        r = -1.0
                    elif r > K + 1.0:
                        r = K + 1.0
                    rr[i] = r
                # island-cut-begin
                # each interval cut into ⌈(|Δr| + |Δ²r|)/σ⌉ parts,
                # 1 where hidden behind the nearer profile
                total = 0
                top = rr[0]
                for j in range(m - 1):
                    dr = rr[j + 1] - rr[j]
                    dr_next = (rr[j + 2] - rr[j + 1]) if j + 2 < m else 0.0
                    d2 = abs(dr_next - dr)
                    if j > 0:
                        d2 = _max_nan(d2, abs(dr - (rr[j] - rr[j - 1])))
                    nj = np.int64(max(1.0, np.ceil((abs(dr) + d2) / sigma)))
                    top = _max_nan(top, rr[j])
                    reach = _max_nan(rr[j + 1], rr[j]) + abs(dr) + d2 + 1.0
                    if reach < top:
                        nj = 1
                    nn[j] = nj
                    total += nj
                # island-cut-end
                if total > budget:
                    scale = budget / max(total, 1)
                    total = 0
                    for j in range(m - 1):
                        nj = np.int64(max(1.0, np.floor(nn[j] * scale)))
                        nn[j] = nj
                        total += nj
                total += 1                          # the far end of the chord
                if total > uu.shape[0]:
                    uu = np.empty(2 * total)
                    gg = np.empty(2 * total, np.float32)
                    xb, yb, pb, cb = (np.empty(2 * total, np.float32), np.empty(2 * total, np.float32),
                                      np.empty(2 * total, np.float32), np.empty(2 * total, np.float32))
                pos = 0
                for j in range(m - 1):
                    nj = nn[j]
                    u_a = up[j]
                    u_b = up[j + 1]
                    for q in range(nj):
                        uu[pos] = u_a + (u_b - u_a) * (q / nj)
                        pos += 1
                uu[pos] = up[m - 1]
            _profile_into(p, cos_p, c0, c1, s, uu, total, h32, xb, yb, pb, cb, gg)
            # the highest pixel the island reaches on this scan line (its profile's top, in _scan_row's units):
            # the pixels above it stay 0 and cannot win, so only those below are scan-converted and merged
            top_g = neg_inf_t
            for i in range(total):
                if gg[i] > top_g:
                    top_g = gg[i]
            rt = np.ceil((top_g - zeta0_t) * inv_dzeta_t)
            K0 = 0 if not rt > zero_t else (K if rt > kf_t else int(rt))
            _scan_row(uu, 0, gg, 0, total, zeta0, dzeta, inv_dzeta_t, zeta0_t, neg_inf_t, kf_t, zero_t, K0, row)
            bu = best_u[c - row0]
            bs = best_surf[c - row0]
            for i in range(K0):
                if row[i] > bu[i]:
                    bu[i] = row[i]
                    bs[i] = k + 1
            samples += total
    return samples


@functools.lru_cache(maxsize=256)
def _pack(islands: tuple, d: float):
    """The islands' parameters as arrays for :func:`_islands_strip`: float32 surfaces, float64 chords."""
    n = len(islands)
    params = np.zeros((n, 12), np.float32)
    chords = np.zeros((n, 2, 8))
    cos_rows, start = [], [0]
    for k, isl in enumerate(islands):
        params[k] = [isl.x, isl.y, isl.cliff.height, isl.cliff.e, isl.cliff.f, isl.cliff.g, isl.beach.height,
                     isl.beach.e, isl.beach.f, isl.beach.g, isl.cliff_top, isl.hill_factor]
        lv = isl.bound_levels(d)
        for i, (par, level) in enumerate(((isl.cliff, lv["cliff"]), (isl.beach, lv["beach"]))):
            X, Y = isl.x, isl.y
            c = par.e * X * X + par.f * X * Y + par.g * Y * Y - (par.height - level)
            chords[k, i] = [par.e, par.f, par.g, X, Y, 2.0 * par.e, 2.0 * par.g * Y, c]
        for cs in isl.cosines:
            cos_rows.append([cs.amplitude, cs.l, cs.m, cs.phase])
        start.append(len(cos_rows))
    cos_p = np.array(cos_rows, np.float32).reshape(-1, 4)
    return params, cos_p, np.array(start, np.int64), chords


def islands_scan(islands, m0s, s_all, c0: int, c1: int, samp, d: float, h: float, zeta0: float, dzeta: float,
                 K: int, sigma: float, budget: int, refine: bool, best_u, best_surf) -> int:
    """:func:`sunset.vector.island_samples.islands_scan` in one compiled call (no GIL held)."""
    params, cos_p, cos_start, chords = _pack(tuple(islands), float(d))
    m0 = np.array([0.0 if m is None else float(m) for m in m0s], np.float64)
    if not (best_u.flags.c_contiguous and best_surf.flags.c_contiguous):
        raise ValueError("best_u and best_surf must be C-contiguous")
    return int(_islands_strip(np.ascontiguousarray(s_all, np.float64), int(c0), int(c1), params, cos_p,
                              cos_start, chords, m0, float(samp.y_clip), float(samp.du), float(zeta0), float(dzeta),
                              int(K), float(sigma), int(budget), bool(refine), float(h), best_u, best_surf, int(c0)))
