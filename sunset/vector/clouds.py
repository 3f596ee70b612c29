"""Clouds in the vector stage: a double-valued height field along the vertical scan lines.

Direct rays
-----------
The eye is below the cloud base, at height h. On the vertical scan line x = s·y
a cloud cell (:mod:`sunset.model.clouds`) occupies, at each distance y inside
its ellipse, the segment Z − B ≤ z ≤ Z + T, which projects onto the picture
plane as the interval of ζ

    g_b(y) = (Z − h − B)/y  <  ζ  <  g_t(y) = (Z − h + T)/y.

The paper's height-field algorithm follows one function g(y) and its running
maximum; here there are two, and a pixel ζ_k is hit at the nearest y whose
interval holds it. The scan line is sampled from near to far on a lattice
even in u = 1/y, spaced so that the mean level's projection (Z − h)u steps σ
pixels, between the ends of the scan line's chord through the ellipse (where
the cloud closes to zero thickness). Sample i covers the pixels strictly
inside (g_b, g_t); a pixel first covered at sample i entered the cloud between
samples i − 1 and i, either through the bottom (g_b passed below it) or
through the top (g_t passed above it: the far side of a tall cloud), and the
crossing is interpolated linearly in u as in the sea's scan line.

"Nearest sample that covers the pixel" needs no loop over pixels: each
sample's covered pixels form a range; the ranges are expanded, in the order
(scan line, sample near to far), into (pixel, sample) pairs, and the first
pair of each pixel (:func:`numpy.unique` with ``return_index``) is its nearest
cover. A pixel is covered by about (T + B)/((Z − h)σ) samples, a few, so the
expansion is cheap. Cells are scanned one at a time and merged like the
islands: the nearest hit (largest u) wins, which is exact, since the union of
the cells is again one segment per (x, y).

Reflected rays and shadows
--------------------------
As the paper proposes, a reflected ray that ends in the sky is traced on until
it pierces the mean cloud level z = Z; if the piercing point lies over a
cloud, the ray sees the cloud's underside there, at depth B(x, y). The ray
starts at the pixel's first reflection point (a second reflection moves it by
metres, the cloud level is kilometres away). The same test is the cloud's
shadow on the sun's glitter: a reflected ray that shows the sun's disk points
at the sun, so where it meets a cloud the glitter is hidden behind it.
"""

from __future__ import annotations

import numpy as np

from ..constants import CLOUD, CLOUD_STRIP_PAIRS, SEA, SKY
from .frame import Frame

__all__ = ["cloud_scan", "cell_scan", "cell_lattice", "column_work", "cell_work", "cloud_strips", "add_clouds", "reflected_clouds"]


def cell_lattice(cell, level_h: float, s, zeta0: float, dzeta: float, n_pixels: int, sigma: float):
    """The samples of one cloud cell on the scan lines ``s`` (the arguments of :func:`cell_scan`).

    Returns (ok, u_near, u_far, du, j_hi, j_lo, count): which scan lines
    cross the cell, the ends of their chords in u = 1/y, the lattice step, the
    first and last inner lattice indices and the number of samples of each
    scan line (the chord's two ends and the lattice points between them, near
    to far: u_near, j_hi·du, ..., j_lo·du, u_far).
    """
    y0, y1 = cell.chord(s)
    du = sigma * dzeta / level_h
    zeta_top = zeta0 + (int(n_pixels) - 1) * dzeta
    low = level_h - cell.bottom * cell.swell                      # the lowest the cell's base can project from
    u_top = zeta_top / low + du if zeta_top > 0 else 0.0           # nearer than this, the base is above the picture
    ok = np.isfinite(y1)
    u_far = np.where(ok, 1.0 / np.where(ok, y1, 1.0), 0.0)
    with np.errstate(divide="ignore"):
        u_near = np.where(ok & (y0 > 0), 1.0 / np.where(y0 > 0, y0, 1.0), np.inf)
    u_near = np.minimum(u_near, u_top)
    ok &= u_near > u_far
    j_hi = np.where(ok, np.ceil(u_near / du) - 1, 0).astype(np.int64)
    j_lo = np.where(ok, np.floor(u_far / du) + 1, 1).astype(np.int64)
    inner = np.maximum(j_hi - j_lo + 1, 0)
    count = np.where(ok, inner + 2, 0)
    return ok, u_near, u_far, du, j_hi, j_lo, count


def column_work(cell, level_h: float, s, zeta0: float, dzeta: float, n_pixels: int, sigma: float):
    """Per scan line of ``s``: (samples, a bound on the (sample, pixel) pairs) of :func:`cell_scan`, not scanning.

    A sample at u covers the pixels strictly between its bottom's and its
    top's projections: at most (T + B)·u/Δζ + 1 of them, with T + B at most
    (top + bottom) times the billows' swell, and never more than the scan
    line's ``n_pixels``. Summed over a scan line's samples (the chord's ends
    and the lattice j·du between them) that is exact arithmetic, no profile
    is evaluated.
    """
    s = np.asarray(s, dtype=float)
    ok, u_near, u_far, du, j_hi, j_lo, count = cell_lattice(cell, level_h, s, zeta0, dzeta, n_pixels, sigma)
    inner = np.maximum(count - 2, 0).astype(np.float64)
    sum_u = np.where(ok, u_near + u_far + du * (j_lo + j_hi) * inner / 2.0, 0.0)
    linear = (cell.top + cell.bottom) * cell.swell * sum_u / dzeta + count
    pairs = np.ceil(np.where(ok, np.minimum(count * float(n_pixels), linear), 0.0))
    return count, pairs


def cell_work(cell, level_h: float, s, zeta0: float, dzeta: float, n_pixels: int, sigma: float) -> tuple[int, int]:
    """(samples, a bound on the pairs) of :func:`cell_scan` over all the scan lines ``s`` (:func:`column_work`)."""
    count, pairs = column_work(cell, level_h, s, zeta0, dzeta, n_pixels, sigma)
    return int(count.sum()), int(pairs.sum())


def cloud_strips(count, pairs) -> list[tuple[int, int]]:
    """Cut the scan lines into runs whose samples and bounded pairs stay within CLOUD_STRIP_PAIRS (one line at least)."""
    cost = np.cumsum(np.asarray(count, np.float64) + np.asarray(pairs, np.float64))
    out, c0 = [], 0
    while c0 < len(cost):
        base = cost[c0 - 1] if c0 else 0.0
        c1 = max(c0 + 1, int(np.searchsorted(cost, base + CLOUD_STRIP_PAIRS, side="right")))
        out.append((c0, c1))
        c0 = c1
    return out


def cell_scan(cell, level_h: float, s, zeta0: float, dzeta: float, n_pixels: int, sigma: float) -> np.ndarray:
    """The nearest hit on one cloud cell of every pixel of the scan lines ``s``: u = 1/y, 0 where it misses.

    Parameters
    ----------
    cell : CloudCell
    level_h : float
        Z − h, the mean level above the eye, metres (> 0).
    s : ndarray (C,)
        The scan lines.
    zeta0, dzeta : float
        The bottom pixel centre's ζ and the pixel pitch; ``n_pixels`` pixels on a scan line.
    sigma : float
        Projected spacing of the mean level's samples, pixels.

    Returns
    -------
    ndarray (C, n_pixels) float64, bottom up.
    """
    s = np.asarray(s, dtype=float)
    C, K = len(s), int(n_pixels)
    out = np.zeros((C, K))
    ok, u_near, u_far, du, j_hi, _, count = cell_lattice(cell, level_h, s, zeta0, dzeta, K, sigma)
    if not ok.any():
        return out
    col = np.repeat(np.arange(C), count)
    start = np.cumsum(count) - count
    pos = np.arange(col.size) - start[col]
    last = pos == count[col] - 1
    inner_u = (j_hi[col] - (pos - 1)) * du
    u = np.where(pos == 0, u_near[col], np.where(last, u_far[col], inner_u))
    y = 1.0 / u
    shape = cell.profile(s[col] * y, y)
    T_, B_ = cell.top * shape, cell.bottom * shape
    rb = ((level_h - B_) * u - zeta0) / dzeta  # the bottom's projection, pixels
    rt = ((level_h + T_) * u - zeta0) / dzeta  # the top's
    k_lo = np.maximum(np.floor(rb) + 1, 0).astype(np.int64)
    k_hi = np.minimum(np.ceil(rt) - 1, K - 1).astype(np.int64)
    n = np.where((T_ + B_ > 0) & (pos > 0), np.maximum(k_hi - k_lo + 1, 0), 0)
    if not n.any():
        return out
    # every (sample, pixel) it covers, in the order (scan line, sample near to far)
    smp = np.repeat(np.arange(u.size), n)
    k = k_lo[smp] + (np.arange(smp.size) - (np.cumsum(n) - n)[smp])
    key = col[smp] * K + k
    _, first = np.unique(key, return_index=True)
    i, k = smp[first], k[first]
    p = i - 1  # the previous sample: same scan line
    through_bottom = k <= rb[p]
    with np.errstate(divide="ignore", invalid="ignore"):
        f_bottom = (rb[p] - k) / (rb[p] - rb[i])
        f_top = (k - rt[p]) / (rt[i] - rt[p])
        f = np.where(through_bottom, f_bottom, f_top)
    f = np.clip(np.nan_to_num(f, nan=1.0), 0.0, 1.0)
    out.reshape(-1)[col[i] * K + k] = u[p] + f * (u[i] - u[p])
    return out


def cloud_scan(scene) -> np.ndarray:
    """The nearest cloud hit of every pixel: u = 1/y, (W, H) scan lines × pixels bottom up, 0 where none."""
    cam, clouds = scene.camera, scene.clouds
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    level_h = clouds.level - cam.eye_height
    s = cam.s_centres()
    best = np.zeros((cam.width, cam.height))
    for cell in clouds.cells:           # in strips of scan lines: the memory stays bounded (sunset.vector.budget)
        count, pairs = column_work(cell, level_h, s, zeta0, dz, cam.height, cam.sigma)
        for c0, c1 in cloud_strips(count, pairs):
            if count[c0:c1].any():
                np.maximum(best[c0:c1], cell_scan(cell, level_h, s[c0:c1], zeta0, dz, cam.height, cam.sigma),
                           out=best[c0:c1])
    return best


def add_clouds(scene, frame: Frame) -> Frame:
    """Put the clouds into a direct frame: a cloud nearer than what the direct ray met replaces it.

    Sets ``surface`` to :data:`~sunset.constants.CLOUD`, the point, the
    distance and ``cloud_depth`` (depth of the hit below the mean level,
    metres) of those pixels; their normal stays NaN (clouds are shaded by depth).
    """
    cam = scene.camera
    H, W = frame.shape
    u = np.ascontiguousarray(cloud_scan(scene)[:, ::-1].T)        # (H, W), row 0 at the top
    frame.cloud_depth = np.full((H, W), np.nan, np.float32)
    hit = u > 0
    if not hit.any():
        return frame
    y = np.where(hit, 1.0 / np.where(hit, u, 1.0), np.inf)
    nearer = hit & ((frame.surface == SKY) | (y < frame.point[..., 1]))
    if not nearer.any():
        return frame
    rows, cols = np.nonzero(nearer)
    s = cam.s_centres()[cols]
    z = cam.zy_centres()[rows]
    yy = y[rows, cols]
    frame.surface[rows, cols] = CLOUD
    frame.part[rows, cols] = 0
    frame.point[rows, cols] = np.stack([s * yy, yy, z * yy], axis=-1)
    frame.distance[rows, cols] = yy * np.sqrt(1.0 + s * s + z * z)
    frame.normal[rows, cols] = np.nan
    frame.cloud_depth[rows, cols] = scene.clouds.level - (cam.eye_height + z * yy)
    return frame


def reflected_clouds(scene, frame: Frame) -> Frame:
    """Trace the sea pixels' reflected rays that end in the sky on to the mean cloud level.

    Where the piercing point lies over a cloud, the ray ends there:
    ``final_surface`` becomes :data:`~sunset.constants.CLOUD` and
    ``cloud_depth`` the depth B(x, y) of the cloud's underside. Direct cloud
    pixels (:func:`add_clouds`) also end in the cloud.
    """
    clouds, h = scene.clouds, scene.camera.eye_height
    if frame.cloud_depth is None:
        frame.cloud_depth = np.full(frame.shape, np.nan, np.float32)
    direct = frame.surface == CLOUD
    frame.final_surface[direct] = CLOUD
    frame.final_part[direct] = 0
    up = (frame.surface == SEA) & (frame.final_surface == SKY) & (frame.ray[..., 2] > 0)
    if not up.any():
        return frame
    q = frame.point[up].astype(np.float64)
    r = frame.ray[up].astype(np.float64)
    t = (clouds.level - h - q[:, 2]) / r[:, 2]
    x, y = q[:, 0] + t * r[:, 0], q[:, 1] + t * r[:, 1]
    T, B = clouds.thickness(x, y)
    over = T + B > 0
    idx = tuple(a[over] for a in np.nonzero(up))
    frame.final_surface[idx] = CLOUD
    frame.final_normal[idx] = np.nan
    frame.cloud_depth[idx] = B[over]
    return frame
