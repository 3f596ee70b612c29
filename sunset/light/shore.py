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

The patch and the light
-----------------------
The patch is the water along the sun-facing shore: azimuths within π/2 + 2α
of the sun's (α as for the post), and from the highest water line (where the
island stands at the sea's highest crest, inland of the mean one) out to L
metres seawards of the mean water line, L chosen as
:func:`sunset.light.ripples.patch_geometry` chooses it for a post whose top is
the highest point of the band. Its parameters (a, b) ∈ [0, 1]² are the
azimuth and the distance inland, with the area element J = r 2(π/2 + 2α)(w_in + L).
The tracers of :mod:`sunset.light.caustics` run over it, the beams by default:
at each point the water's light, its shadows, Fresnel's split and the two rays
are :func:`sunset.light.sunrays.sun_points`'s. Water where the island stands
above the waves at that moment is dry land (the light fell on the island);
water whose sun ray crosses an island lies in its shadow. A reflected ray
lands on this island only if no other island stands in its way
(:func:`sunset.vector.pierce.pierce_islands` over all of them: the nearest
is the one it meets); a refracted ray lands on this island's sea bed. As on
the post, the crests' and the islands' shadows are looked for only where a
ray lands.

Bookkeeping: every ray's flux ends in one account of
:attr:`ShoreTexture.accounts`, which add up to the flux in. Left out: the
reflected ray meeting another wave on its way, and light after two bounces.

The owner of a point
--------------------
:func:`shore_source` lights the points of the RGB back end's direct rays that
lie on an island with that island's texture only: the point belongs to the
island whose surface (with its cosine terms) is nearest above or below it,
within :data:`OWNER_TOLERANCE`. A band's coordinates (φ, w) reach 80 m and
more out to sea, over the water in front of another island, and a point of
that island there is not on this one's shore.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import (RIPPLE_MAX_RAYS, RIPPLE_MAX_REACH, RIPPLE_SLOPE_SIGMAS,
                         SHORE_CELL, SHORE_INLAND, SHORE_MESH, SHORE_MIN_TEXELS, SHORE_TEXEL_CELLS,
                         SHORE_TEXEL_PIXELS, SHORE_TEXELS)
from ..errors import SunsetError, require_finite, require_int_range
from ..model.sky import spectral_data
from ..vector.pierce import pierce_island, pierce_islands
from .caustics import LIT, Nodes, trace_photons
from .postrays import rms_slope
from .ripples import METHODS, _splat, beams_on, histogram, photon_bandwidth
from .sunrays import in_shadow, sea_table, sun_points
from .water import absorption, scattering

__all__ = ["ShoreTexture", "ShoreReceiver", "trace_shore", "water_line", "radius_at", "smooth_surface", "texel_areas",
           "shore_lookup", "owner", "shore_source", "frame_texels", "AREA_SUBSAMPLES", "OWNER_TOLERANCE"]

#: Midpoint-rule points per texel side for the texels' true areas.
AREA_SUBSAMPLES = 8
#: How far (m, vertically) a point may lie from an island's surface and still be that island's (:func:`owner`).
OWNER_TOLERANCE = 0.5


@dataclass(frozen=True)
class ShoreTexture:
    """The light an island's shore receives from the water, relative to the direct sun's E.

    ``reflected`` (n_w, n_φ): irradiance of the reflected light per true surface area; ``refracted``
    (n_w, n_φ, n_λ): of the refracted light (under water), attenuated, per wavelength of
    :func:`~sunset.model.sky.spectral_data`. ``phi`` (n_φ,) azimuths about the apex and ``w`` (n_w,)
    metres inland of the mean water line are the texel centres; ``area`` (n_w, n_φ) the texels' true
    areas (m²) and ``height`` (n_w, n_φ) the smooth surface's height at their centres (m above mean sea
    level); ``accounts`` the flux of every ray by where it ended (relative to E, m²; refracted ones
    averaged over wavelength). ``method``, ``cell``, ``rays`` and ``bandwidth`` as for
    :class:`~sunset.light.ripples.RippleTexture`; ``reach`` the patch's L, m.
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
    method: str = "beams"
    cell: float = 0.0


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


class ShoreReceiver:
    """One island's shore and the water along it for :mod:`sunset.light.caustics` (module docstring)."""

    dark_names = {1: "in the waves' shadow", 2: "fell on the island", 3: "in an island's shadow"}
    reflected_names = {0: "reflected onto the shore", 1: "reflected past it", 2: "reflected back into the water",
                       3: "reflected onto another island"}
    refracted_names = {0: "refracted onto the shore", 1: "refracted elsewhere"}
    reflected_clipped = "reflected onto the island beyond the band"
    refracted_clipped = "refracted elsewhere"

    def __init__(self, scene, island_index: int, t: float, hours: float, texels: int, inland, shadows: bool = True,
                 refracted: bool = True):
        island, sea = scene.islands[island_index], scene.sea
        self.islands, self.island, self.index, self.shadows = scene.islands, island, island_index, shadows
        self.refracted = refracted
        if not refracted:
            self.refracted_names = {0: "refracted onto the shore", 1: "refracted into the sea (not traced)"}
        p = self.p = scene.sun.position(float(hours))
        if p[2] <= 0.0 or math.hypot(p[0], p[1]) < 1e-9:
            raise SunsetError("the sun must be above the horizon and not overhead to light the shore from the water")
        self.phi_sun = math.atan2(p[1], p[0])
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
        low = max(e - 2.0 * alpha, e / 3.0)
        top = float(smooth_surface(island, *_points(island, ring, far)[:2])[0].max())
        self.L = min((top + sea.max_elevation) / math.tan(low), RIPPLE_MAX_REACH)
        self.half = 0.5 * math.pi + min(2.0 * alpha, math.radians(60.0))
        self.w_in = float((water_line(island, ring) - radius_at(island, ring, sea.max_elevation)).max())
        self.w_edges = np.linspace(-self.L, far, texels + 1)
        dw = self.w_edges[1] - self.w_edges[0]
        self.r_bar = float(water_line(island, self.phi_sun))
        n_phi = max(8, int(round(2.0 * math.pi * self.r_bar / dw)))
        self.phi_edges = np.linspace(0.0, 2.0 * math.pi, n_phi + 1)
        lam = spectral_data().wavelengths
        self.attenuation = absorption(lam) + scattering(lam)
        self.shape_reflected = (texels, n_phi)
        self.shape_refracted = (texels, n_phi, len(lam))
        self.table = sea_table(sea, t)

    @property
    def area(self) -> float:
        """The patch's horizontal area, m² (∫∫ J da db by the midpoint rule in a)."""
        a = (np.arange(256) + 0.5) / 256
        phi = self.phi_sun + (2.0 * a - 1.0) * self.half
        r_out = water_line(self.island, phi) + 0.5 * (self.L - self.w_in)
        return float(np.mean(r_out) * 2.0 * self.half * (self.w_in + self.L))

    def _coordinates(self, hit):
        phi, w = _surface_coordinates(self.island, hit)
        dphi, dw = self.phi_edges[1] - self.phi_edges[0], self.w_edges[1] - self.w_edges[0]
        return phi / dphi, (w - self.w_edges[0]) / dw

    def _glance(self, hit, d):
        _, gx, gy = smooth_surface(self.island, hit[:, 0], hit[:, 1])
        return (gx * d[:, 0] + gy * d[:, 1] - d[:, 2]) / np.sqrt(1.0 + gx * gx + gy * gy)

    def evaluate(self, a, b) -> Nodes:
        a, b = np.asarray(a, float), np.asarray(b, float)
        island, p = self.island, self.p
        phi = self.phi_sun + (2.0 * a - 1.0) * self.half
        w = self.w_in - b * (self.w_in + self.L)
        x, y, r = _points(island, phi, w)
        sp = sun_points(self.table, x, y, p)
        q = sp.q
        dry = smooth_surface(island, x, y)[0] >= q[:, 2]
        down = sp.reflected[:, 2] <= 0.0
        t_r, which, _ = pierce_islands(self.islands, 0.0, q, np.where(down[:, None], [0.0, 0.0, 1.0], sp.reflected))
        code_r = np.where(down, 2, np.where(~np.isfinite(t_r), 1, np.where(which == self.index + 1, 0, 3)))
        t_t = pierce_island(island, 0.0, q, sp.refracted)[0] if self.refracted else np.full(len(a), np.inf)
        code_t = np.where(np.isfinite(t_t), 0, 1)
        lands = ~dry & ((code_r == 0) | (code_t == 0))
        dark = np.zeros(len(a), np.int64)
        dark[dry] = 2
        sel = np.flatnonzero(lands)
        if sel.size:                       # the islands' and the crests' shadows where light lands
            behind = np.isfinite(pierce_islands(self.islands, 0.0, q[sel], np.broadcast_to(p, (sel.size, 3)))[0])
            dark[sel[behind]] = 3
            waves = in_shadow(self.table, x, y, q[:, 2], sp.omega, p, lands & (dark == 0) & self.shadows)
            dark[lands & (dark == 0) & waves] = 1
        status = np.where(dark > 0, dark, LIT + 10 * code_r + code_t)
        on_r, on_t = (status >= LIT) & (code_r == 0), (status >= LIT) & (code_t == 0)
        ur, vr, ut, vt = (np.full(len(a), np.nan) for _ in range(4))
        path, glance = np.zeros(len(a)), np.ones(len(a))
        if np.any(on_r):
            hit = q[on_r] + t_r[on_r, None] * sp.reflected[on_r]
            ur[on_r], vr[on_r] = self._coordinates(hit)
            glance[on_r] = self._glance(hit, sp.reflected[on_r])
        if np.any(on_t):
            hit = q[on_t] + t_t[on_t, None] * sp.refracted[on_t]
            ut[on_t], vt[on_t] = self._coordinates(hit)
            glance[on_t] = np.minimum(glance[on_t], self._glance(hit, sp.refracted[on_t]))
            path[on_t] = t_t[on_t]
        flux = sp.omega * r * 2.0 * self.half * (self.w_in + self.L)
        return Nodes(a, b, status.astype(np.int64), flux, sp.R, ur, vr, ut, vt, path, glance)


def trace_shore(scene, island_index: int = 0, t: float = 0.0, hours: float = 2.0, *, method: str = "beams",
                cell: float | None = None, rays: int = 1 << 17, texels: int = 32, inland: float | None = None,
                bandwidth: float | None = None, seed: int = 0, shadows: bool = True, refine: int = 0,
                refracted: bool = True) -> ShoreTexture:
    """Trace the sunlight off the water along the sun-facing shore of one island at time ``t``.

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
    method : {"beams", "photons"}
        The density estimate (:mod:`sunset.light.ripples`).
    cell : float, optional
        Beams: the side of a cell of the mesh on the water, metres (by default
        :data:`~sunset.constants.SHORE_CELL`, or larger where the patch would need more than
        :data:`~sunset.constants.SHORE_MESH` corners or a texel's height would hold more than
        :data:`~sunset.constants.SHORE_TEXEL_CELLS` cells).
    rays : int
        Photons: how many (1 to :data:`~sunset.constants.RIPPLE_MAX_RAYS`).
    texels : int
        Texels across the band, from L out at sea to ``inland`` metres inland of the mean water line;
        about square at the water line, so about 2π r̄_w/Δw round the island.
    inland : float, optional
        How far inland of the mean water line the band runs, metres (default
        :data:`~sunset.constants.SHORE_INLAND`, at most half the water line's least radius).
    bandwidth : float, optional
        Photons: the kernel's radius h, metres (default :data:`~sunset.constants.RIPPLE_BANDWIDTH_TEXELS`
        texels; 0: a histogram).
    seed : int
        Photons: the seed of their jittered grid.
    shadows : bool
        Whether crests shadow the water behind them.
    refine : int
        Beams: halvings of the beams that land at a glance (0 to :data:`~sunset.light.caustics.MAX_REFINE`).
    refracted : bool
        Whether to trace the refracted light onto the sea bed (False: it is booked as going into the sea, and
        the ``refracted`` texture is 0, a read-only view that holds no memory; the RGB back end shows the
        reflected light alone).
    """
    if not scene.islands:
        raise SunsetError("the scene has no islands to light")
    require_int_range("island_index", island_index, 0, len(scene.islands) - 1)
    require_finite("t", t)
    require_finite("hours", hours)
    if method not in METHODS:
        raise SunsetError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    require_int_range("texels", texels, 2, 4096)
    receiver = ShoreReceiver(scene, island_index, float(t), float(hours), int(texels), inland, bool(shadows),
                             bool(refracted))
    phi_edges, w_edges = receiver.phi_edges, receiver.w_edges
    dw = w_edges[1] - w_edges[0]
    h = 0.0
    if method == "beams":
        if cell is None:
            cell = max(SHORE_CELL, math.sqrt(receiver.area / SHORE_MESH), dw / SHORE_TEXEL_CELLS)
        arc = 2.0 * receiver.half * receiver.r_bar
        books, rays = beams_on(receiver, arc, receiver.w_in + receiver.L, cell, refine)
    else:
        require_int_range("rays", rays, 1, RIPPLE_MAX_RAYS)
        h = photon_bandwidth(bandwidth, dw)

        def splat(u, v, flux, shape):
            if h == 0:
                return histogram(u, v, flux, shape)
            return _splat(np.mod(u * (phi_edges[1] - phi_edges[0]), 2.0 * math.pi), w_edges[0] + v * dw, flux,
                          phi_edges, w_edges, receiver.r_bar, h)

        books = trace_photons(receiver, int(rays), int(seed), splat)
    area = texel_areas(receiver.island, phi_edges, w_edges)
    phi_c, w_c = 0.5 * (phi_edges[1:] + phi_edges[:-1]), 0.5 * (w_edges[1:] + w_edges[:-1])
    height = smooth_surface(receiver.island, *_points(receiver.island, phi_c[None, :], w_c[:, None])[:2])[0]
    # untraced refracted light: a zero view that holds no memory (a film keeps a light's textures per frame)
    refracted = (books.refracted / area[..., None] if receiver.refracted
                 else np.broadcast_to(np.zeros((1, 1, 1)), books.refracted.shape))
    return ShoreTexture(island_index=int(island_index), phi=phi_c, w=w_c, reflected=books.reflected / area,
                        refracted=refracted, area=area, height=height,
                        accounts=books.accounts, rays=int(rays), bandwidth=h, reach=float(receiver.L), method=method,
                        cell=float(cell) if method == "beams" else 0.0)


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


def owner(islands, points) -> np.ndarray:
    """The island (0-based, −1 for none) each point (…, 3; z above the sea) lies on: the one whose surface, with its
    cosine terms, is nearest above or below it, within :data:`OWNER_TOLERANCE` metres."""
    pts = np.asarray(points, dtype=float)
    best = np.full(pts.shape[:-1], np.inf)
    out = np.full(pts.shape[:-1], -1, np.int64)
    for k, island in enumerate(islands):
        with np.errstate(invalid="ignore"):
            gap = np.abs(island.height(pts[..., 0], pts[..., 1]) - pts[..., 2])
            nearer = (gap < best) & (gap <= OWNER_TOLERANCE)
        out = np.where(nearer, k, out)
        best = np.where(nearer, gap, best)
    return out


def frame_texels(scene, island_index: int) -> int:
    """Texels across an island's band for a frame of ``scene``'s camera: a texel about
    :data:`~sunset.constants.SHORE_TEXEL_PIXELS` pixels across at the island's water line nearest the eye (the band
    taken as its longest, :data:`~sunset.constants.RIPPLE_MAX_REACH` + :data:`~sunset.constants.SHORE_INLAND`),
    between :data:`~sunset.constants.SHORE_MIN_TEXELS` and :data:`~sunset.constants.SHORE_TEXELS`. A finer texture
    than the picture resolves would cost beams and show nothing more."""
    island, cam = scene.islands[island_index], scene.camera
    ring = np.linspace(0.0, 2.0 * math.pi, 721)[:-1]
    x, y, _ = _points(island, ring, 0.0)
    metres = SHORE_TEXEL_PIXELS * float(np.hypot(x, y).min()) * max(cam.pixel_pitch)
    band = RIPPLE_MAX_REACH + SHORE_INLAND
    return int(np.clip(math.ceil(band / max(metres, 1e-9)), SHORE_MIN_TEXELS, SHORE_TEXELS))


def shore_source(scene, t: float, hours: float, light, texels: int | None = None, cell: float | None = None):
    """An extra light source for the RGB back end: the ripples of light on the shores of the scene's islands.

    One texture per island (:func:`trace_shore`, beams; by default of :func:`frame_texels` texels across, its
    beams' cell a fifth of a texel's height or more); ``source(points, normals, part)`` for
    :attr:`sunset.light.lighting.Lighting.extra_irradiance` adds, at island points of direct rays (eye
    coordinates) inside a band and on that band's own island (:func:`owner`), the texture's irradiance times
    the part's albedo and the hour's direct sun over π (:attr:`~sunset.light.lighting.Lighting.island_direct`),
    in XYZ. Reflected rays' island points (NaN) get nothing.
    """
    textures = [trace_shore(scene, j, t, hours, texels=frame_texels(scene, j) if texels is None else texels, cell=cell,
                            refracted=False) for j in range(len(scene.islands))]
    lift = np.array([0.0, 0.0, scene.camera.eye_height])
    direct = {code: np.asarray(v, dtype=np.float32) for code, v in light.island_direct.items()}

    def source(points, normals, part):
        out = np.zeros(np.shape(normals), np.float32)
        if points is None or len(points) == 0:
            return out
        pts = np.asarray(points, dtype=float) + lift
        part = np.asarray(part)
        mine = owner(scene.islands, pts)
        e = np.zeros(len(pts))
        for k, (island, tex) in enumerate(zip(scene.islands, textures)):
            on = mine == k
            if np.any(on):
                e[on] += shore_lookup(tex, island, pts[on])
        for code, xyz in direct.items():
            sel = part == code
            out[sel] += (e[sel, None] * xyz).astype(np.float32)
        return out

    source.textures = textures
    return source
