"""Triangles of light onto a texture, with the exact area each texel covers.

A beam of the wavefront tracer (:mod:`sunset.light.caustics`) lands on its
receiver as a triangle in the texture's coordinates, carrying a flux that it
spreads evenly over its area. :func:`rasterise` adds each triangle's flux to
the texels in proportion to the area of the triangle that falls in each: the
triangle is clipped against the texel's square (Sutherland and Hodgman's
polygon clipping, one edge of the square after the other) and the clipped
polygon's area is the shoelace sum of its fan, taken relative to its first
vertex so that a tiny triangle far from the origin keeps its digits.

The texture is u across (periodic: column i is u in [i, i + 1) modulo n_u,
round the post or the island) and v up (texels [j, j + 1) for j in 0 .. n_v − 1);
coordinates are in texels. A triangle that reaches past v = 0 or v = n_v
(over the post's top, out of a shore's band) keeps only the share of its flux
that falls on the texture, ``kept`` = covered area / area; the caller books
the rest. A triangle wholly inside the texture's rows keeps all of its flux
(its texels' shares are normalised by their sum, so that the flux is
conserved to round-off however thin it is); one whose area is zero (three
points on a line, the fold of a caustic exactly; :data:`FLAT`) puts its flux
in the texel of its centroid.
"""

from __future__ import annotations

import numpy as np

from ..kernels import twin

__all__ = ["rasterise", "triangle_area", "clip_area"]

#: Vertices a triangle clipped by a square can have.
MAX_VERTICES = 8
#: A triangle whose area is under FLAT × its extent² is a segment or a point (its area is round-off): it puts
#: its flux in the texel of its centroid.
FLAT = 1e-12
#: (Triangle, texel) pairs the NumPy reference clips at once: its memory stays bounded (some 200 bytes a pair).
PAIRS = 1 << 17


def triangle_area(u, v) -> np.ndarray:
    """Areas (T,) of triangles with vertices u, v (T, 3), texels², from the edges out of vertex 0."""
    return 0.5 * np.abs((u[:, 1] - u[:, 0]) * (v[:, 2] - v[:, 0]) - (u[:, 2] - u[:, 0]) * (v[:, 1] - v[:, 0]))


def _clip_half(px, py, count, axis: int, bound: float, below: bool):
    """Clip polygons (P, M) with ``count`` vertices to p[axis] <= bound (``below``) or >= bound."""
    n, m = px.shape
    k = np.arange(m)[None, :]
    nxt = (k + 1) % np.maximum(count, 1)[:, None]
    coord = px if axis == 0 else py
    side = (bound - coord) if below else (coord - bound)
    valid = k < count[:, None]
    s_next = np.take_along_axis(side, nxt, axis=1)
    inside = valid & (side >= 0)
    cross = valid & ((side >= 0) != (s_next >= 0))
    emit = inside.astype(np.int64) + cross
    start = np.cumsum(emit, axis=1) - emit
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(cross, side / (side - s_next), 0.0)
    xn, yn = np.take_along_axis(px, nxt, axis=1), np.take_along_axis(py, nxt, axis=1)
    ox, oy = np.zeros((n, m + 1)), np.zeros((n, m + 1))
    rows = np.broadcast_to(np.arange(n)[:, None], (n, m))
    ox[rows[inside], start[inside]] = px[inside]
    oy[rows[inside], start[inside]] = py[inside]
    at = start + inside
    ix = px + f * (xn - px)
    iy = py + f * (yn - py)
    if axis == 0:
        ix = np.where(cross, bound, ix)
    else:
        iy = np.where(cross, bound, iy)
    ox[rows[cross], at[cross]] = ix[cross]
    oy[rows[cross], at[cross]] = iy[cross]
    return ox[:, :m], oy[:, :m], emit.sum(axis=1)


def clip_area(u, v, i, j) -> np.ndarray:
    """Areas (P,) of triangles u, v (P, 3) inside the unit squares
    [i, i + 1] × [j, j + 1] (P,)."""
    m = MAX_VERTICES
    px, py = np.zeros((len(u), m)), np.zeros((len(u), m))
    px[:, :3] = u - i[:, None]                  # in the texel's own coordinates
    py[:, :3] = v - j[:, None]
    count = np.full(len(u), 3)
    for axis, bound, below in ((0, 0.0, False), (0, 1.0, True),
                               (1, 0.0, False), (1, 1.0, True)):
        px, py, count = _clip_half(px, py, count, axis, bound, below)
    # the shoelace sum of the fan from vertex 0
    ex, ey = px - px[:, :1], py - py[:, :1]
    fan = ex[:, 1:-1] * ey[:, 2:] - ex[:, 2:] * ey[:, 1:-1]
    k = np.arange(1, m - 1)[None, :]
    fan = np.where(k + 1 < count[:, None], fan, 0.0)
    return 0.5 * np.abs(np.sum(fan, axis=1))


@twin("sunset.light.raster_numba")
def rasterise(u, v, flux, n_u: int, n_v: int) -> tuple[np.ndarray, np.ndarray]:
    """Spread each triangle's flux (T, C) evenly over its area: the texture (n_v, n_u, C) and ``kept`` (T,).

    ``u``, ``v`` (T, 3): the vertices in texels; u is unwrapped by the caller (a triangle spans less than the
    texture round), v may reach past the rows.
    """
    T, C = flux.shape
    out = np.zeros((n_v * n_u, C))
    kept = np.zeros(T)
    if T == 0:
        return out.reshape(n_v, n_u, C), kept
    area = triangle_area(u, v)
    i0 = np.floor(u.min(axis=1)).astype(np.int64)
    i1 = np.floor(u.max(axis=1)).astype(np.int64)
    j0 = np.maximum(np.floor(v.min(axis=1)), 0).astype(np.int64)
    j1 = np.minimum(np.floor(v.max(axis=1)), n_v - 1).astype(np.int64)
    inside = (v.min(axis=1) >= 0) & (v.max(axis=1) <= n_v)
    # the zero-area ones: the centroid's texel, if it lies on the texture
    # zero area, or an area below the round-off of its corners (three points on a line)
    extent = np.maximum(np.ptp(u, axis=1), np.ptp(v, axis=1))
    flat = ~(area > FLAT * extent * extent)
    cu, cv = u.mean(axis=1), v.mean(axis=1)
    on = flat & (cv >= 0) & (cv < n_v)
    kept[on] = 1.0
    cells = np.floor(cv[on]).astype(np.int64) * n_u + np.mod(np.floor(cu[on]).astype(np.int64), n_u)
    # every (triangle, texel) pair of the others' bounding boxes, at most about PAIRS of them at a time (a
    # beam from far out at sea can land over hundreds of texels of a cliff)
    live = ~flat & (j1 >= j0)
    ni, nj = i1 - i0 + 1, j1 - j0 + 1
    counts = np.where(live, ni * nj, 0)
    total = np.zeros(T)
    ends = np.cumsum(counts)
    start = 0
    while start < T:
        stop = max(int(np.searchsorted(ends, (ends[start - 1] if start else 0) + PAIRS, side="right")), start + 1)
        group = np.arange(start, min(stop, T))
        start = int(group[-1]) + 1
        c = counts[group]
        if not c.sum():
            continue
        tri = np.repeat(group, c)
        rank = np.arange(tri.size) - np.repeat(np.cumsum(c) - c, c)
        ti = i0[tri] + rank // nj[tri]
        tj = j0[tri] + rank % nj[tri]
        cover = clip_area(u[tri], v[tri], ti, tj)
        local = tri - group[0]
        total[group] = np.bincount(local, weights=cover, minlength=group.size)
        norm = np.where(inside[group], total[group], area[group])[local]
        share = cover / np.where(norm > 0, norm, 1.0)
        where = tj * n_u + np.mod(ti, n_u)
        for ch in range(C):
            out[:, ch] += np.bincount(where, weights=share * flux[tri, ch], minlength=n_v * n_u)
    kept_live = np.where(inside, 1.0, np.minimum(total / np.where(area > 0, area, 1.0), 1.0))
    kept[live] = kept_live[live]
    for ch in range(C):
        out[:, ch] += np.bincount(cells, weights=flux[on, ch], minlength=n_v * n_u)
    # a live triangle whose clipped areas all came out 0 (thinner than round-off): its centroid, as a flat one
    lost = live & (total <= 0) & inside
    if np.any(lost):
        cells = np.floor(cv[lost]).astype(np.int64) * n_u + np.mod(np.floor(cu[lost]).astype(np.int64), n_u)
        for ch in range(C):
            out[:, ch] += np.bincount(cells, weights=flux[lost, ch], minlength=n_v * n_u)
    return out.reshape(n_v, n_u, C), kept
