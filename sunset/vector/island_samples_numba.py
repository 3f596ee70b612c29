"""Numba twins of :mod:`sunset.vector.island_samples`: the islands' samples kept compressed.

:func:`island_scan` samples an island on its scan lines as the reference
does but keeps the samples as one flat array (no padding to evaluate or scan),
cuts the probe intervals with :func:`expand_intervals`, and merges them into
the depth buffer with :func:`sunset.vector.heightfield_numba.scan_merge`.
Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import numpy as np

from ..kernels import jit as _jit
from .heightfield_numba import scan_merge
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
        lat = _island_lattice(island, s, samp, d, 1)
        if lat is None:
            return 0
        u, valid = lat
        counts = valid.sum(axis=1)
        g = _island_profile(island, s, u, valid, h)
    scan_merge(u, g, counts, zeta0, dzeta, K, best_u, best_surf, code)
    return int(counts.sum())
