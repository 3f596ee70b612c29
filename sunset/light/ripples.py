"""Ripples of light: sunlight reflected and refracted by the waves, gathered on a post (light tracing).

The paper's second proposal: "trace a family of sun rays meeting a small patch
of water, and then trace the reflected and refracted rays until they pierce a
small object extending above and below the water line", and average them
into an array over the object's surface. This module does exactly that, for a
:class:`~sunset.model.posts.Post`.

The patch and the rays
----------------------
Light reflected off the water travels on away from the sun, so only water on
the sun's side of the post can light it. The patch is the rectangle that
starts at the post's axis and runs L metres towards the sun (horizontally),
2W wide: L is where a ray reflected at elevation max(e − 2α, e/3) would pass
over the post's top, α = atan(k σ_s) with σ_s the sea's rms slope
(:func:`rms_slope`) and k = :data:`~sunset.constants.RIPPLE_SLOPE_SIGMAS`,
capped at :data:`~sunset.constants.RIPPLE_MAX_REACH`; W = ρ + L tan 2α covers
the sideways spread. Light reflected from farther (off facets steeper than
kσ_s, arriving lower than that elevation) is not traced: the patch is where
nearly all of it comes from, not all. N sun rays (direction −P) fall on it at the points of a
jittered √N × √N grid; each carries the flux E sin(e) A/N through the
horizontal (E the direct sun's normal irradiance, A the patch's area), exact
for a parallel beam whatever the local tilt of the water. Rays that land
inside the post's own circle are blocked by it.

At each point the wave's normal N gives cos i = P·N, Fresnel's R(cos i)
(:mod:`sunset.light.fresnel`), the reflected ray r = d − 2(d·N)N carrying R of
the flux, and the refracted ray (Snell) carrying 1 − R, attenuated on its way
down by the clear sea water, exp(−c(λ) s) with c = a + b
(:mod:`sunset.light.water`). Both are pierced against the post's side
(:meth:`~sunset.model.posts.Post.pierce`).

Density estimation
------------------
A hit at (φ, z) on the side spreads its flux over the texels of the post's
texture (azimuth φ of the side's normal × height z) with the Epanechnikov
kernel K(d) ∝ 1 − (d/h)² of the arc distance d = √((ρΔφ)² + Δz²), h the
bandwidth in metres; the kernel's weights are normalised over the texels it
reaches (wrapping round in φ, cut at the ends in z), so every hit's flux lands
in the texture whole. Irradiance is a texel's flux over its area ρΔφΔz,
relative to E.

Bookkeeping
-----------
Every ray's flux ends in exactly one account: blocked by the post, reflected
onto the post (gathered), reflected past it (missed), reflected back down into
the water (a low sun on a steep facet; not traced on), refracted onto the post
(gathered, after the water took its share: absorbed), refracted past it
(into the deep). :attr:`RippleTexture.accounts` holds them; they add up to the
flux in.

What is left out: the reflected ray meeting another wave before the post, and
light reaching the post after two reflections or from the sky; the post's
shadow on the water (it lies on the far side, away from the patch).

In the RGB back end
-------------------
:func:`ripple_source` turns the textures into an extra light source of a
:class:`~sunset.light.lighting.Lighting`: the reflected light's irradiance
(relative to the direct sun) times the wood's albedo and the direct sun of the
hour, added where a direct ray meets a post's side. Under water the post is
only seen through the waves, which the vector stage does not trace, so the
refracted texture is shown in the figures, not in the frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import RIPPLE_BANDWIDTH_TEXELS, RIPPLE_MAX_RAYS, RIPPLE_MAX_REACH, RIPPLE_SLOPE_SIGMAS
from ..errors import SunsetError, require_finite, require_int_range
from ..kernels import twin
from ..model.sky import spectral_data
from .fresnel import reflectance, refract
from .water import absorption, scattering

__all__ = ["RippleTexture", "trace_ripples", "patch_geometry", "rms_slope", "texture_lookup", "ripple_source"]


@dataclass(frozen=True)
class RippleTexture:
    """The light a post receives from the water, as irradiance over its side, relative to the direct sun's E.

    ``above`` (n_z, n_φ): reflected light, the same at every wavelength (Fresnel's R barely depends on λ);
    ``below`` (n_zb, n_φ, n_λ): refracted light under water, attenuated by the water, per wavelength of
    :func:`~sunset.model.sky.spectral_data`. ``phi`` (n_φ,), ``z`` (n_z,) and ``z_below`` (n_zb,) are the
    texel centres; ``accounts`` the flux of every ray by where it ended (relative to E, m²; the refracted
    ones per wavelength, averaged).
    """

    phi: np.ndarray
    z: np.ndarray
    z_below: np.ndarray
    above: np.ndarray
    below: np.ndarray
    accounts: dict
    rays: int
    bandwidth: float


def rms_slope(sea) -> float:
    """The sea's root-mean-square slope, √(Σ over trains and harmonics of (a_n n k)²/2)."""
    total = 0.0
    for train in sea.trains:
        amps = train.harmonic_amplitudes()
        total += float(np.sum((amps * np.arange(1, len(amps) + 1) * train.k) ** 2)) / 2.0
    return math.sqrt(total)


def patch_geometry(post, sea, sun_dir) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(towards the sun, across, L, W): the patch's horizontal unit vectors and its length and half-width, metres."""
    p = np.asarray(sun_dir, dtype=float)
    horiz = math.hypot(p[0], p[1])
    if p[2] <= 0.0 or horiz < 1e-9:
        raise SunsetError("the sun must be above the horizon and not overhead to light a post from the water")
    toward = np.array([p[0], p[1], 0.0]) / horiz
    across = np.array([-toward[1], toward[0], 0.0])
    e = math.asin(min(1.0, p[2]))
    alpha = math.atan(RIPPLE_SLOPE_SIGMAS * rms_slope(sea))
    low = max(e - 2.0 * alpha, e / 3.0)
    reach = (post.top + sea.max_elevation) / math.tan(low)
    L = min(post.radius + reach, RIPPLE_MAX_REACH)
    W = post.radius + L * math.tan(min(2.0 * alpha, math.radians(60.0)))
    return toward, across, L, W


@twin("sunset.light.ripples_numba")
def _splat(phi, z, weight, phi_edges, z_edges, radius: float, h: float) -> np.ndarray:
    """Spread each hit's weight (hits, channels) over the texels with the normalised Epanechnikov kernel."""
    import scipy.sparse

    n_phi, n_z = len(phi_edges) - 1, len(z_edges) - 1
    dphi, dz = phi_edges[1] - phi_edges[0], z_edges[1] - z_edges[0]
    weight = weight.reshape(len(phi), math.prod(weight.shape[1:]))     # (hits, channels), also for no hits
    if len(phi) == 0:
        return np.zeros((n_z, n_phi, weight.shape[1]))
    i0 = np.floor(phi / dphi).astype(np.int64)
    j0 = np.floor((z - z_edges[0]) / dz).astype(np.int64)
    mi = int(math.ceil(h / (radius * dphi))) + 1
    mj = int(math.ceil(h / dz)) + 1
    di, dj = np.meshgrid(np.arange(-mi, mi + 1), np.arange(-mj, mj + 1), indexing="ij")
    i = i0[None, :] + di.reshape(-1, 1)                        # (stencil, hits)
    j = j0[None, :] + dj.reshape(-1, 1)
    dp = ((i + 0.5) * dphi - phi[None, :]) * radius
    dzz = z_edges[0] + (j + 0.5) * dz - z[None, :]
    ker = np.maximum(1.0 - (dp * dp + dzz * dzz) / (h * h), 0.0)
    ker = np.where((j >= 0) & (j < n_z), ker, 0.0)
    total = ker.sum(axis=0)
    ok = total > 0
    ker = ker / np.where(ok, total, 1.0)
    # a hit whose kernel reaches no texel (off the texture's ends) lands whole in the nearest texel
    ker[(mi * (2 * mj + 1) + mj), ~ok] = 1.0
    jc = np.where(ok[None, :], j, j0[None, :])
    flat = np.clip(jc, 0, n_z - 1) * n_phi + np.mod(i, n_phi)
    hits = np.broadcast_to(np.arange(len(phi)), flat.shape)
    keep = ker > 0
    m = scipy.sparse.csr_matrix((ker[keep], (flat[keep], hits[keep])), shape=(n_z * n_phi, len(phi)))
    return np.asarray(m @ weight).reshape(n_z, n_phi, -1)


def trace_ripples(scene, post_index: int = 0, t: float = 0.0, hours: float = 2.0, rays: int = 1 << 18,
                  texels: int = 48, bandwidth: float | None = None, seed: int = 0) -> RippleTexture:
    """Trace sun rays off a patch of water onto one post of ``scene`` at time ``t`` (the sun ``hours`` before sunset).

    Parameters
    ----------
    scene : Scene
        Its sea, sun and ``posts``.
    post_index : int
        Which post (from 0).
    t : float
        Time, seconds (the waves move).
    hours : float
        Hours before sunset: the sun's direction.
    rays : int
        Sun rays on the patch (1 to :data:`~sunset.constants.RIPPLE_MAX_RAYS`).
    texels : int
        Texels up the post's height above the water; they are square, so there are about 2πρ/Δz around
        it, and under water as many per metre.
    bandwidth : float, optional
        The kernel's radius h, metres (default :data:`~sunset.constants.RIPPLE_BANDWIDTH_TEXELS` texel heights).
    seed : int
        Seed of the jitter: the same seed gives the same texture.
    """
    require_int_range("post_index", post_index, 0, max(len(scene.posts) - 1, 0))
    if not scene.posts:
        raise SunsetError("the scene has no posts to light")
    require_finite("t", t)
    require_finite("hours", hours)
    require_int_range("rays", rays, 1, RIPPLE_MAX_RAYS)
    require_int_range("texels", texels, 2, 4096)
    n_z = int(texels)
    post, sea = scene.posts[post_index], scene.sea
    p = scene.sun.position(float(hours))
    toward, across, L, W = patch_geometry(post, sea, p)
    d = -p
    z_lo = -sea.max_elevation
    z_edges = np.linspace(z_lo, post.top, n_z + 1)
    dz = z_edges[1] - z_edges[0]
    n_phi = max(8, int(round(2.0 * math.pi * post.radius / dz)))
    n_zb = max(1, int(math.ceil(post.depth / dz))) if post.depth > 0 else 1
    zb_edges = np.linspace(-max(post.depth, dz), 0.0, n_zb + 1)
    phi_edges = np.linspace(0.0, 2.0 * math.pi, n_phi + 1)
    h = RIPPLE_BANDWIDTH_TEXELS * dz if bandwidth is None else float(bandwidth)
    require_finite("bandwidth", h)
    if h <= 0:
        raise SunsetError(f"bandwidth must be positive, got {h!r}")
    lam = spectral_data().wavelengths
    c_water = absorption(lam) + scattering(lam)                        # beam attenuation, m⁻¹
    area = L * 2.0 * W
    # per ray, relative to E
    flux = math.sin(math.asin(min(1.0, p[2]))) * area / rays
    # the jittered grid on the patch: along ∈ [0, L] towards the sun,
    # lateral ∈ [−W, W]
    m = int(math.ceil(math.sqrt(rays)))
    rng = np.random.default_rng(seed)
    k = np.arange(rays)
    a = (k // m + rng.random(rays)) / m
    b = (k % m + rng.random(rays)) / m
    a = np.minimum(a, 1.0)
    x = post.x + toward[0] * a * L + across[0] * (2.0 * b - 1.0) * W
    y = post.y + toward[1] * a * L + across[1] * (2.0 * b - 1.0) * W
    blocked = np.hypot(x - post.x, y - post.y) <= post.radius
    x, y = x[~blocked], y[~blocked]
    q = np.stack([x, y, sea.elevation(x, y, t)], axis=-1)
    normal = sea.normal(x, y, t)
    cos_i = np.clip(normal @ p, 0.0, 1.0)
    R = reflectance(cos_i)
    r = d[None, :] - 2.0 * (normal @ d)[:, None] * normal
    # reflected rays; one that heads down (a low sun on a steep facet) meets the
    # water again: not traced on
    down = r[:, 2] <= 0.0
    t_r = np.where(down, np.inf, post.pierce(q, r))
    hit_r = np.isfinite(t_r)
    pr = q[hit_r] + t_r[hit_r, None] * r[hit_r]
    phi_r, z_r = post.surface_coordinates(pr)
    above = _splat(phi_r, z_r, R[hit_r] * flux, phi_edges, z_edges, post.radius,
                   h)[..., 0]
    # refracted rays
    tr = refract(np.broadcast_to(d, normal.shape), normal, cos_i)
    t_t = post.pierce(q, tr)
    pt = q + np.where(np.isfinite(t_t), t_t, 0.0)[:, None] * tr
    hit_t = np.isfinite(t_t) & (pt[:, 2] <= 0.0)
    att = np.exp(-np.outer(t_t[hit_t], c_water))                       # (hits, n_λ)
    phi_t, z_t = post.surface_coordinates(pt[hit_t])
    wt = ((1.0 - R[hit_t]) * flux)[:, None] * att
    below = _splat(phi_t, z_t, wt, phi_edges, zb_edges, post.radius, h)
    texel_area = post.radius * (phi_edges[1] - phi_edges[0]) * dz
    texel_area_b = post.radius * (phi_edges[1] - phi_edges[0]) * (zb_edges[1] - zb_edges[0])
    transmitted = (1.0 - R) * flux
    accounts = {
        "in": rays * flux,
        "blocked": float(blocked.sum()) * flux,
        "reflected onto the post": float(np.sum(R[hit_r]) * flux),
        "reflected past it": float(np.sum(R[~hit_r & ~down]) * flux),
        "reflected back into the water": float(np.sum(R[down]) * flux),
        "refracted onto the post": float(np.mean(wt.sum(axis=0))),
        "absorbed on the way": float(np.mean((transmitted[hit_t][:, None] * (1.0 - att)).sum(axis=0))),
        "refracted past it": float(np.sum(transmitted[~hit_t])),
    }
    return RippleTexture(
        phi=0.5 * (phi_edges[1:] + phi_edges[:-1]), z=0.5 * (z_edges[1:] + z_edges[:-1]),
        z_below=0.5 * (zb_edges[1:] + zb_edges[:-1]), above=above / texel_area, below=below / texel_area_b,
        accounts=accounts, rays=int(rays), bandwidth=h)


def texture_lookup(tex: RippleTexture, post, points) -> np.ndarray:
    """The reflected light's irradiance (relative to the direct sun) at ``points`` (…, 3, z above the sea) on
    the post's side, bilinear in the texture (periodic in φ); 0 off the side or below the texture."""
    p = np.asarray(points, dtype=float)
    r = np.hypot(p[..., 0] - post.x, p[..., 1] - post.y)
    dz = tex.z[1] - tex.z[0]
    with np.errstate(invalid="ignore"):
        on = (np.abs(r - post.radius) <= 1e-3 * post.radius + 1e-4) & (p[..., 2] >= tex.z[0] - 0.5 * dz) \
            & (p[..., 2] <= tex.z[-1] + 0.5 * dz)
    out = np.zeros(p.shape[:-1])
    if not np.any(on):
        return out
    phi, z = post.surface_coordinates(p[on])
    n_phi = len(tex.phi)
    fi = phi / (2.0 * math.pi) * n_phi - 0.5
    i0 = np.floor(fi).astype(np.int64)
    a = fi - i0
    fj = np.clip((z - tex.z[0]) / dz, 0.0, len(tex.z) - 1.0)
    j0 = np.minimum(fj.astype(np.int64), len(tex.z) - 2) if len(tex.z) > 1 else np.zeros_like(i0)
    b = fj - j0
    j1 = np.minimum(j0 + 1, len(tex.z) - 1)
    A = tex.above
    i0w, i1w = np.mod(i0, n_phi), np.mod(i0 + 1, n_phi)
    out[on] = ((1 - a) * (1 - b) * A[j0, i0w] + a * (1 - b) * A[j0, i1w]
               + (1 - a) * b * A[j1, i0w] + a * b * A[j1, i1w])
    return out


def ripple_source(scene, t: float, hours: float, light, rays: int = 1 << 17, texels: int = 48, seed: int = 0):
    """An extra light source for the RGB back end: the ripples of light on the scene's posts at time ``t``.

    Traces one texture per post (:func:`trace_ripples`) and returns
    ``source(points, normals, part)`` for :attr:`sunset.light.lighting.Lighting.extra_irradiance`:
    at island points that lie on a post's side (direct rays; the points in
    eye coordinates), the texture's irradiance times the wood's albedo and the
    direct sun of the hour over π, in XYZ.
    """
    from ..constants import PART_CLIFF

    textures = [trace_ripples(scene, j, t, hours, rays, texels, seed=seed) for j in range(len(scene.posts))]
    lift = np.array([0.0, 0.0, scene.camera.eye_height])
    wood = np.asarray(light.island_direct[PART_CLIFF], dtype=np.float32)

    def source(points, normals, part):
        out = np.zeros(np.shape(normals), np.float32)
        if points is None or len(points) == 0:
            return out
        p = np.asarray(points, dtype=float) + lift
        for post, tex in zip(scene.posts, textures):
            e = texture_lookup(tex, post, p)
            out += (e[:, None] * wood).astype(np.float32)
        return out

    source.textures = textures
    return source
