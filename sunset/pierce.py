"""Reflected rays: piercing quadrics instead of height fields (paper eqs. 5–6).

The direct ray through every sea pixel has met the water at a point Q with
unit normal N (:mod:`sunset.heightfield`). It reflects (Blinn 1977):

    R = D − 2 (D·N) N.

Reflected rays do not start at the eye, so the height-field scan line does not
serve them. As the paper does, they are traced against simpler surfaces that
a ray can pierce in closed form: the islands without their cosine terms
(eq. 3) and, for secondary reflections, a parabolic cylinder fitted to the
crest of the largest wave ahead of the ray.

The quadratic (eqs. 5–6)
------------------------
A paraboloid P(x, y) = top − e u² − f u v − g v², u = x − X, v = y − Y, bounds
the solid z <= P. Along the ray S(t) = Q + tR,

    F(t) = P(S_x, S_y) − S_z = a t² + b t + c,

    a = −(e R_x² + f R_x R_y + g R_y²)
    b = −(2e u₀ R_x + f (u₀ R_y + v₀ R_x) + 2g v₀ R_y) − R_z
    c = P(Q_x, Q_y) − Q_z,          u₀ = Q_x − X, v₀ = Q_y − Y.

The ray is inside the solid where F >= 0. For an elliptical paraboloid
(e > 0, g > 0, f² < 4eg) and for the degenerate parabolic cylinder
(f² = 4eg) a <= 0, so F is concave: the ray meets the convex solid in one
interval [t_in, t_out], between the two roots when the discriminant
d = b² − 4ac >= 0. The entry t_in is the *smaller* root. (With a < 0 the
paper's printed (−b − √d)/2a is the larger one; it reads as the smaller root
for the equation written the other way round, S_z − P = 0.) The roots are
computed in the cancellation-free form q = −(b + sign(b)√|d|)/2, roots q/a
and c/q, which also covers a = 0 (a vertical ray, R_x = R_y = 0; a ray along a
cylinder's axis): F is then linear and the ray enters where F rises through 0.

The paper's two vectorized passes are kept: :func:`quadratic_interval`
takes √|d| and both roots for every ray (pass 1, no branches); the
callers then drop the misses (d < 0), the entries behind the origin (t <= 0)
and the rays that are not nearer than the nearest island so far (pass 2).

Rays that start inside a solid
------------------------------
A reflected ray starts on the sea, and the sea may lie inside an island's
cosine-free paraboloid (the direct rays saw the island *with* its cosine terms
and the waves; the piercing sees neither). The hit we want is the first
crossing from outside to inside the solid at t > 0. Since the solid is convex,
a ray that starts inside (c > 0, so t_in < 0 < t_out) leaves it and never comes
back: it does not hit that solid. That is exactly what the paper's "t < 0"
test does, since the smaller root is then negative.

Bounding tests and the compiled path
------------------------------------
:func:`island_candidates` and :func:`crest_candidates` only skip rays that
cannot hit, before the quadratics. :func:`trace_reflections` uses the
compiled twins of these loops (:mod:`sunset.compiled`) when they are on; they
do the same operations in the same order and give the same frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import compiled
from .constants import PART_BEACH, PART_CLIFF, PART_HILL, PART_NONE, SEA, SKY
from .errors import SunsetError, require_finite, require_int_range
from .frame import Frame
from .islands import Island
from .stokes import series_crest_curvature
from .waves import Sea, WaveTrain, unit_normal

__all__ = [
    "reflect", "paraboloid_coefficients", "quadratic_interval", "first_entry", "pierce_paraboloid",
    "island_intervals", "pierce_island", "pierce_islands", "island_candidates", "island_gradient", "island_normal",
    "largest_train", "crest_curvature", "CrestCylinder", "crest_cylinder", "cylinder_coefficients",
    "secondary_reflections", "gather", "scatter", "trace_reflections", "harmonic_sum", "crest_candidates",
    "crest_lift",
]


# --------------------------------------------------------------------------- reflection
def _vectors(name: str, v) -> np.ndarray:
    arr = np.asarray(v, dtype=float)
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise SunsetError(f"{name} must have a last axis of length 3, got shape {arr.shape}")
    require_finite(name, arr)
    return arr


def reflect(d, n) -> np.ndarray:
    """Reflect directions ``d`` about unit normals ``n``: R = D − 2(D·N)N (Blinn 1977).

    Parameters
    ----------
    d, n : array_like, shape (..., 3)
        Ray directions and unit surface normals (broadcast against each other).

    Returns
    -------
    ndarray, shape broadcast(d, n)
        The reflected directions, float64. Lengths and the angle to the normal
        are preserved (R·N = −D·N).
    """
    d = _vectors("d", d)
    n = _vectors("n", n)
    dot = np.sum(d * n, axis=-1, keepdims=True)
    return d - 2.0 * dot * n


# --------------------------------------------------------------------------- the quadratic
def paraboloid_coefficients(q, r, top, e, f, g, x0, y0):
    """Coefficients a, b, c of eq. 6 for the ray S(t) = Q + tR and a paraboloid (eq. 3).

    The paraboloid is P(x, y) = top − e(x−x0)² − f(x−x0)(y−y0) − g(y−y0)² in
    the eye's coordinates (``top`` is a z coordinate, so an island's height
    above mean sea level minus the eye height h), and F(t) = P(S) − S_z.

    Parameters
    ----------
    q, r : array_like, shape (..., 3)
        Ray origins (metres) and directions.
    top, e, f, g, x0, y0 : float or array_like broadcasting with ``q[..., 0]``
        The paraboloid: apex height (m), coefficients (m⁻¹), apex position (m).

    Returns
    -------
    a, b, c : ndarray
        a t² + b t + c = P(S(t)) − S_z (eq. 6); a <= 0 for e, g >= 0, f² <= 4eg.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    u = q[..., 0] - x0
    v = q[..., 1] - y0
    rx, ry, rz = r[..., 0], r[..., 1], r[..., 2]
    a = -(e * rx * rx + f * rx * ry + g * ry * ry)
    b = -(2.0 * e * u * rx + f * (u * ry + v * rx) + 2.0 * g * v * ry) - rz
    c = top - (e * u * u + f * u * v + g * v * v) - q[..., 2]
    return a, b, c


def quadratic_interval(a, b, c):
    """Pass 1: where the line meets the solid F = a t² + b t + c >= 0, for a <= 0.

    Every ray gets √|d| and both roots with no branching, as on the Cray; the
    roots come from the stable form q = −(b + sign(b)√|d|)/2, t = q/a, c/q.
    a = 0 (vertical rays, rays along a cylinder's axis) is the linear case
    b t + c >= 0. Values are meaningless where ``meets`` is False.

    Parameters
    ----------
    a, b, c : array_like
        The coefficients of eq. 6 (a <= 0; a tiny positive a from rounding is
        treated as 0).

    Returns
    -------
    t_in, t_out : ndarray
        The interval of t inside the solid (t_in <= t_out; ±inf where the
        linear case leaves it unbounded).
    meets : ndarray of bool
        True where the whole line meets the solid (d >= 0 for a < 0).
    """
    a, b, c = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (a, b, c)))
    d = b * b - 4.0 * a * c
    root = np.sqrt(np.abs(d))
    qq = -0.5 * (b + np.copysign(root, b))
    quad = a < 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = qq / a
        r2 = c / qq
        lin = -c / b
    # a < 0: the two roots (fmin/fmax drop the 0/0 of a double root at t = 0)
    t_in = np.fmin(r1, r2)
    t_out = np.fmax(r1, r2)
    # a = 0: F = b t + c, inside for t >= −c/b (b > 0) or t <= −c/b (b < 0)
    lin_in = np.where(b > 0.0, lin, -np.inf)
    lin_out = np.where(b < 0.0, lin, np.inf)
    t_in = np.where(quad, t_in, lin_in)
    t_out = np.where(quad, t_out, lin_out)
    meets = np.where(quad, d >= 0.0, (b != 0.0) | (c >= 0.0))
    return t_in, t_out, meets


def first_entry(t_in, meets) -> np.ndarray:
    """The first crossing from outside to inside at t > 0, +inf where there is none.

    For a convex solid this is t_in when it is positive; a ray with t_in <= 0
    starts inside (or has the solid behind it) and never enters it.
    """
    return np.where(meets & (t_in > 0.0), t_in, np.inf)


def pierce_paraboloid(q, r, top, e, f, g, x0, y0) -> np.ndarray:
    """Distance t > 0 at which each ray first enters the solid z <= P (eq. 3), +inf for a miss.

    Parameters as :func:`paraboloid_coefficients`; the result has the shape of
    ``q[..., 0]``.
    """
    q = _vectors("q", q)
    r = _vectors("r", r)
    a, b, c = paraboloid_coefficients(q, r, top, e, f, g, x0, y0)
    t_in, _, meets = quadratic_interval(a, b, c)
    return first_entry(t_in, meets)


# --------------------------------------------------------------------------- islands
def island_intervals(island: Island, eye_height: float, q, r) -> dict:
    """Intervals of each ray inside the beach and inside cliff ∩ hill.

    The hill paraboloid is H = cliff_top + hill_factor·(P_cliff − cliff_top):
    same apex position, coefficients scaled by ``hill_factor``. Its a, b, c
    reuse the cliff's quadratic forms (the common subexpressions the paper
    mentions): with A = eR_x² + fR_xR_y + gR_y², B = 2eu₀R_x + f(u₀R_y + v₀R_x)
    + 2gv₀R_y and C = eu₀² + fu₀v₀ + gv₀²,

        cliff: a = −A,      b = −B − R_z,      c = top − h − C − Q_z
        hill:  a = −k A,    b = −k B − R_z,    c = top_c − h + k(top − top_c − C) − Q_z

    (k = hill_factor, top_c = cliff_top). The solid {z <= P_cliff} ∩ {z <= H}
    is the intersection of two convex sets: a ray is inside it on the overlap
    of its two intervals, entering at the later entry.

    Returns
    -------
    dict
        ``beach``: (t_in, t_out, meets); ``upper``: (t_in, t_out, meets) of
        cliff ∩ hill; ``hill_entry``: True where cliff ∩ hill is entered
        through the hill paraboloid.
    """
    h = float(eye_height)
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    u = q[..., 0] - island.x
    v = q[..., 1] - island.y
    rx, ry, rz, qz = r[..., 0], r[..., 1], r[..., 2], q[..., 2]
    # cliff and hill: shared quadratic forms
    cl = island.cliff
    A = cl.e * rx * rx + cl.f * rx * ry + cl.g * ry * ry
    B = 2.0 * cl.e * u * rx + cl.f * (u * ry + v * rx) + 2.0 * cl.g * v * ry
    C = cl.e * u * u + cl.f * u * v + cl.g * v * v
    k = island.hill_factor
    c_in, c_out, c_meets = quadratic_interval(-A, -B - rz, (cl.height - h) - C - qz)
    h_in, h_out, h_meets = quadratic_interval(
        -k * A, -k * B - rz, (island.cliff_top - h) + k * (cl.height - island.cliff_top - C) - qz)
    up_in = np.maximum(c_in, h_in)
    up_out = np.minimum(c_out, h_out)
    up_meets = c_meets & h_meets & (up_in <= up_out)
    bch = island.beach
    b_in, b_out, b_meets = quadratic_interval(
        *paraboloid_coefficients(q, r, bch.height - h, bch.e, bch.f, bch.g, island.x, island.y))
    return {"beach": (b_in, b_out, b_meets), "upper": (up_in, up_out, up_meets), "hill_entry": h_in > c_in}


def pierce_island(island: Island, eye_height: float, q, r):
    """First entry t > 0 of each ray into an island, and the part entered.

    The island solid is {z <= P_beach} ∪ ({z <= P_cliff} ∩ {z <= H}), all in
    eye coordinates (heights above mean sea level minus ``eye_height``). The
    hit is the first t > 0 at which the ray crosses from outside this union to
    inside it: the entry into the beach unless it lies inside cliff ∩ hill,
    or the entry into cliff ∩ hill unless it lies inside the beach, whichever
    is nearer.

    Returns
    -------
    t : ndarray
        Distance along R (metres when |R| = 1); +inf for a miss.
    part : ndarray of int8
        PART_BEACH, PART_CLIFF or PART_HILL by the surface entered; PART_NONE for a miss.
    """
    iv = island_intervals(island, eye_height, q, r)
    b_in, b_out, b_meets = iv["beach"]
    u_in, u_out, u_meets = iv["upper"]
    beach_t = np.where(b_meets & (b_in > 0.0) & ~(u_meets & (u_in < b_in) & (b_in <= u_out)), b_in, np.inf)
    upper_t = np.where(u_meets & (u_in > 0.0) & ~(b_meets & (b_in < u_in) & (u_in <= b_out)), u_in, np.inf)
    take_upper = upper_t <= beach_t
    t = np.where(take_upper, upper_t, beach_t)
    upper_part = np.where(iv["hill_entry"], PART_HILL, PART_CLIFF)
    part = np.where(np.isfinite(t), np.where(take_upper, upper_part, PART_BEACH), PART_NONE).astype(np.int8)
    return t, part


def pierce_islands(islands, eye_height: float, q, r):
    """Nearest island each ray pierces (pass 2 over the islands).

    Parameters
    ----------
    islands : sequence of Island
    eye_height : float
        h, metres: island heights are above mean sea level, eye z = height − h.
    q, r : array_like, shape (..., 3)
        Ray origins and directions.

    Returns
    -------
    t : ndarray
        Distance to the nearest island, +inf where none is hit.
    which : ndarray of int8
        1-based island number, or SKY (−1) where none is hit.
    part : ndarray of int8
        The part entered (PART_NONE for sky).
    """
    q = _vectors("q", q)
    r = _vectors("r", r)
    shape = q.shape[:-1]
    q = q.reshape(-1, 3)
    r = r.reshape(-1, 3)
    best = np.full(len(q), np.inf)
    which = np.full(len(q), SKY, dtype=np.int8)
    part = np.zeros(len(q), dtype=np.int8)
    for k, island in enumerate(islands, start=1):
        idx, (qk, rk) = gather(island_candidates(island, eye_height, q, r), q, r)
        t, p = pierce_island(island, eye_height, qk, rk)
        nearer = t < best[idx]  # misses are +inf; entries behind the origin were dropped already
        idx, (t, p) = idx[nearer], (t[nearer], p[nearer])
        scatter(idx, t, best)
        scatter(idx, k, which)
        scatter(idx, p, part)
    return best.reshape(shape), which.reshape(shape), part.reshape(shape)


def island_candidates(island: Island, eye_height: float, q, r) -> np.ndarray:
    """Rays that may hit ``island``: a cheap bounding test before the quadratics.

    A ray with R_z >= 0 never goes below its origin, so it can only enter the
    island where the beach or the cliff paraboloid stands above the lowest
    such origin z₀: inside a circle about the apex of radius
    ρ = √((top − z₀)/λ_min), λ_min the smaller eigenvalue of the quadratic
    form (cliff ∩ hill lies under the cliff). The ray is a candidate if its
    horizontal line passes within ρ of the apex, not behind the origin, or if
    its origin is within ρ. Rays heading down are always candidates. The test
    only skips work: the quadratics decide.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    up = r[..., 2] >= 0.0
    if not up.any():
        return np.ones(q.shape[:-1], bool)
    z0 = float(np.min(q[..., 2][up]))
    rho = island.smooth_radius(eye_height + z0)
    top = island.smooth_height
    cx = island.x - q[..., 0]
    cy = island.y - q[..., 1]
    rx, ry, rz = r[..., 0], r[..., 1], r[..., 2]
    horiz = np.sqrt(rx * rx + ry * ry)
    along = rx * cx + ry * cy  # |R_h| times the distance to the apex along the ray's horizontal line
    near_line = (np.abs(rx * cy - ry * cx) <= rho * horiz) & (along > -rho * horiz)
    # ... and the ray is still below the island's top when it reaches the circle
    low_enough = (along - rho * horiz) * rz <= (top - eye_height - q[..., 2]) * horiz * horiz
    return ~up | (near_line & low_enough) | (cx * cx + cy * cy <= rho * rho)


def island_gradient(island: Island, x, y, part):
    """(∂z/∂x, ∂z/∂y) of island surface ``part`` with all its cosine terms (eq. 4).

    Beach: ∇P_beach (no cosines). Cliff: ∇Q, Q = P_cliff + Σ a cos(ℓx + my).
    Hill: hill_factor·∇Q. The part is the one the ray entered (so that the
    normal and the part's colour agree), not the part on top of the surface
    with cosines, which :meth:`Island.gradient` would take; the gradients
    themselves come from :mod:`sunset.islands`. ``x``, ``y`` in metres.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    part = np.asarray(part)
    qx, qy = island.cliff_equation_gradient(x, y)
    bx, by = island.beach.gradient(x - island.x, y - island.y)
    scale = np.where(part == PART_HILL, island.hill_factor, 1.0)
    gx = np.where(part == PART_BEACH, bx, scale * qx)
    gy = np.where(part == PART_BEACH, by, scale * qy)
    return gx, gy


def island_normal(island: Island, x, y, part) -> np.ndarray:
    """Unit upward normal of the island surface with its cosine terms (the wrinkle normal).

    Blinn's (1978) wrinkle approximation, as in the paper: the ray pierces the
    smooth paraboloid, but is shaded with the normal of eq. 4 at the
    piercing point's (x, y). Shape ``broadcast(x, y) + (3,)``.
    """
    return unit_normal(*island_gradient(island, x, y, part))


# --------------------------------------------------------------------------- secondary reflections
def largest_train(sea: Sea) -> WaveTrain | None:
    """The train with the largest first-harmonic amplitude (the first on a tie); None for still water."""
    moving = [t for t in sea.trains if t.amplitude > 0]
    if not moving:
        return None
    return max(moving, key=lambda t: t.amplitude)


def crest_curvature(train: WaveTrain) -> float:
    """κ = Σ_n a_n (n k)², the curvature of the train's Stokes series (eq. 2) at its crest, m⁻¹.

    The series z(u) = Σ a_n cos(n k u) has z'(0) = 0 and z''(0) = −Σ a_n (nk)²;
    :func:`sunset.stokes.series_crest_curvature` gives κ/k for the train's
    steepness α = k a₁ and Stokes order.
    """
    return float(series_crest_curvature(train.steepness, train.stokes_order)) * train.k


@dataclass(frozen=True)
class CrestCylinder:
    """Parabolic cylinders fitted to the first crest ahead of each ray, as degenerate paraboloids.

    z = top − e(x−x0)² − f(x−x0)(y−y0) − g(y−y0)² with f² = 4eg: the axis
    is the crest line through (x0, y0), the foot of the perpendicular from the
    ray's origin (eye coordinates, metres). ``u0`` is the signed distance from
    the crest line to the origin along the wave's direction of travel, ``w``
    the rate of change of that distance per unit t along the ray.
    """

    top: np.ndarray
    e: float
    f: float
    g: float
    x0: np.ndarray
    y0: np.ndarray
    curvature: float
    u0: np.ndarray
    w: np.ndarray


def harmonic_sum(amps, c):
    """Σ_n a_n cos nθ from c = cos θ, by the Chebyshev recurrence T_(n+1) = 2c T_n − T_(n−1).

    One cosine per ray instead of one per harmonic (the speed-up the paper
    suggests for the Stokes series); :mod:`sunset.compiled` does the same
    operations in the same order.
    """
    c = np.asarray(c, dtype=float)
    out = amps[0] * c
    t_prev, t_cur = 1.0, c
    for a in amps[1:]:
        t_prev, t_cur = t_cur, 2.0 * c * t_cur - t_prev
        out = out + a * t_cur
    return out


def _crest_ahead(train: WaveTrain, t: float, q, r):
    """(ψ = θ mod 2π at the origin, the rate ℓR_x + mR_y of θ along the ray, u₀) for :func:`crest_cylinder`."""
    k = train.k
    l, m = train.wave_vector
    theta = l * q[..., 0] + m * q[..., 1] - train.omega * t + train.phase
    rate = l * r[..., 0] + m * r[..., 1]
    psi = np.mod(theta, 2.0 * math.pi)
    ahead = np.where(rate >= 0.0, 2.0 * math.pi - psi, np.where(psi > 0.0, -psi, -2.0 * math.pi))
    return psi, rate, -ahead / k


def crest_lift(train: WaveTrain) -> float:
    """A bound on how far a crest cylinder's top stands above its ray's origin, metres.

    top − Q_z = Σ a_n − Σ a_n cos nθ(Q) <= 2 Σ a_n (every a_n >= 0), with a
    little to spare for rounding.
    """
    return 2.0 * float(np.sum(train.harmonic_amplitudes())) * (1.0 + 1e-6) + 1e-9


def crest_candidates(train: WaveTrain, t: float, q, r) -> np.ndarray:
    """Rays that may meet their crest cylinder: a bounding test before the cosines and the quadratic.

    Along the ray, F(t) = top − κu(t)²/2 − Q_z − R_z t with u(t) = u₀ + w t
    (:func:`cylinder_coefficients`), and top − Q_z <= L = :func:`crest_lift`.
    A ray heading up (R_z > 0) is above the cylinder for t > L/R_z, and
    within that reach it can only be inside where κu²/2 <= L, i.e.
    |u| <= √(2L/κ). When u stays beyond that half-width on one side over the
    whole reach, the ray clears the crest: F < 0 for every t > 0. Rays heading
    down or level are always candidates. Like :func:`island_candidates`, the
    test only skips work.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    _, rate, u0 = _crest_ahead(train, t, q, r)
    w = rate / train.k
    lift = crest_lift(train)
    half = math.sqrt(2.0 * lift / crest_curvature(train))
    rz = r[..., 2]
    up = rz > 0.0
    reach = np.where(up, lift / np.where(up, rz, 1.0), 0.0)
    u_end = u0 + w * reach
    clear = up & (((u0 > half) & (u_end > half)) | ((u0 < -half) & (u_end < -half)))
    return ~clear


def crest_cylinder(train: WaveTrain, t: float, q, r) -> CrestCylinder:
    """The parabolic cylinder tangent to the first crest of ``train`` ahead of each ray.

    Crest lines are where the train's phase θ = ℓx + my − ωt + φ ≡ 0 (mod 2π).
    Along the ray, θ changes at the rate ℓR_x + mR_y per unit t; the first
    crest ahead is the next multiple of 2π that θ reaches in that direction
    (a crest through the origin itself is the one the ray leaves, not one
    ahead). A ray exactly parallel to the crests (rate 0, including vertical
    rays) takes the next crest in the direction of travel of the waves: the
    limit of rays turned ever so slightly forward; its cylinder's axis is
    parallel to the ray, and the quadratic becomes linear.

    Height. The cylinder is z = top − κu²/2 across the crest line (u the
    distance across), with κ = :func:`crest_curvature`. Its top is set so that
    the crest stands as far above the ray's origin Q as this train's crest
    stands above this train's own elevation at Q:

        top = Q_z + Σ_n a_n − Σ_n a_n cos(nθ(Q)),

    i.e. the other trains' elevation is taken as a constant offset, its value
    at Q. Because every a_n >= 0 and cos y >= 1 − y²/2, the train's profile
    lies on or above its osculating parabola, so the origin is never inside
    the cylinder (c <= 0): every ray heading down meets it, and the test
    "d >= 0 and t > 0" (the paper's) picks out exactly the rays that do not
    clear the crest.

    Parameters
    ----------
    train : WaveTrain
    t : float
        Time, seconds.
    q, r : array_like, shape (N, 3)
        Ray origins on the sea (eye coordinates, metres) and first reflected directions.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    k = train.k
    l, m = train.wave_vector
    psi, rate, u0 = _crest_ahead(train, t, q, r)
    amps = train.harmonic_amplitudes()
    elevation = harmonic_sum(amps, np.cos(psi))  # cos θ = cos ψ, cheaper on the reduced angle
    top = q[..., 2] + float(np.sum(amps)) - elevation
    kappa = crest_curvature(train)
    cl, cm = l / k, m / k
    x0 = q[..., 0] - u0 * cl
    y0 = q[..., 1] - u0 * cm
    return CrestCylinder(top=top, e=0.5 * kappa * cl * cl, f=kappa * cl * cm, g=0.5 * kappa * cm * cm,
                         x0=x0, y0=y0, curvature=kappa, u0=u0, w=rate / k)


def cylinder_coefficients(cyl: CrestCylinder, q, r):
    """a, b, c of eq. 6 for a crest cylinder, in its factored form.

    With u(t) = u₀ + w t the distance across the crest line,
    F(t) = top − κu(t)²/2 − Q_z − R_z t, so a = −κw²/2 (exactly <= 0, even
    where rounding would make e R_x² + f R_x R_y + g R_y² of the unfactored
    form slightly negative), b = −κu₀w − R_z, c = top − κu₀²/2 − Q_z.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    kap = cyl.curvature
    a = -0.5 * kap * cyl.w * cyl.w
    b = -kap * cyl.u0 * cyl.w - r[..., 2]
    c = cyl.top - 0.5 * kap * cyl.u0 * cyl.u0 - q[..., 2]
    return a, b, c


def secondary_reflections(sea: Sea, t: float, q, r):
    """Second reflections off the crest ahead (Figure 6), for rays (N, 3).

    Pierce each ray's crest cylinder (the rays that :func:`crest_candidates`
    keeps, gathered); the rays that hit (d >= 0, t > 0) are
    gathered into contiguous arrays, reflected again off the true wave normal
    (:meth:`Sea.normal`) at the piercing point's (x, y), and returned with
    their indices for scattering back.

    Returns
    -------
    idx : ndarray of intp
        Indices of the rays that reflect twice.
    point : ndarray (len(idx), 3)
        The piercing points on the cylinders (the second rays' origins).
    ray : ndarray (len(idx), 3)
        The second reflected directions (R_z not yet made positive).
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    train = largest_train(sea)
    if train is None or q.shape[0] == 0:
        return np.zeros(0, np.intp), np.zeros((0, 3)), np.zeros((0, 3))
    cand, (qc, rc) = gather(crest_candidates(train, t, q, r), q, r)
    cyl = crest_cylinder(train, t, qc, rc)
    t_in, _, meets = quadratic_interval(*cylinder_coefficients(cyl, qc, rc))
    hit = first_entry(t_in, meets)
    sel, (q2, r2, t2) = gather(np.isfinite(hit), qc, rc, hit)
    idx = cand[sel]
    point = q2 + t2[:, None] * r2
    normal = sea.normal(point[:, 0], point[:, 1], t)
    return idx, point, reflect(r2, normal)


# --------------------------------------------------------------------------- gather / scatter
def gather(mask, *arrays):
    """Compress: the indices where ``mask`` holds and each array's rows there.

    The Cray's "compress": the selected rays are copied into consecutive
    positions, so that the work that follows runs on dense vectors.
    """
    idx = np.flatnonzero(np.asarray(mask).ravel())
    return idx, [np.take(np.asarray(a), idx, axis=0) for a in arrays]  # take: rows, fast for (N, 3)


def scatter(idx, values, out) -> np.ndarray:
    """Decompress: write ``values`` back into rows ``idx`` of ``out`` (in place), and return ``out``."""
    out[idx] = values
    return out


# --------------------------------------------------------------------------- the frame
def trace_reflections(scene, frame: Frame, reflections: int) -> Frame:
    """Trace the reflected rays of every sea pixel and fill the frame's final fields.

    Parameters
    ----------
    scene : Scene
    frame : Frame
        After :meth:`Frame.finish_direct` (called here if it was not).
    reflections : {0, 1, 2}
        0: R_z → |R_z|, straight to the sky. 1: one reflection, |R_z|, then the
        islands or the sky (Figures 4, 5). 2: secondary reflections off the
        crest cylinder, then |R_z|, then the islands or the sky (Figure 6).

    Returns
    -------
    Frame
        The same frame, with ``reflections`` set and ``bounces``, ``ray``,
        ``final_surface``, ``final_part`` and ``final_normal`` filled for sea
        pixels (``final_normal`` is NaN where the ray ends in the sky).
    """
    require_int_range("reflections", reflections, 0, 2)
    if frame.bounces is None:
        frame.finish_direct()
    frame.reflections = reflections
    sea_mask = frame.surface == SEA
    if not sea_mask.any():
        return frame
    if compiled.enabled():
        return _trace_reflections_compiled(scene, frame, reflections)
    h = scene.camera.eye_height
    q = frame.point[sea_mask].astype(np.float64)
    d = frame.direction[sea_mask].astype(np.float64)
    n = frame.normal[sea_mask].astype(np.float64)
    r = reflect(d, n)
    bounces = np.ones(len(q), np.uint8)
    if reflections == 2:
        idx, point, ray2 = secondary_reflections(scene.sea, frame.t, q, r)
        scatter(idx, point, q)
        scatter(idx, ray2, r)
        scatter(idx, 2, bounces)
    r[:, 2] = np.abs(r[:, 2])
    final = np.full(len(q), SKY, np.int8)
    part = np.zeros(len(q), np.int8)
    normal = np.full((len(q), 3), np.nan)
    if reflections >= 1 and scene.islands:
        dist, final, part = pierce_islands(scene.islands, h, q, r)
        for k, island in enumerate(scene.islands, start=1):
            idx, (qk, rk, tk, pk) = gather(final == k, q, r, dist, part)
            if len(idx):
                hit = qk + tk[:, None] * rk
                scatter(idx, island_normal(island, hit[:, 0], hit[:, 1], pk), normal)
    frame.bounces[sea_mask] = bounces
    frame.ray[sea_mask] = r
    frame.final_surface[sea_mask] = final
    frame.final_part[sea_mask] = part
    frame.final_normal[sea_mask] = normal
    return frame


def _trace_reflections_compiled(scene, frame: Frame, reflections: int) -> Frame:
    """:func:`trace_reflections` with the per-ray loops compiled (:mod:`sunset.compiled`).

    The same steps in the same arithmetic: gather and reflect the sea pixels,
    pierce the crest cylinders, reflect the hits again off the true wave
    normal (NumPy, on the compressed subset), |R_z|, pierce the islands, and
    shade the island hits (NumPy, compressed). Gives the frame the NumPy path gives.
    """
    h = scene.camera.eye_height
    flat, q, r = compiled.reflect_sea(frame, SEA)
    bounces = np.ones(len(q), np.uint8)
    if reflections == 2:
        train = largest_train(scene.sea)
        if train is not None:
            hit = compiled.crest_hits(train, frame.t, q, r)
            idx, (q2, r2, t2) = gather(np.isfinite(hit), q, r, hit)
            point = q2 + t2[:, None] * r2
            normal = scene.sea.normal(point[:, 0], point[:, 1], frame.t)
            scatter(idx, point, q)
            scatter(idx, reflect(r2, normal), r)
            scatter(idx, 2, bounces)
    np.abs(r[:, 2], out=r[:, 2])
    final = np.full(len(q), SKY, np.int8)
    part = np.zeros(len(q), np.int8)
    normal = None
    if reflections >= 1 and scene.islands:
        dist, final, part = compiled.pierce_islands(scene.islands, h, q, r)
        normal = np.full((len(q), 3), np.nan)
        # compress once to the rays that hit an island, then split by island
        any_idx, (qa, ra, ta, pa, fa) = gather(final > 0, q, r, dist, part, final)
        for k, island in enumerate(scene.islands, start=1):
            sel, (qk, rk, tk, pk) = gather(fa == k, qa, ra, ta, pa)
            if len(sel):
                hit = qk + tk[:, None] * rk
                scatter(any_idx[sel], island_normal(island, hit[:, 0], hit[:, 1], pk), normal)
    if normal is None:
        normal = np.full((len(q), 3), np.nan)
    compiled.write_back(frame, flat, bounces, r, final, part, normal)
    return frame
