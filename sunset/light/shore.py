"""Ripples of light on the shore: sunlight reflected and refracted by the waves, gathered on an island.

The paper's second proposal (see :mod:`sunset.light.ripples`) names "a small
object"; the islands' beaches and cliffs near the water line catch the same
light. This module traces it onto one island of a scene, reusing the post's
machinery: the patch's reach, Fresnel, the clear sea water's attenuation and
the normalised Epanechnikov kernel (:func:`sunset.light.ripples._splat`).

The receiver and its texture
----------------------------
Rays are pierced against the island the reflected rays of the vector stage
pierce: the smooth island (eq. 3 without its cosine terms, beach ∪ (cliff ∩
hill), :func:`sunset.vector.pierce.pierce_island` with eye height 0, so that
z is the height above the mean sea level). Along each azimuth φ about the
apex that surface falls monotonically with the distance r from the apex, and
it crosses the mean sea level at r_w(φ) (:func:`water_line`, closed form:
each paraboloid reaches height z at r² = (top − z)/(e cos²φ + f cos φ sin φ
+ g sin²φ)). The texture's coordinates are φ (all round, periodic) and the
*horizontal distance inland from the mean water line*, w = r_w(φ) − r
(negative out at sea, over the sea bed). Height would crowd a gentle beach
(2–3° on Carla's Island: a 0.25 m step in height is 6 m of sand) into a few
texels and make a texel's area jump by a factor of thirty at the foot of the
cliff; horizontal distance keeps the texels' areas within a factor of two.

Irradiance per true surface area
--------------------------------
The map (φ, w) → (x, y) has Jacobian r, so a texel's horizontal area is
∫∫ r dφ dw; its area on the surface is the horizontal area over the cosine of
the surface's tilt, 1/cos θ = √(1 + |∇H|²), ∇H the smooth surface's
gradient: A = ∫∫ r √(1 + |∇H|²) dφ dw, by the midpoint rule on
:data:`AREA_SUBSAMPLES`² points per texel (:func:`texel_areas`). A texel's
irradiance, relative to the direct sun's E, is the flux it gathered over A.

The patch and the rays
----------------------
The patch is the water along the sun-facing shore: azimuths within π/2 + 2α
of the sun's (α as for the post), and from the highest water line (where the
island stands at the sea's highest crest, inland of the mean one) out to L
metres seawards of the mean water line, L chosen as
:func:`sunset.light.ripples.patch_geometry` chooses it for a post whose top is
the highest point of the band. N sun rays land on a jittered √N × √N grid in
(φ, w), each carrying E sin e times its share r ΔφΔw of the horizontal area.
A ray whose path from the sun crosses the island lands in its shadow; one
that lands where the island stands above the waves at that moment lands on
the island (neither is traced on). The rest reflect and refract as on the
post and are pierced against the island.

Bookkeeping: every ray's flux ends in one account of
:attr:`ShoreTexture.accounts`, which add up to the flux in. Left out: other
islands (in front of this one, or receiving its light), the reflected ray
meeting another wave on its way, and light after two bounces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import RIPPLE_BANDWIDTH_TEXELS, RIPPLE_MAX_RAYS, RIPPLE_MAX_REACH, RIPPLE_SLOPE_SIGMAS, SHORE_INLAND
from ..errors import SunsetError, require_finite, require_int_range
from ..model.sky import spectral_data
from ..vector.pierce import pierce_island
from .fresnel import reflectance, refract
from .ripples import _splat, rms_slope
from .water import absorption, scattering

__all__ = ["ShoreTexture", "trace_shore", "water_line", "radius_at", "smooth_surface", "texel_areas", "shore_lookup",
           "shore_source", "AREA_SUBSAMPLES"]

#: Midpoint-rule points per texel side for the texels' true areas.
AREA_SUBSAMPLES = 8


@dataclass(frozen=True)
class ShoreTexture:
    """The light an island's shore receives from the water, relative to the direct sun's E.

    ``reflected`` (n_w, n_φ): irradiance of the reflected light per true surface area; ``refracted``
    (n_w, n_φ, n_λ): of the refracted light (under water), attenuated, per wavelength of
    :func:`~sunset.model.sky.spectral_data`. ``phi`` (n_φ,) azimuths about the apex and ``w`` (n_w,)
    metres inland of the mean water line are the texel centres; ``area`` (n_w, n_φ) the texels' true
    areas (m²) and ``height`` (n_w, n_φ) the smooth surface's height at their centres (m above mean sea
    level); ``accounts`` the flux of every ray by where it ended (relative to E, m²; refracted ones
    averaged over wavelength).
    """

    island_index: int
    phi: np.ndarray
    w: np.ndarray
    reflected: np.ndarray
    refracted: np.ndarray
    area: np.ndarray
    height: np.ndarray
    accounts: dict
    rays: int
    bandwidth: float
    reach: float


def _quadratic_form(par, phi):
    c, s = np.cos(phi), np.sin(phi)
    return par.e * c * c + par.f * c * s + par.g * s * s


def radius_at(island, phi, z):
    """r(φ, z): the distance from the apex at which the smooth island stands ``z`` m above mean sea level.

    The beach reaches z out to r_b² = (top_b − z)/Q_b(φ); cliff ∩ hill out to r_u² = (top_c − z')/Q_c(φ),
    z' = max(z, c + (z − c)/k) (above the cliff top c the hill's factor k); the island is the union, so
    r = max(r_b, r_u) (0 where neither reaches z).
    """
    phi, z = np.broadcast_arrays(np.asarray(phi, float), np.asarray(z, float))
    ct, k = island.cliff_top, island.hill_factor
    zu = np.maximum(z, ct + (z - ct) / k)
    rb = np.sqrt(np.maximum(island.beach.height - z, 0.0) / _quadratic_form(island.beach, phi))
    ru = np.sqrt(np.maximum(island.cliff.height - zu, 0.0) / _quadratic_form(island.cliff, phi))
    return np.maximum(rb, ru)


def water_line(island, phi):
    """r_w(φ): where the smooth island meets the mean sea level along azimuth φ about its apex, metres."""
    return radius_at(island, phi, 0.0)


def smooth_surface(island, x, y):
    """Height (m above mean sea level) and gradient (gx, gy) of the smooth island (no cosine terms)."""
    dx, dy = np.asarray(x, float) - island.x, np.asarray(y, float) - island.y
    ct, k = island.cliff_top, island.hill_factor
    pc = island.cliff.value(dx, dy)
    hill = pc > ct
    upper = np.where(hill, ct + k * (pc - ct), pc)
    pb = island.beach.value(dx, dy)
    beach = pb >= upper
    cx, cy = island.cliff.gradient(dx, dy)
    bx, by = island.beach.gradient(dx, dy)
    scale = np.where(hill, k, 1.0)
    return (np.where(beach, pb, upper), np.where(beach, bx, scale * cx), np.where(beach, by, scale * cy))


def _points(island, phi, w):
    r = water_line(island, phi) - w
    return island.x + r * np.cos(phi), island.y + r * np.sin(phi), r


def texel_areas(island, phi_edges, w_edges, m: int = AREA_SUBSAMPLES) -> np.ndarray:
    """True areas (n_w, n_φ) of the texels: ∫∫ r √(1 + |∇H|²) dφ dw.

    By the midpoint rule, m² points each.
    """
    dphi, dw = phi_edges[1] - phi_edges[0], w_edges[1] - w_edges[0]
    sub = (np.arange(m) + 0.5) / m
    phi = (phi_edges[:-1, None] + dphi * sub[None, :]).reshape(-1)  # (n_φ m,)
    w = (w_edges[:-1, None] + dw * sub[None, :]).reshape(-1)  # (n_w m,)
    x, y, r = _points(island, phi[None, :], w[:, None])
    _, gx, gy = smooth_surface(island, x, y)
    slope = np.sqrt(1.0 + gx * gx + gy * gy)
    dens = np.maximum(r, 0.0) * slope * (dphi / m) * (dw / m)
    n_w, n_phi = len(w_edges) - 1, len(phi_edges) - 1
    return dens.reshape(n_w, m, n_phi, m).sum(axis=(1, 3))


def _surface_coordinates(island, p):
    phi = np.mod(np.arctan2(p[..., 1] - island.y, p[..., 0] - island.x), 2.0 * math.pi)
    return phi, water_line(island, phi) - np.hypot(p[..., 0] - island.x, p[..., 1] - island.y)


def trace_shore(scene, island_index: int = 0, t: float = 0.0, hours: float = 2.0, rays: int = 1 << 17,
                texels: int = 32, inland: float | None = None, bandwidth: float | None = None,
                seed: int = 0) -> ShoreTexture:
    """Trace sun rays off the water along the sun-facing shore of one island at time ``t``.

    Parameters
    ----------
    scene : Scene
        Its sea, sun and ``islands``.
    island_index : int
        Which island (from 0).
    t : float
        Time, seconds (the waves move).
    hours : float
        Hours before sunset: the sun's direction.
    rays : int
        Sun rays on the patch (1 to :data:`~sunset.constants.RIPPLE_MAX_RAYS`).
    texels : int
        Texels across the band, from L out at sea to ``inland`` metres inland of the mean water line;
        about square at the water line, so about 2π r̄_w/Δw round the island.
    inland : float, optional
        How far inland of the mean water line the band runs, metres (default
        :data:`~sunset.constants.SHORE_INLAND`, at most half the water line's least radius).
    bandwidth : float, optional
        The kernel's radius h, metres (default :data:`~sunset.constants.RIPPLE_BANDWIDTH_TEXELS` texels).
    seed : int
        Seed of the jitter: the same seed gives the same texture.
    """
    if not scene.islands:
        raise SunsetError("the scene has no islands to light")
    require_int_range("island_index", island_index, 0, len(scene.islands) - 1)
    require_finite("t", t)
    require_finite("hours", hours)
    require_int_range("rays", rays, 1, RIPPLE_MAX_RAYS)
    require_int_range("texels", texels, 2, 4096)
    island, sea = scene.islands[island_index], scene.sea
    p = scene.sun.position(float(hours))
    horiz = math.hypot(p[0], p[1])
    if p[2] <= 0.0 or horiz < 1e-9:
        raise SunsetError("the sun must be above the horizon and not overhead to light the shore from the water")
    phi_sun = math.atan2(p[1], p[0])
    ring = np.linspace(0.0, 2.0 * math.pi, 721)[:-1]
    r_min = float(water_line(island, ring).min())
    if r_min <= 0.0:
        raise SunsetError("the island does not reach the sea level: it has no shore")
    far = min(SHORE_INLAND, 0.5 * r_min) if inland is None else float(inland)
    require_finite("inland", far)
    if not 0.0 < far <= 0.9 * r_min:
        raise SunsetError(f"inland must lie in (0, {0.9 * r_min:.4g}] m (short of the apex), got {far!r}")
    # the patch's reach, as for a post whose top is the band's highest point
    e = math.asin(min(1.0, p[2]))
    alpha = math.atan(RIPPLE_SLOPE_SIGMAS * rms_slope(sea))
    spread = min(2.0 * alpha, math.radians(60.0))
    low = max(e - 2.0 * alpha, e / 3.0)
    top = float(smooth_surface(island, *_points(island, ring, far)[:2])[0].max())
    L = min((top + sea.max_elevation) / math.tan(low), RIPPLE_MAX_REACH)
    w_high = water_line(island, ring) - radius_at(island, ring, sea.max_elevation)
    # the texture: w from −L to inland, φ all round
    n_w = int(texels)
    w_edges = np.linspace(-L, far, n_w + 1)
    dw = w_edges[1] - w_edges[0]
    r_bar = float(water_line(island, phi_sun))
    n_phi = max(8, int(round(2.0 * math.pi * r_bar / dw)))
    phi_edges = np.linspace(0.0, 2.0 * math.pi, n_phi + 1)
    h = RIPPLE_BANDWIDTH_TEXELS * dw if bandwidth is None else float(bandwidth)
    require_finite("bandwidth", h)
    if h <= 0:
        raise SunsetError(f"bandwidth must be positive, got {h!r}")
    lam = spectral_data().wavelengths
    c_water = absorption(lam) + scattering(lam)
    # the rays: a jittered grid in (φ, w) over the patch, each with its share r Δφ Δw of the horizontal area
    m = int(math.ceil(math.sqrt(rays)))
    rng = np.random.default_rng(seed)
    k = np.arange(rays)
    a = np.minimum((k // m + rng.random(rays)) / m, 1.0)
    b = np.minimum((k % m + rng.random(rays)) / m, 1.0)
    half = 0.5 * math.pi + spread
    w_in = float(w_high.max())
    phi = phi_sun + (2.0 * a - 1.0) * half
    w = w_in - b * (w_in + L)
    x, y, r = _points(island, phi, w)
    flux = math.sin(e) * r * (2.0 * half / m) * ((w_in + L) / m)          # each ray one cell of the grid
    eta = sea.elevation(x, y, t)
    q = np.stack([x, y, eta], axis=-1)
    d = -p
    shadow = np.isfinite(pierce_island(island, 0.0, q, np.broadcast_to(p, q.shape))[0])
    dry = ~shadow & (smooth_surface(island, x, y)[0] >= eta)
    wet = ~shadow & ~dry
    q, fw = q[wet], flux[wet]
    normal = sea.normal(x[wet], y[wet], t)
    cos_i = np.clip(normal @ p, 0.0, 1.0)
    R = reflectance(cos_i)
    # reflected
    rr = d[None, :] - 2.0 * (normal @ d)[:, None] * normal
    down = rr[:, 2] <= 0.0
    t_r = np.where(down, np.inf, pierce_island(island, 0.0, q, rr)[0])
    hit = np.isfinite(t_r)
    phi_r, w_r = _surface_coordinates(island, q[hit] + t_r[hit, None] * rr[hit])
    band_r = np.zeros(len(q), bool)
    band_r[hit] = (w_r >= w_edges[0]) & (w_r <= w_edges[-1])
    inb = band_r[hit]
    gathered_r = _splat(phi_r[inb], w_r[inb], (R * fw)[band_r], phi_edges, w_edges, r_bar, h)[..., 0]
    # refracted
    tr = refract(np.broadcast_to(d, normal.shape), normal, cos_i)
    t_t = pierce_island(island, 0.0, q, tr)[0]
    hit_t = np.isfinite(t_t)
    phi_t, w_t = _surface_coordinates(island, q[hit_t] + t_t[hit_t, None] * tr[hit_t])
    band_t = np.zeros(len(q), bool)
    band_t[hit_t] = (w_t >= w_edges[0]) & (w_t <= w_edges[-1])
    inb_t = band_t[hit_t]
    att = np.exp(-np.outer(t_t[band_t], c_water))
    transmitted = (1.0 - R) * fw
    wt = transmitted[band_t][:, None] * att
    gathered_t = _splat(phi_t[inb_t], w_t[inb_t], wt, phi_edges, w_edges, r_bar, h)
    area = texel_areas(island, phi_edges, w_edges)
    phi_c, w_c = 0.5 * (phi_edges[1:] + phi_edges[:-1]), 0.5 * (w_edges[1:] + w_edges[:-1])
    height = smooth_surface(island, *_points(island, phi_c[None, :], w_c[:, None])[:2])[0]
    reflected = R * fw
    accounts = {
        "in": float(flux.sum()),
        "in the island's shadow": float(flux[shadow].sum()),
        "fell on the island": float(flux[dry].sum()),
        "reflected onto the shore": float(reflected[band_r].sum()),
        "reflected onto the island beyond the band": float(reflected[hit & ~band_r].sum()),
        "reflected past it": float(reflected[~hit & ~down].sum()),
        "reflected back into the water": float(reflected[down].sum()),
        "refracted onto the shore": float(np.mean(wt.sum(axis=0))),
        "absorbed on the way": float(np.mean((transmitted[band_t][:, None] * (1.0 - att)).sum(axis=0))),
        "refracted elsewhere": float(transmitted[~band_t].sum()),
    }
    return ShoreTexture(island_index=int(island_index), phi=phi_c, w=w_c, reflected=gathered_r / area,
                        refracted=gathered_t / area[..., None], area=area, height=height, accounts=accounts,
                        rays=int(rays), bandwidth=h, reach=float(L))


def shore_lookup(tex: ShoreTexture, island, points) -> np.ndarray:
    """The reflected light's irradiance (relative to the direct sun) at ``points`` (…, 3; z above the sea),
    bilinear in the texture by (φ, w) of their horizontal positions (periodic in φ), 0 outside the band."""
    pts = np.asarray(points, dtype=float)
    out = np.zeros(pts.shape[:-1])
    with np.errstate(invalid="ignore"):
        ok = np.all(np.isfinite(pts), axis=-1)
    if not np.any(ok):
        return out
    phi, w = _surface_coordinates(island, pts[ok])
    dw = tex.w[1] - tex.w[0]
    inside = (w >= tex.w[0] - 0.5 * dw) & (w <= tex.w[-1] + 0.5 * dw)
    n_phi, n_w = len(tex.phi), len(tex.w)
    fi = phi / (2.0 * math.pi) * n_phi - 0.5
    i0 = np.floor(fi).astype(np.int64)
    a = fi - i0
    fj = np.clip((w - tex.w[0]) / dw, 0.0, n_w - 1.0)
    j0 = np.minimum(fj.astype(np.int64), n_w - 2)
    b = fj - j0
    j1 = j0 + 1
    A = tex.reflected
    i0w, i1w = np.mod(i0, n_phi), np.mod(i0 + 1, n_phi)
    val = ((1 - a) * (1 - b) * A[j0, i0w] + a * (1 - b) * A[j0, i1w] + (1 - a) * b * A[j1, i0w]
           + a * b * A[j1, i1w])
    out[ok] = np.where(inside, val, 0.0)
    return out


def shore_source(scene, t: float, hours: float, light, rays: int = 1 << 16, texels: int = 32, seed: int = 0):
    """An extra light source for the RGB back end: the ripples of light on the shores of the scene's islands.

    One texture per island (:func:`trace_shore`); ``source(points, normals, part)`` for
    :attr:`sunset.light.lighting.Lighting.extra_irradiance` adds, at island points of direct rays (eye
    coordinates) inside a band, the texture's irradiance times the part's albedo and the hour's direct sun
    over π (:attr:`~sunset.light.lighting.Lighting.island_direct`), in XYZ. Reflected rays' island points
    (NaN) get nothing.
    """
    textures = [trace_shore(scene, j, t, hours, rays, texels, seed=seed) for j in range(len(scene.islands))]
    lift = np.array([0.0, 0.0, scene.camera.eye_height])
    direct = {code: np.asarray(v, dtype=np.float32) for code, v in light.island_direct.items()}

    def source(points, normals, part):
        out = np.zeros(np.shape(normals), np.float32)
        if points is None or len(points) == 0:
            return out
        pts = np.asarray(points, dtype=float) + lift
        part = np.asarray(part)
        e = np.zeros(len(pts))
        for island, tex in zip(scene.islands, textures):
            e += shore_lookup(tex, island, pts)
        for code, xyz in direct.items():
            sel = part == code
            out[sel] += (e[sel, None] * xyz).astype(np.float32)
        return out

    source.textures = textures
    return source
