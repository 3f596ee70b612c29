"""Islands along the vertical scan lines: where to sample them, and how densely.

The sea's samples on a scan line are evenly spaced in u = 1/y
(:mod:`sunset.vector.heightfield`). An island (:mod:`sunset.model.islands`) is
sampled on the same scan lines, only between the ends of each scan line's
chord through the island's bounding ellipse, on the sea's lattice in u refined
by an integer factor m so that the island's own projected samples are about σ
pixels apart as well: the island's steep faces project much more sparsely than
the sea (the paper's m = 1 is kept as an option). An island's probe interval
that lies, with its allowance and a pixel to spare, below the island's own
profile nearer to the eye is hidden and is not refined (samples only where
they can be seen). :func:`island_scan` scan-converts the samples and merges
them into the per-scan-line depth buffer: the nearest surface (largest u) wins.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import ISLAND_MAX_REFINEMENT, ISLAND_PROBE_SAMPLES
from ..kernels import twin
from .heightfield import Sampling, scan_convert

__all__ = ["probe_refinement", "islands_scan", "island_scan", "expand_intervals"]

_F32 = np.float32


def _island_lattice(island, s, samp: Sampling, d: float, refine: int):
    """The u samples of one island on scan lines s: chord ends plus the refined lattice.

    Returns (u (C, n) float64 near to far, valid (C, n) bool) or None when no
    scan line meets the bounding ellipses in front of the near plane.
    """
    y0, y1 = island.chord(s, d)
    ok = np.isfinite(y0) & (y1 > samp.y_clip)
    if not ok.any():
        return None
    y0 = np.where(ok, np.maximum(y0, samp.y_clip), 1.0)
    y1 = np.where(ok, y1, 1.0)
    ua, ub = 1.0 / y0, 1.0 / y1
    du = samp.du / refine
    j_top = np.floor(ua / du - 1e-9).astype(np.int64)
    j_bot = np.ceil(ub / du + 1e-9).astype(np.int64)
    inner = np.where(ok, np.maximum(j_top - j_bot + 1, 0), 0)
    count = np.where(ok, inner + 2, 0)
    n = int(count.max())
    p = np.arange(n)[None, :]
    u = (j_top[:, None] - (p - 1)) * du
    u = np.where(p == 0, ua[:, None], u)
    last = (count - 1)[:, None]
    u = np.where(p == last, ub[:, None], u)
    valid = p < count[:, None]
    u = np.where(valid, u, ub[:, None])
    return u, valid


def _island_profile(island, s, u, valid, h: float):
    """g = (H − h)·u on the island's samples, −inf where not valid (float32).

    Only the valid samples are evaluated (:func:`_island_profile_flat`).
    """
    g = np.full(u.shape, -np.inf, dtype=_F32)
    rows = np.nonzero(valid)[0]
    g[valid] = _island_profile_flat(island, s[rows], u[valid], h)
    return g


def _island_profile_flat(island, s_rows, uu, h: float):
    """g = (H − h)·u at samples ``uu`` (1/y) on scan lines ``s_rows`` (same shape), float32."""
    y = (1.0 / uu).astype(_F32)
    x = (s_rows * y).astype(_F32)
    hgt = island.surface(x, y, with_gradient=False)[0]
    return (hgt.astype(_F32) - _F32(h)) * uu.astype(_F32)


def probe_refinement(island, s, samp: Sampling, d: float, most: int | None = None) -> int | float | None:
    """Refinement m0 of the sea's lattice that puts ISLAND_PROBE_SAMPLES across the widest chord.

    None when no scan line meets the island's bounding ellipses. With
    ``most`` (the scan line's budget of samples), a chord wider than ``most``
    of the sea's samples is probed on a coarser lattice: m0 = 1/2ᵖ, the
    sea's step times the smallest power of two that leaves at most ``most``
    probe samples on every scan line (a window a sliver tall has a sea step
    so fine that the islands' chords would span millions of its samples).
    A power of two, so that du/m0 is the exact multiple of du, the same in
    both kernels; the paper's lattice (``refine_islands=False``) is coarsened
    the same way (``min(m0, 1)``).
    """
    y0, y1 = island.chord(s, d)
    ok = np.isfinite(y0) & (y1 > samp.y_clip)
    if not ok.any():
        return None
    width = float(((1.0 / np.maximum(y0[ok], samp.y_clip) - 1.0 / y1[ok]) / samp.du).max())  # in sea samples
    if most is not None and width + 3 > most:         # chord ends, the lattice between and a rounding to spare
        return 0.5 ** math.ceil(math.log2(width / max(most - 3, 1)))
    m0 = int(math.ceil(ISLAND_PROBE_SAMPLES / max(width, 1e-12)))
    return max(1, min(m0, ISLAND_MAX_REFINEMENT))


def _island_samples(island, s, samp: Sampling, d: float, h: float, m0: int, zeta0: float, dzeta: float,
                    K: int, sigma: float, budget: int):
    """Adaptive samples of one island on scan lines s, about σ pixels apart in projection.

    A probe on the sea's lattice refined by m0 gives each probe interval's
    projected step |Δr| in pixels (clipped to the picture, so that what
    projects above or below it costs nothing), plus the change of the step
    from its neighbours (a curvature allowance); each interval is then cut
    into ⌈(|Δr| + |Δ²r|)/σ⌉ equal parts in u. Columns are scaled down to at
    most ``budget`` samples.

    Returns
    -------
    (u, valid) : (ndarray (C, T) float64 near to far, ndarray (C, T) bool), or None.
        Row c holds its samples first, then zeros (``valid`` False).
    """
    flat = _island_samples_flat(island, s, samp, d, h, m0, zeta0, dzeta, K, sigma, budget)
    if flat is None:
        return None
    uf, count = flat
    T = int(count.max()) if count.size else 0
    valid = np.arange(T)[None, :] < count[:, None]
    u = np.zeros(valid.shape)
    u[valid] = uf
    return u, valid


def _island_samples_flat(island, s, samp: Sampling, d: float, h: float, m0: int, zeta0: float, dzeta: float,
                         K: int, sigma: float, budget: int):
    """:func:`_island_samples` as one flat array: (u (S,) float64, count (C,) int64), or None.

    The samples of scan line c are ``u[start[c] : start[c] + count[c]]``,
    near to far, with start the exclusive cumulative sum of ``count``.
    """
    lat = _island_lattice(island, s, samp, d, m0)
    if lat is None:
        return None
    up, vp = lat
    C, P = up.shape
    if P < 2:
        return up[vp], vp.sum(axis=1).astype(np.int64)
    gp = _island_profile(island, s, up, vp, h).astype(np.float64)
    with np.errstate(invalid="ignore"):
        r = np.clip((gp - zeta0) / dzeta, -1.0, K + 1.0)
    pair = vp[:, 1:] & vp[:, :-1]
    dr = np.where(pair, np.diff(r, axis=1), 0.0)
    # the change of the step from its neighbours; beyond a scan line's last interval the step is 0 (the
    # same for every row, however long the strip's longest row is)
    d2 = np.abs(np.diff(dr, axis=1, append=0.0))
    d2[:, 1:] = np.maximum(d2[:, 1:], d2[:, :-1].copy())
    n = np.where(pair, np.maximum(1, np.ceil((np.abs(dr) + d2) / sigma)), 0).astype(np.int64)
    # samples only where they can be seen: an interval that stays, with its allowance and a pixel to
    # spare, below the profile's running maximum nearer to the eye is hidden behind the island itself
    reach = np.maximum(r[:, 1:], r[:, :-1]) + np.abs(dr) + d2 + 1.0
    nearer_top = np.maximum.accumulate(np.where(vp, r, -np.inf), axis=1)[:, :-1]
    n[pair & (reach < nearer_top)] = 1
    total = n.sum(axis=1)
    over = total > budget
    if over.any():
        scale = np.where(over, budget / np.maximum(total, 1), 1.0)
        n = np.where(pair, np.maximum(1, np.floor(n * scale[:, None])), 0).astype(np.int64)
        total = n.sum(axis=1)
    has = vp.any(axis=1)
    count = np.where(has, total + 1, 0).astype(np.int64)  # + the far end of the chord
    last_valid = vp.sum(axis=1) - 1
    return expand_intervals(up, n, count, last_valid), count


@twin("sunset.vector.island_samples_numba")
def expand_intervals(up, n, count, last_valid):
    """Cut each probe interval j of scan line c into ``n[c, j]`` equal parts in u.

    Parameters
    ----------
    up : ndarray (C, P) float64
        The probe samples, near to far.
    n : ndarray (C, P − 1) int64
        Parts of each interval (0 where the interval is not valid).
    count : ndarray (C,) int64
        Samples of each scan line: its parts plus the far end of the chord (0: none).
    last_valid : ndarray (C,) int64
        The index of each scan line's last valid probe sample.

    Returns
    -------
    ndarray (count.sum(),) float64
        The samples in row-major order (row c, interval j, part q), each row's
        far end of the chord after its intervals.
    """
    P = up.shape[1]
    has = count > 0
    total = n.sum(axis=1)
    flat_n = n.ravel()
    pair_id = np.repeat(np.arange(flat_n.size), flat_n)
    start = np.cumsum(flat_n) - flat_n
    q = np.arange(pair_id.size) - start[pair_id]
    c, j = np.divmod(pair_id, P - 1)
    ua, ub = up[c, j], up[c, j + 1]
    u = ua + (ub - ua) * (q / n[c, j])
    rows = np.nonzero(has)[0]
    ends = np.cumsum(total)[rows]
    return np.insert(u, ends, up[rows, last_valid[rows]])


@twin("sunset.vector.island_samples_numba")
def island_scan(island, s, samp: Sampling, d: float, h: float, m0: int, zeta0: float, dzeta: float, K: int,
                sigma: float, budget: int, refine: bool, best_u, best_surf, code: int) -> int:
    """Sample one island on C scan lines, scan-convert it and merge it into their depth buffers.

    Parameters
    ----------
    island : Island
    s : ndarray (C,)
        The scan lines.
    samp : Sampling
        The sea's lattice; ``d`` the sea's largest elevation, ``h`` the eye's height.
    m0 : int or float
        The island's probe refinement (:func:`probe_refinement`; 1/2ᵖ where the lattice is coarsened).
    zeta0, dzeta : float
        The bottom pixel centre's ζ and the pixel pitch; ``K`` pixels on a scan line.
    sigma : float
        Projected sample spacing, pixels; ``budget`` the most samples on a scan line.
    refine : bool
        Refine the lattice where the island is steep (False: the sea's samples, as the paper did).
    best_u, best_surf : ndarray (C, K)
        The depth buffer, updated in place where the island is nearer: code ``code``.

    Returns
    -------
    int
        The island's samples on these scan lines.
    """
    if refine:
        lat = _island_samples(island, s, samp, d, h, m0, zeta0, dzeta, K, sigma, budget)
    else:
        lat = _island_lattice(island, s, samp, d, min(m0, 1))
    if lat is None:
        return 0
    u, valid = lat
    g = _island_profile(island, s, u, valid, h)
    u_hit = scan_convert(u, g, zeta0, dzeta, K)
    nearer = u_hit > best_u
    best_u[nearer] = u_hit[nearer]
    best_surf[nearer] = code
    return int(valid.sum())


@twin("sunset.vector.island_samples_numba")
def islands_scan(islands, m0s, s_all, c0: int, c1: int, samp: Sampling, d: float, h: float, zeta0: float,
                 dzeta: float, K: int, sigma: float, budget: int, refine: bool, best_u, best_surf) -> int:
    """Every island on scan lines ``s_all[c0:c1]`` (:func:`island_scan`, in island order), into their depth buffers.

    ``m0s`` holds each island's probe refinement (None: out of view);
    ``best_u``, ``best_surf`` (c1 − c0, K) are the strip's rows of the
    depth buffer, island k winning with code k (1-based) where strictly
    nearer. Returns the islands' samples. The compiled twin does a whole
    strip in one call without the GIL, every scan line on its own: the same
    numbers for any cut into strips.
    """
    n = 0
    for k, (island, m0) in enumerate(zip(islands, m0s), start=1):
        if m0 is not None:
            n += island_scan(island, s_all[c0:c1], samp, d, h, m0, zeta0, dzeta, K, sigma, budget, refine, best_u,
                             best_surf, k)
    return n
