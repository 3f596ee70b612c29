"""The sun's rays on the waves: where they land, how much light each point gets, where it goes on.

Both tracers of the ripples of light, the beams (:mod:`sunset.light.caustics`)
and the photons (:mod:`sunset.light.ripples`), start from the same question:
what does a point of the water, named by its horizontal position (x, y), do
with the sunlight? This module answers it, one array of points at a time.

The sea as a table of cosines
-----------------------------
Eq. 1 with Stokes' harmonics is a sum of cosines, one per train j and
harmonic n: η(x, y) = Σ a cos(k_x x + k_y y + c) with (k_x, k_y) = n(ℓ_j, m_j)
and c = n(φ_j − ω_j t) (:func:`sea_table`). The compiled kernels read this
table; so does the NumPy reference, which is the sea's own
:meth:`~sunset.model.waves.Sea.elevation` written as one sum.

The light a point receives
--------------------------
The water is parametrised by its horizontal position: the point q = (x, y,
η) over the patch element dA = dx dy has the surface element N dS =
(−η_x, −η_y, 1) dA, so the parallel beam of sunlight (irradiance E on a plane
facing the sun P) brings it the flux E (P·N) dS = E ω dA with

    ω = P_z − P_x η_x − P_y η_y,

exact for any slope. Facets that face away (ω <= 0) get nothing; so do
facets that face the sun but lie in the shadow of a crest between them and
the sun (:func:`visible`). On still water ω = sin e, the flux E sin e A of a
patch of area A.

The shadow test
---------------
Along the sun ray from q, q + τP, the ray's height above the water is
g(τ) = q_z + τP_z − η(q_h + τP_h), with g(0) = 0 and g'(0) = ω, and the
table bounds its curvature: |g''| <= K = Σ|a|(k·P_h)². From any τ where the
ray is g above the water, climbing at g', the parabola g + g's − Ks²/2 stays
under it, so the ray cannot meet the water before that parabola's root
s* = 2g/(√(g'² + 2Kg) − g'). The test steps s*/2, where the ray is still at
least g/2 above the water (the parabola is concave), starting at τ = ω/K.
It is lit when it climbs above the sea's highest crest d
(q_z + τP_z >= d), shadowed when g falls below :data:`SHADOW_TOLERANCE` or
it has not cleared the crests after :data:`SHADOW_STEPS` steps (a ray
grazing a crest).

Where the light goes
--------------------
At q the angle of incidence has cos i = P·N; Fresnel's R(cos i)
(:mod:`sunset.light.fresnel`) goes into the reflected ray r = −P + 2(P·N)N
and 1 − R into the refracted one (Snell, :func:`~sunset.light.fresnel.refract`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels import twin
from .fresnel import reflectance, refract

__all__ = ["SeaTable", "sea_table", "surface", "visible", "SunPoints", "sun_points", "in_shadow", "SHADOW_TOLERANCE",
           "SHADOW_STEPS"]

#: A sun ray that comes within this many metres of the water is in its shadow.
SHADOW_TOLERANCE = 1e-9
#: The most steps of the shadow test; a ray that has not cleared the crests by then grazes one: shadowed.
SHADOW_STEPS = 200


@dataclass(frozen=True)
class SeaTable:
    """The sea at one time as a sum of cosines a cos(k_x x + k_y y + c): one entry (H,) per train and harmonic;
    ``top`` the highest the sea can rise (Σ|a|, metres)."""

    a: np.ndarray
    kx: np.ndarray
    ky: np.ndarray
    c: np.ndarray
    top: float


def sea_table(sea, t: float) -> SeaTable:
    """The cosines of eq. 1 (with Stokes' harmonics) at time ``t``: a_jn, n ℓ_j, n m_j and n(φ_j − ω_j t)."""
    rows = []
    for train in sea.trains:
        l, m = train.wave_vector
        for n, a in enumerate(train.harmonic_amplitudes(), start=1):
            if a != 0.0:
                rows.append((float(a), n * l, n * m, n * (train.phase - train.omega * float(t))))
    a, kx, ky, c = (np.array(col, dtype=float) for col in zip(*rows)) if rows else (np.zeros(0),) * 4
    return SeaTable(a, kx, ky, c, float(np.abs(a).sum()))


@twin("sunset.light.sunrays_numba")
def surface(a, kx, ky, c, x, y):
    """The sea's height η and slopes (η_x, η_y) at the points (x, y) (n,): Σ a cos θ and
    −Σ a (k_x, k_y) sin θ."""
    eta, gx, gy = np.zeros(x.shape), np.zeros(x.shape), np.zeros(x.shape)
    for h in range(len(a)):
        theta = kx[h] * x + ky[h] * y + c[h]
        eta += a[h] * np.cos(theta)
        s = a[h] * np.sin(theta)
        gx -= kx[h] * s
        gy -= ky[h] * s
    return eta, gx, gy


@twin("sunset.light.sunrays_numba")
def visible(a, kx, ky, c, top: float, qx, qy, qz, omega, p) -> np.ndarray:
    """Whether the sun ray from each water point q (n,) reaches the sun past the
    crests (module docstring)."""
    kp = kx * p[0] + ky * p[1]
    curv = max(float(np.sum(np.abs(a) * kp * kp)), 1e-300)      # K
    lit = np.zeros(qx.shape, dtype=bool)
    tau = np.where(omega > 0, omega / curv, 0.0)                 # the first step
    todo = np.flatnonzero(omega > 0)
    for _ in range(SHADOW_STEPS):
        if todo.size == 0:
            break
        t = tau[todo]
        height = qz[todo] + t * p[2]
        up = height >= top                                       # above every crest
        lit[todo[up]] = True
        x, y = qx[todo] + t * p[0], qy[todo] + t * p[1]
        eta, gx, gy = surface.reference(a, kx, ky, c, x, y)
        g = height - eta                                         # over the water
        climb = p[2] - p[0] * gx - p[1] * gy                     # g'
        go = ~up & (g > SHADOW_TOLERANCE)
        g, climb = g[go], climb[go]
        # half the way to the parabola g + g's - K s^2/2's root
        root = np.sqrt(climb * climb + 2.0 * curv * g)
        tau[todo[go]] = t[go] + g / (root - climb)
        todo = todo[go]
    return lit


@dataclass(frozen=True)
class SunPoints:
    """What the water does with the sunlight at n points.

    ``q`` (n, 3) the points on the water (z above mean sea level), ``normal`` (n, 3) its unit normals,
    ``omega`` (n,) the sunlight's flux per horizontal area relative to E if no crest shadows the point (0
    where the water faces away), ``R`` (n,) Fresnel's reflectance, ``reflected`` and ``refracted`` (n, 3)
    the two rays' unit directions.
    """

    q: np.ndarray
    normal: np.ndarray
    omega: np.ndarray
    R: np.ndarray
    reflected: np.ndarray
    refracted: np.ndarray


def sun_points(table: SeaTable, x, y, p) -> SunPoints:
    """:class:`SunPoints` for the water at horizontal positions ``x``, ``y`` (n,), the sun in direction ``p``."""
    x = np.ascontiguousarray(x, dtype=float)
    y = np.ascontiguousarray(y, dtype=float)
    p = np.asarray(p, dtype=float)
    eta, gx, gy = surface(table.a, table.kx, table.ky, table.c, x, y)
    inv = 1.0 / np.sqrt(gx * gx + gy * gy + 1.0)
    normal = np.stack([-gx * inv, -gy * inv, inv], axis=-1)
    omega = np.maximum(p[2] - p[0] * gx - p[1] * gy, 0.0)
    cos_i = np.clip(normal @ p, 0.0, 1.0)
    reflected = -p[None, :] + (2.0 * (normal @ p))[:, None] * normal
    refracted = refract(np.broadcast_to(-p, normal.shape), normal, cos_i)
    return SunPoints(np.stack([x, y, eta], axis=-1), normal, omega, reflectance(cos_i), reflected, refracted)


def in_shadow(table: SeaTable, x, y, eta, omega, p, where) -> np.ndarray:
    """Whether each water point (x, y, η) (n,) lies in the waves' shadow: facing away from the sun (ω <= 0), or
    behind a crest (:func:`visible`); the crests are looked for only ``where`` (n,) is True."""
    dark = ~(np.asarray(omega) > 0)
    sel = np.flatnonzero(np.asarray(where) & ~dark)
    if sel.size and table.top > 0:
        dark[sel] = ~visible(table.a, table.kx, table.ky, table.c, table.top, np.ascontiguousarray(x[sel]),
                             np.ascontiguousarray(y[sel]), np.ascontiguousarray(eta[sel]),
                             np.ascontiguousarray(omega[sel]), np.asarray(p, dtype=float))
    return dark
