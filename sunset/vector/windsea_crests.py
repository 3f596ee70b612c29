"""A wind sea's secondary reflections: the reflected ray marched over the tile's height field (issue 31).

Max's trains give the second bounce in closed form: the crest ahead is a
parabolic cylinder (:mod:`sunset.vector.crests`). A wind sea has no largest
train, but its surface is the tile's bilinear interpolant, bounded and
Lipschitz, so a reflected ray can be marched over it safely:

* **where the ray may meet the sea.** With B = ``tile.bound(t)`` the sea at
  t lies in [−h − B, −h + B] (eye coordinates, h the eye height): a ray that
  rises above −h + B leaves. Along the ray Q + sR (|R| = 1) the gap
  F(s) = (z(Q_xy + sR_xy) − h) − (Q_z + sR_z) is < 0 above the sea, and
  F′(s) <= S_x|R_x| + S_y|R_y| − R_z = ρ, where S_x, S_y are the largest
  differences of neighbouring grid heights over the spacing Δ: the bilinear
  interpolant's slopes are convex combinations of them. A ray with ρ <= 0
  never comes nearer the sea.
* **the safe step.** From a point where the ray is −F above the sea, no
  crossing lies within −F/ρ: the march steps by max(−F/ρ, δ), δ = Δ/:data:`MARCH_MIN_STEP`.
  A crossing that enters and leaves the sea within δ of a point the march
  visits while it steps by δ (a graze thinner than δ) is missed: the only
  approximation besides rounding.
* **the hit.** The first step that ends under the sea (F >= 0) brackets a
  crossing; :data:`MARCH_BISECTIONS` halvings refine it (to δ/2⁴⁰), and the
  ray is reflected again off the sea's normal there (the FFT gradient,
  :meth:`sunset.model.waves.Sea.normal`), as on the trains.

The march starts from the interpolated sea under the first bounce (the
scan line's hit is within its error of it), δ along the ray: a ray already
under the interpolated sea there (it leaves nearly tangent, and the normal
is the FFT gradient's, not the interpolant's slope) has no second bounce. It gives up
after :data:`MARCH_MAX_TILES` tile sides of travel (a ray nearly level with
the sea): such a ray leaves as after one bounce. A choppy tile (λ > 0) moves
the grid's points, and the slope bound above does not hold for it: its
second reflections are refused (:func:`check_second_reflections`).

:func:`wind_secondary_reflections` has a compiled twin
(:mod:`sunset.vector.windsea_crests_numba`), one ray at a time with the
same steps; the two agree within the tolerances the tests state, and both
against a fine fixed-step march (tests).

:func:`wind_sea_rays` is the wind sea's strip kernel of the reflected rays,
beside the trains' :func:`sunset.vector.reflect.trace_sea_rays` (the pipeline
picks the one of the sea's kind, :func:`sunset.pipeline.frame.sea_stage`),
with its own twin.
"""

from __future__ import annotations

import numpy as np

from ..errors import SunsetError
from ..kernels import twin
from .frame import Frame
from .pierce import reflect
from .reflect import sea_rays

__all__ = ["MARCH_MIN_STEP", "MARCH_BISECTIONS", "MARCH_MAX_TILES", "check_second_reflections", "slope_bounds",
           "march_constants", "wind_march", "bounce_off", "wind_secondary_reflections", "wind_sea_rays"]

#: δ = Δ / MARCH_MIN_STEP: the least step of the march, in grid spacings.
MARCH_MIN_STEP = 16
#: Halvings of a bracketed crossing.
MARCH_BISECTIONS = 40
#: The longest march, in tile sides: a ray still above the sea after it leaves.
MARCH_MAX_TILES = 8
#: What a choppy wind sea says when it is asked for two reflections.
CHOPPY_REFUSED = ("reflections: a choppy wind sea (sea.wind.choppiness > 0) has no second reflection (its "
                  "moved grid has no slope bound to march by): use --reflections 1 or choppiness = 0")


def check_second_reflections(sea, reflections: int) -> None:
    """Refuse two reflections on a choppy wind sea (one line, :data:`CHOPPY_REFUSED`)."""
    if reflections == 2 and sea.wind is not None and sea.wind.tile.choppiness > 0:
        raise SunsetError(CHOPPY_REFUSED)


def slope_bounds(z, spacing: float) -> tuple[float, float]:
    """(S_x, S_y): the largest |difference| of periodic neighbours of the grid ``z`` ([i, j] ↔ (y, x)) over Δ."""
    sx = float(np.max(np.abs(np.roll(z, -1, axis=1) - z))) / spacing
    sy = float(np.max(np.abs(np.roll(z, -1, axis=0) - z))) / spacing
    return sx, sy


def march_constants(tile, t: float, h: float) -> tuple[float, float, float, float, float]:
    """(top, S_x, S_y, δ, the longest march): what the march needs of the tile at t (eye coordinates)."""
    z = tile.fields(t)["z"]
    sx, sy = slope_bounds(z, tile.spacing)
    return float(np.max(np.abs(z))) - h, sx, sy, tile.spacing / MARCH_MIN_STEP, MARCH_MAX_TILES * tile.size


def wind_march(tile, t: float, h: float, q, r) -> np.ndarray:
    """Distance s along each ray Q + sR (N, 3; |R| = 1) to the wind sea's
    interpolated surface, +inf where none.

    The march of the module's docstring, whole arrays at a time: each step
    is taken by every ray still above the sea.
    """
    q = np.asarray(q, dtype=np.float64)
    r = np.asarray(r, dtype=np.float64)
    top, sx, sy, delta, longest = march_constants(tile, t, h)
    n = len(q)
    out = np.full(n, np.inf)
    if n == 0:
        return out

    def gap(idx, s):
        x = q[idx, 0] + s * r[idx, 0]
        y = q[idx, 1] + s * r[idx, 1]
        return (tile.heights(x, y, t) - h) - (q[idx, 2] + s * r[idx, 2])

    rate = sx * np.abs(r[:, 0]) + sy * np.abs(r[:, 1]) - r[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        end = np.where(r[:, 2] > 0.0, (top - q[:, 2]) / r[:, 2], np.inf)
    end = np.minimum(end, longest)
    idx = np.flatnonzero((rate > 0.0) & (end > delta))
    s = np.full(idx.size, delta)
    f = gap(idx, s)
    keep = f < 0.0
    idx, s, f = idx[keep], s[keep], f[keep]
    lo = np.zeros(0)
    hi = np.zeros(0)
    hit_idx = np.zeros(0, np.intp)
    while idx.size:
        step = np.maximum(-f / rate[idx], delta)
        nxt = np.minimum(s + step, end[idx])
        fn = gap(idx, nxt)
        under = fn >= 0.0
        hit_idx = np.concatenate([hit_idx, idx[under]])
        lo = np.concatenate([lo, s[under]])
        hi = np.concatenate([hi, nxt[under]])
        go = ~under & (nxt < end[idx])
        idx, s, f = idx[go], nxt[go], fn[go]
    for _ in range(MARCH_BISECTIONS):
        mid = 0.5 * (lo + hi)
        under = gap(hit_idx, mid) >= 0.0
        hi = np.where(under, mid, hi)
        lo = np.where(under, lo, mid)
    out[hit_idx] = hi
    return out


def bounce_off(sea, t: float, q, r, h: float, march):
    """The second bounces of rays (N, 3) leaving a wind sea at Q along R, with ``march`` (:func:`wind_march` or its twin).

    The march starts from the interpolated sea under Q (the scan line's hit
    lies within the scan line's error of it); the rays that meet the sea
    again are reflected off its normal there.
    """
    tile = sea.wind.tile
    q = np.array(q, dtype=np.float64)
    r = np.asarray(r, dtype=np.float64)
    q[:, 2] = tile.heights(q[:, 0], q[:, 1], t) - h
    dist = march(tile, t, h, q, r)
    idx = np.flatnonzero(np.isfinite(dist))
    point = q[idx] + dist[idx, None] * r[idx]
    normal = sea.normal(point[:, 0], point[:, 1], t)
    return idx, point, reflect(r[idx], normal)


@twin("sunset.vector.windsea_crests_numba")
def wind_secondary_reflections(sea, t: float, q, r, h: float):
    """Second reflections off a wind sea (:func:`bounce_off` with :func:`wind_march`), for rays (N, 3).

    The same result as :func:`sunset.vector.crests.secondary_reflections`:
    the indices of the rays that meet the sea again, the points where they
    meet it, and their second reflected directions (off the normal there).
    ``h`` is the eye height, metres.
    """
    return bounce_off(sea, t, q, r, h, wind_march)


@twin("sunset.vector.windsea_crests_numba")
def wind_sea_rays(scene, frame: Frame, reflections: int) -> Frame:
    """The reflected rays of a strip of rows (``frame``) on a wind sea: reflect, march, reflect again, pierce.

    :func:`sunset.vector.reflect.sea_rays` with the second reflections of
    :func:`bounce_off` and :func:`wind_march` (NumPy throughout); a choppy
    sea's two reflections are refused (:func:`check_second_reflections`).
    """
    check_second_reflections(scene.sea, reflections)
    h = scene.camera.eye_height
    return sea_rays(scene, frame, reflections, lambda q, r: bounce_off(scene.sea, frame.t, q, r, h, wind_march))
