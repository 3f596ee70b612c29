"""Reflected rays: piercing quadrics instead of height fields (paper eqs. 5–6).

The direct ray through every sea pixel has met the water at a point Q with
unit normal N (:mod:`sunset.vector.heightfield`). It reflects (Blinn 1977):

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
:func:`island_candidates` (and :func:`sunset.vector.crests.crest_candidates`)
only skip rays that cannot hit, before the quadratics. The crest cylinders of
the secondary reflections are in :mod:`sunset.vector.crests`; the frame's
reflected rays are traced by :mod:`sunset.vector.reflect`, whose Numba twin
(:mod:`sunset.vector.reflect_numba`) does these loops' operations in the same
order and gives the same frame.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, PART_NONE, SKY
from ..errors import SunsetError, require_finite
from ..model.islands import Island
from ..model.waves import unit_normal

__all__ = [
    "reflect", "paraboloid_coefficients", "quadratic_interval", "first_entry", "pierce_paraboloid",
    "island_intervals", "pierce_island", "pierce_islands", "island_bounds", "island_candidates", "island_gradient", "island_normal",
    "gather", "scatter",
]


# --------------------------------------------------------------------------- reflection
def _vectors(name: str, v) -> np.ndarray:
    arr = np.asarray(v, dtype=float)
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise SunsetError(f"{name} must have a last axis of length 3, got shape {arr.shape}")
    require_finite(name, arr)
    return arr


def reflect(d, n) -> np.ndarray:
    """Reflect directions ``d`` about unit normals ``n``: R = D − 2(D·N)N (Blinn).

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
    """Coefficients a, b, c of eq. 6 for the ray S(t) = Q + tR and a paraboloid.

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
        hill:  a = −k A,    b = −k B − R_z,
               c = top_c − h + k(top − top_c − C) − Q_z

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
        -k * A, -k * B - rz,
        (island.cliff_top - h) + k * (cl.height - island.cliff_top - C) - qz)
    up_in = np.maximum(c_in, h_in)
    up_out = np.minimum(c_out, h_out)
    up_meets = c_meets & h_meets & (up_in <= up_out)
    bch = island.beach
    b_in, b_out, b_meets = quadratic_interval(
        *paraboloid_coefficients(q, r, bch.height - h, bch.e, bch.f, bch.g,
                                 island.x, island.y))
    return {"beach": (b_in, b_out, b_meets), "upper": (up_in, up_out, up_meets),
            "hill_entry": h_in > c_in}


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
        # misses are +inf; entries behind the origin were dropped already
        nearer = t < best[idx]
        idx, (t, p) = idx[nearer], (t[nearer], p[nearer])
        scatter(idx, t, best)
        scatter(idx, k, which)
        scatter(idx, p, part)
    return best.reshape(shape), which.reshape(shape), part.reshape(shape)


#: How far the bounding test reaches beyond the bounding paraboloids, relative (a million times the
#: rounding of the quadratics, which the test must never undercut).
BOUND_GRACE = 1e-6


def _bounding_paraboloid(top: float, e: float, f: float, g: float, scale: float = 1.0):
    """(λ, λ − grace·Λ, top + grace·(1 + |top|), grace) of the bound top − λd² over z = top − scale·(e u² + f u v + g v²).

    λ is the form's smallest eigenvalue taken a little low, so that rounding
    cannot make it too large (then top − λ d² >= the paraboloid everywhere),
    Λ the largest. ``grace`` widens the test in proportion to Λ/λ, how much
    the quadratics' rounding can exceed the bounding paraboloid; a form too
    thin to bound (λ = 0) makes every ray a candidate.
    """
    spread = math.hypot(e - g, f)
    lam = max(0.0, 0.5 * (e + g - spread) * (1.0 - 1e-9) - 1e-12 * (e + g)) * scale
    if not lam > 0.0:
        return 0.0, 0.0, math.inf, 0.0
    big = 0.5 * (e + g + spread) * scale
    grace = BOUND_GRACE * max(1.0, big / lam)
    return lam, lam - grace * big, top + grace * (1.0 + abs(top)), grace


def island_bounds(island: Island, eye_height: float):
    """The bounding paraboloids of revolution of the beach and of cliff ∩ hill, for :func:`island_candidates`.

    Two tuples (λ, λ − grace·Λ, top + grace·(1 + |top|), grace)
    (:func:`_bounding_paraboloid`), tops in eye coordinates (height above mean sea
    level − ``eye_height``). Cliff ∩ hill lies under the hill, whose form is
    the cliff's times the hill factor and whose top is cliff_top +
    hill_factor·(cliff height − cliff_top); the hill's bound is the tighter
    of the two for the islands of the scenes (the cliff's adds little).
    """
    h = float(eye_height)
    cl, bc, k = island.cliff, island.beach, island.hill_factor
    return (_bounding_paraboloid(bc.height - h, bc.e, bc.f, bc.g),
            _bounding_paraboloid(island.cliff_top + k * (cl.height - island.cliff_top) - h, cl.e, cl.f, cl.g, k))


def island_candidates(island: Island, eye_height: float, q, r) -> np.ndarray:
    """Rays that may hit ``island``: a cheap bounding test before the quadratics.

    A paraboloid P = top − (e u² + f u v + g v²) lies under the paraboloid
    of revolution top − λ d², λ the form's smallest eigenvalue and d the
    distance from the apex. Along the ray, d(t)² = c² − 2 t a + t² |R_h|²
    (c the horizontal distance from the origin to the apex, a = R_h·(apex −
    Q_h)), so the ray is under that bound where

        G(t) = λ|R_h|² t² + (R_z − 2λa) t + λc² − (top − Q_z) <= 0.

    G is convex: its least value over t >= 0 is G(0) when 2λa <= R_z, else
    G(0) − (2λa − R_z)²/(4λ|R_h|²). A ray that reaches no point under the
    beach's bound nor under the hill's (over cliff ∩ hill) cannot hit the
    island (:func:`island_bounds`). Every ray is tested on its own, heading
    up or down; the test is widened by a grace far beyond rounding, so it
    only skips rays that miss: the quadratics decide.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    cx = island.x - q[..., 0]
    cy = island.y - q[..., 1]
    rx, ry, rz, qz = r[..., 0], r[..., 1], r[..., 2], q[..., 2]
    c2 = cx * cx + cy * cy
    along = rx * cx + ry * cy
    h2 = rx * rx + ry * ry

    def under(lam, lo, hi, grace):
        # λc² − (top − Q_z) − grace·(1 + |top| + |Q_z| + Λc²), the least value of G if 2λa <= R_z
        slack = lo * c2 + (qz - grace * np.abs(qz)) - hi
        k = 2.0 * lam * along - rz
        with np.errstate(invalid="ignore"):      # λ = 0: 0·(−inf), and every ray is a candidate
            return (slack <= 0.0) | ((k > 0.0) & (k * k >= 4.0 * lam * h2 * slack))

    beach, upper = island_bounds(island, eye_height)
    return under(*beach) | under(*upper)


def island_gradient(island: Island, x, y, part):
    """(∂z/∂x, ∂z/∂y) of island surface ``part`` with all its cosine terms (eq. 4).

    Beach: ∇P_beach (no cosines). Cliff: ∇Q, Q = P_cliff + Σ a cos(ℓx + my).
    Hill: hill_factor·∇Q. The part is the one the ray entered (so that the
    normal and the part's colour agree), not the part on top of the surface
    with cosines, which :meth:`Island.gradient` would take; the gradients
    themselves come from :mod:`sunset.model.islands`. ``x``, ``y`` in metres.
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


# --------------------------------------------------------------------------- gather / scatter


# --------------------------------------------------------------------------- the frame


def gather(mask, *arrays):
    """Compress: the indices where ``mask`` holds and each array's rows there.

    The Cray's "compress": the selected rays are copied into consecutive
    positions, so that the work that follows runs on dense vectors.
    """
    idx = np.flatnonzero(np.asarray(mask).ravel())
    # np.take of rows: fast for (N, 3)
    return idx, [np.take(np.asarray(a), idx, axis=0) for a in arrays]


def scatter(idx, values, out) -> np.ndarray:
    """Decompress: write ``values`` back into rows ``idx`` of ``out`` (in place), and return ``out``."""
    out[idx] = values
    return out
