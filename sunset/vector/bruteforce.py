"""An independent brute-force ray caster for the direct rays (small pictures only).

It shares nothing with :mod:`sunset.vector.heightfield` but the surfaces themselves
(:meth:`sunset.model.waves.Sea.elevation` and :meth:`sunset.model.islands.Island.surface`):
every ray through a pixel centre, x = s·y, z = ζ·y, is marched in small steps
of y, and the first step where it passes under a surface is refined by
bisection to float64 precision. The nearest of the sea and the islands wins.

Brackets come from bounds, not from the scan line:

* the sea lies between −h − d and −h + d, so a ray with ζ < 0 is above the
  sea for y < (h − d)/|ζ| and below it for y > (h + d)/|ζ|: its first
  crossing is in between;
* island k lies below the lowest sea outside the circle of radius
  max(√((h_c + d_k + d)/λ_c), √((h_b + d)/λ_b)) about its apex, λ the
  smaller eigenvalue of each paraboloid's quadratic form (P <= height − λr²):
  a ray can only meet it on its chord through that circle.

The steps are a small fraction of the shortest wavelength in each surface
(and of the island's size), so a crossing is only missed where a ray grazes a
crest or a ridge within one step: the error this caster leaves is far below
the one it is built to measure.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import PART_NONE, SEA, SKY
from ..errors import SunsetError, require_positive, require_time
from .frame import Frame
from ..model.waves import unit_normal

#: Steps per shortest wavelength of the sea (divided again by the highest Stokes order).
SEA_STEPS_PER_WAVELENGTH = 16
#: Steps per shortest cosine wavelength of an island.
ISLAND_STEPS_PER_WAVELENGTH = 64
#: Steps across an island's bounding circle (at least).
ISLAND_STEPS_PER_DIAMETER = 4000
#: Bisection iterations (float64: 60 halvings exhaust any bracket).
BISECTIONS = 60
#: Samples evaluated per block while marching (memory bound).
BLOCK = 1 << 18


def _march(fun, y_lo, y_hi, step):
    """First y in [y_lo, y_hi] (per ray) where fun(rays, y) >= 0, bracketed.

    Parameters
    ----------
    fun : callable(idx, y) -> ndarray
        The surface's height minus the ray's, for the rays ``idx`` (1-D int
        array) at distances ``y`` (shape (len(idx), n)): >= 0 once the ray
        is under the surface.
    y_lo, y_hi : ndarray (n_rays,)
        The bracket along y for each ray.
    step : float
        Marching step in y, metres.

    Returns
    -------
    a, b : ndarray
        For each ray, fun < 0 at a and >= 0 at b (a == b when the ray starts
        under the surface); NaN where no crossing is found in [y_lo, y_hi].
    """
    n_rays = y_lo.size
    a = np.full(n_rays, np.nan)
    b = np.full(n_rays, np.nan)
    if n_rays == 0:
        return a, b
    start = y_lo.copy()
    prev = fun(np.arange(n_rays), start[:, None])[:, 0]
    under = prev >= 0
    a[under] = b[under] = start[under]
    todo = np.nonzero(~under)[0]
    pos = start.copy()
    while todo.size:
        per = max(1, BLOCK // todo.size)
        j = np.arange(1, per + 1)
        ys = pos[todo][:, None] + step * j[None, :]
        ys = np.minimum(ys, y_hi[todo][:, None])
        f = fun(todo, ys)
        cross = f >= 0
        any_cross = cross.any(axis=1)
        first = np.argmax(cross, axis=1)
        done = todo[any_cross]
        fj = first[any_cross]
        b[done] = ys[any_cross, fj]
        a[done] = np.where(fj > 0, ys[any_cross, np.maximum(fj - 1, 0)], pos[done])
        last = ys[:, -1]
        pos[todo] = last
        rest = ~any_cross & (last < y_hi[todo])
        todo = todo[rest]
    return a, b


def _bisect(fun, a, b):
    """Refine brackets fun(a) < 0 <= fun(b) by bisection (vectorized over rays)."""
    ok = np.isfinite(a) & (b > a)
    idx = np.nonzero(ok)[0]
    lo, hi = a[idx].copy(), b[idx].copy()
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        f = fun(idx, mid[:, None])[:, 0]
        below = f >= 0
        hi = np.where(below, mid, hi)
        lo = np.where(below, lo, mid)
    out = b.copy()
    out[idx] = hi
    return out


def sea_hits(sea, h: float, s, zeta, t: float = 0.0, step: float | None = None):
    """Distance y at which each ray (s, 1, ζ) first meets the sea, metres (inf: none).

    Parameters
    ----------
    sea : Sea
    h : float
        Eye height, metres.
    s, zeta : ndarray (n,)
        The rays' slopes x/y and z/y.
    t : float
        Time, seconds.
    step : float, optional
        Marching step in y; by default the shortest wavelength over
        SEA_STEPS_PER_WAVELENGTH times the highest Stokes order (a wind sea:
        its tile's grid spacing over SEA_STEPS_PER_WAVELENGTH).
    """
    s = np.asarray(s, dtype=float)
    zeta = np.asarray(zeta, dtype=float)
    d = sea.max_elevation
    out = np.full(s.size, np.inf)
    down = zeta < 0
    if not down.any():
        return out
    if d == 0:
        out[down] = h / -zeta[down]
        return out
    if step is None and sea.wind is not None:     # a wind sea: the tile's grid spacing, its bilinear cells' side
        step = sea.wind.tile.spacing / SEA_STEPS_PER_WAVELENGTH
    elif step is None:
        lam = min(tr.wavelength / tr.stokes_order for tr in sea.trains if tr.amplitude > 0)
        step = lam / SEA_STEPS_PER_WAVELENGTH
    rs, rz = s[down], zeta[down]
    y_lo = np.maximum(h - d, 1e-6 * h) / -rz
    y_hi = (h + d) / -rz

    def fun(idx, y):
        return sea.elevation(rs[idx][:, None] * y, y, t) - h - rz[idx][:, None] * y

    a, b = _march(fun, y_lo, y_hi, step)
    out[down] = _bisect(fun, a, b)
    return out


def island_circle(island, d: float) -> float:
    """Radius of a circle about the apex outside which the island is below −d, metres."""
    dk = island.max_perturbation
    rc = math.sqrt(max(island.cliff.height + dk + d, 0.0) / island.cliff.min_curvature)
    rb = math.sqrt(max(island.beach.height + d, 0.0) / island.beach.min_curvature)
    return max(rc, rb)


def island_hits(island, h: float, s, zeta, d: float, step: float | None = None):
    """Distance y at which each ray (s, 1, ζ) first meets the island, metres (inf: none).

    Rays that are already below the lowest sea (−h − d) where they enter the
    island's circle, or above the island's highest point throughout it, are
    not marched: the first meets the sea before, the second nothing.
    """
    s = np.asarray(s, dtype=float)
    zeta = np.asarray(zeta, dtype=float)
    out = np.full(s.size, np.inf)
    R = island_circle(island, d)
    X, Y = island.x, island.y
    # the ray's chord through the circle (s y − X)² + (y − Y)² = R²
    A = 1.0 + s * s
    B = s * X + Y
    C = X * X + Y * Y - R * R
    disc = B * B - A * C
    ok = disc > 0
    root = np.sqrt(np.where(ok, disc, 0.0))
    y_a = np.maximum((B - root) / A, 1e-6 * h)
    y_b = (B + root) / A
    top = max(island.cliff.height + island.max_perturbation, island.beach.height) - h
    ray_low = np.minimum(zeta * y_a, zeta * y_b)   # the ray's lowest z on the chord
    ray_entry = zeta * y_a
    ok &= y_b > y_a
    ok &= ray_low < top
    ok &= ray_entry > -(h + d)
    if not ok.any():
        return out
    if step is None:
        waves = [2 * math.pi / math.hypot(c.l, c.m) for c in island.cosines if c.amplitude > 0 and (c.l or c.m)]
        step = min([2 * R / ISLAND_STEPS_PER_DIAMETER] + [w / ISLAND_STEPS_PER_WAVELENGTH for w in waves])
    rs, rz = s[ok], zeta[ok]

    def fun(idx, y):
        return island.surface(rs[idx][:, None] * y, y, with_gradient=False)[0] - h - rz[idx][:, None] * y

    a, b = _march(fun, y_a[ok], y_b[ok], step)
    out[ok] = _bisect(fun, a, b)
    return out


def trace_direct_bruteforce(scene, t: float = 0.0, *, sea_step: float | None = None,
                            island_step: float | None = None) -> Frame:
    """The direct-ray frame of ``scene`` by marching every ray (slow: small pictures).

    Parameters
    ----------
    scene : Scene
    t : float
        Time, seconds.
    sea_step, island_step : float, optional
        Marching steps in y, metres (see :func:`sea_hits`, :func:`island_hits`).

    Returns
    -------
    Frame
        The same direct fields as :func:`sunset.pipeline.frame.trace_direct`;
        the hit point is exactly on the surface (to the bisection's float64
        precision).
    """
    require_time("t", t)
    if sea_step is not None:
        require_positive("sea_step", sea_step)
    if island_step is not None:
        require_positive("island_step", island_step)
    cam = scene.camera
    H, W, h = cam.height, cam.width, cam.eye_height
    s = np.broadcast_to(cam.s_centres()[None, :], (H, W)).ravel()
    zeta = np.broadcast_to(cam.zy_centres()[:, None], (H, W)).ravel()
    d = scene.sea.max_elevation
    best = sea_hits(scene.sea, h, s, zeta, t, sea_step)
    surf = np.where(np.isfinite(best), SEA, SKY).astype(np.int8)
    for k, island in enumerate(scene.islands, start=1):
        yk = island_hits(island, h, s, zeta, d, island_step)
        nearer = yk < best
        best = np.where(nearer, yk, best)
        surf[nearer] = k
    hit = np.isfinite(best)
    y = np.where(hit, best, np.nan)
    point = np.stack([s * y, y, zeta * y], axis=-1)
    distance = np.where(hit, y * np.sqrt(1.0 + s * s + zeta * zeta), np.inf)
    normal = np.full((H * W, 3), np.nan)
    part = np.full(H * W, PART_NONE, dtype=np.int8)
    sea = surf == SEA
    if sea.any():
        normal[sea] = scene.sea.normal(point[sea, 0], point[sea, 1], t)
    for k, island in enumerate(scene.islands, start=1):
        sel = surf == k
        if sel.any():
            _, part[sel], gx, gy = island.surface(point[sel, 0], point[sel, 1])
            normal[sel] = unit_normal(gx, gy)
    d = cam.directions()
    return Frame(t=float(t), reflections=0, direction=d.astype(np.float32), surface=surf.reshape(H, W),
                 part=part.reshape(H, W), distance=distance.reshape(H, W).astype(np.float32),
                 point=point.reshape(H, W, 3).astype(np.float32), normal=normal.reshape(H, W, 3).astype(np.float32))


def compare(frame, reference) -> dict:
    """How a frame's direct rays agree with a reference frame (e.g. this caster's).

    Parameters
    ----------
    frame, reference : Frame
        Of the same picture.

    Returns
    -------
    dict
        ``agree``: share of pixels whose surface class (sky, sea, island k)
        is the same; ``agree_part``: share whose class and island part agree;
        and for the pixels where both hit the same surface, the relative error
        |d/d_ref − 1| of the hit distance: ``sea_median``, ``sea_p90``,
        ``sea_p99``, ``island_median``, ``island_p90``, ``island_max`` (NaN
        where there are no such pixels), with the pixel counts ``n_sea`` and
        ``n_island``; and the angle between the two normals, degrees:
        ``sea_normal_median``, ``sea_normal_p90``, ``island_normal_median``,
        ``island_normal_p90``.
    """
    if frame.shape != reference.shape:
        raise SunsetError(f"frame must have the reference's shape {reference.shape}, got {frame.shape}")
    same = frame.surface == reference.surface
    out = {"agree": float(np.mean(same)),
           "agree_part": float(np.mean(same & (frame.part == reference.part)))}
    hit = same & (reference.surface != SKY)
    rel = np.full(frame.shape, np.nan)
    rel[hit] = np.abs(frame.distance[hit].astype(float) / reference.distance[hit].astype(float) - 1.0)
    cosang = np.clip(np.sum(frame.normal.astype(float) * reference.normal.astype(float), axis=-1), -1.0, 1.0)
    angle = np.degrees(np.arccos(np.where(hit, cosang, 1.0)))
    for name, mask, stats in (("sea", same & (reference.surface == SEA), (50, 90, 99)),
                              ("island", same & (reference.surface > 0), (50, 90, 100))):
        vals = rel[mask]
        out[f"n_{name}"] = int(vals.size)
        for q in stats:
            key = {50: "median", 100: "max"}.get(q, f"p{q}")
            out[f"{name}_{key}"] = float(np.percentile(vals, q)) if vals.size else float("nan")
        for q in (50, 90):
            key = "median" if q == 50 else f"p{q}"
            out[f"{name}_normal_{key}"] = float(np.percentile(angle[mask], q)) if vals.size else float("nan")
    return out


def cloud_hits(clouds, h: float, s, zeta, step: float | None = None) -> np.ndarray:
    """Distance y of each ray's first entry into the cloud layer, NaN where it misses (brute force).

    A ray x = s·y, z = h + ζ·y is inside the layer where
    min(z − (Z − B), (Z + T) − z) >= 0 over the layer's domain (T + B > 0).
    It can only be inside between the heights Z − max B and Z + max T, which
    bracket y; it is marched in steps of ``step`` metres (default: a
    thousandth of the smallest cell's smaller semi-axis) and refined by
    bisection.
    """
    s = np.asarray(s, dtype=float).ravel()
    zeta = np.asarray(zeta, dtype=float).ravel()
    out = np.full(s.size, np.nan)
    up = zeta > 0
    if not up.any():
        return out
    if step is None:
        step = min(min(c.a, c.b) for c in clouds.cells) / 1000.0
    z_lo, z_hi = clouds.level - clouds.max_bottom, clouds.level + clouds.max_top
    reach = max(math.hypot(c.x, c.y) + max(c.a, c.b) for c in clouds.cells)
    su, zu = s[up], zeta[up]
    y_lo = (z_lo - h) / zu
    y_hi = np.minimum((z_hi - h) / zu, reach)

    def fun(idx, y):
        x, z = su[idx][:, None] * y, h + zu[idx][:, None] * y
        T, B = clouds.thickness(x, y)
        inside = np.minimum(z - (clouds.level - B), clouds.level + T - z)
        return np.where(T + B > 0, inside, -1.0)

    ok = y_lo < y_hi
    y_lo = np.where(ok, y_lo, 0.0)
    y_hi = np.where(ok, y_hi, 0.0)
    a, b = _march(fun, y_lo, y_hi, step)
    a = np.where(ok, a, np.nan)
    out[np.nonzero(up)[0]] = _bisect(fun, a, b)
    out[np.nonzero(up)[0][~ok]] = np.nan
    return out


def trace_clouds_bruteforce(scene, step: float | None = None) -> np.ndarray:
    """1/y of the first cloud hit through every pixel centre, (H, W) rows from the top, 0 where none."""
    cam = scene.camera
    s = cam.s_centres()[None, :]
    zeta = cam.zy_centres()[:, None]
    s, zeta = np.broadcast_arrays(s, zeta)
    y = cloud_hits(scene.clouds, cam.eye_height, s, zeta, step).reshape(s.shape)
    return np.where(np.isfinite(y), 1.0 / np.where(np.isfinite(y), y, 1.0), 0.0)
