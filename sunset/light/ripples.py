"""Ripples of light: sunlight reflected and refracted by the waves onto a post, by beams and by photons.

The paper's second proposal: "trace a family of sun rays meeting a small patch
of water, and then trace the reflected and refracted rays until they pierce a
small object extending above and below the water line", and average them
into an array over the object's surface. This module does that for a
:class:`~sunset.model.posts.Post`, two ways: as a mesh of beams, each spread
over the polygon where it lands (:func:`sunset.light.caustics.trace_beams`,
the default: sharp caustics without noise), and as photons, each a point
spread by a kernel or counted in its texel (:func:`trace_photons`, kept as
the independent check). Both follow the same rays and keep the same books;
only the density estimate differs.

The patch
---------
Light reflected off the water travels on away from the sun, so only water on
the sun's side of the post can light it. The patch is the rectangle that
starts at the post's axis and runs L metres towards the sun (horizontally),
2W wide: L is where a ray reflected at elevation max(e − 2α, e/3) would pass
over the post's top, α = atan(k σ_s) with σ_s the sea's rms slope
(:func:`rms_slope`) and k = :data:`~sunset.constants.RIPPLE_SLOPE_SIGMAS`,
capped at :data:`~sunset.constants.RIPPLE_MAX_REACH`; W = ρ + L tan 2α covers
the sideways spread. Light reflected from farther (off facets steeper than
kσ_s, arriving lower than that elevation) is not traced: the patch is where
nearly all of it comes from, not all. Its parameters (a, b) ∈ [0, 1]² are the
distance towards the sun aL and across (2b − 1)W, area element J = 2WL.

The water's light and the post
------------------------------
At each point (x, y) of the patch the sunlight's flux, its shadows, Fresnel's
split and the two rays are :func:`sunset.light.sunrays.sun_points`'s. Water
inside the post's circle is under the post (the sun ray meets the post, not
the water). Each ray is pierced against the post's side extended up and down
(:func:`sunset.light.postrays.post_rays`): the landing point's texture coordinates are the azimuth φ of
the side's normal and the height z; light landing above the post's top (or
below its foot) is booked as passing it, by the texture's rows. The refracted
light is attenuated on its way by the clear sea water, e^(−c(λ)s) with
c = a + b (:mod:`sunset.light.water`), per wavelength of
:func:`~sunset.model.sky.spectral_data`.

Irradiance is a texel's flux over its area ρΔφΔz, relative to E: ``above``
(n_z, n_φ) for the reflected light from z = −d to the top (d the sea's
highest crest), ``below`` (n_zb, n_φ, n_λ) for the refracted light from the
post's foot to z = d.

Books: every ray's flux ends in exactly one account of
:attr:`RippleTexture.accounts`, which add up to ``in``. What is left out:
the reflected ray meeting another wave before the post, light reaching the
post after two reflections or from the sky, and the sun's disk (a point sun:
its 2 × 0.75° would blur a caustic thrown from D metres by about D/40 m).

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

from ..constants import RIPPLE_BANDWIDTH_TEXELS, RIPPLE_CELL, RIPPLE_MAX_RAYS, RIPPLE_MESH
from ..errors import SunsetError, require_finite, require_int_range
from ..kernels import twin
from .caustics import MAX_REFINE, trace_beams, trace_photons
from .postrays import PostReceiver, patch_geometry, rms_slope

__all__ = ["RippleTexture", "trace_ripples", "patch_geometry", "rms_slope", "texture_lookup", "ripple_source",
           "histogram", "METHODS"]

#: The two density estimates: a mesh of beams (the default) and photons.
METHODS = ("beams", "photons")


@dataclass(frozen=True)
class RippleTexture:
    """The light a post receives from the water, as irradiance over its side, relative to the direct sun's E.

    ``above`` (n_z, n_φ): reflected light, the same at every wavelength (Fresnel's R barely depends on λ);
    ``below`` (n_zb, n_φ, n_λ): refracted light under water, attenuated by the water, per wavelength of
    :func:`~sunset.model.sky.spectral_data`. ``phi`` (n_φ,), ``z`` (n_z,) and ``z_below`` (n_zb,) are the
    texel centres; ``accounts`` the flux of every ray by where it ended (relative to E, m²; the refracted
    ones per wavelength, averaged). ``method`` says which estimate made it: ``"beams"`` (``cell`` the beams'
    side on the water, m; ``rays`` the mesh's vertices) or ``"photons"`` (``rays`` of them, ``bandwidth`` the
    kernel's radius in metres, 0 for a histogram).
    """

    phi: np.ndarray
    z: np.ndarray
    z_below: np.ndarray
    above: np.ndarray
    below: np.ndarray
    accounts: dict
    rays: int
    bandwidth: float
    method: str = "beams"
    cell: float = 0.0


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


def histogram(u, v, flux, shape) -> np.ndarray:
    """Photons counted in the texel each lands in (u periodic, v clipped into the rows): (n_v, n_u, C)."""
    n_v, n_u = shape
    cell = np.clip(np.floor(v).astype(np.int64), 0, n_v - 1) * n_u + np.mod(np.floor(u).astype(np.int64), n_u)
    out = np.zeros((n_v * n_u, flux.shape[1]))
    for c in range(flux.shape[1]):
        out[:, c] = np.bincount(cell, weights=flux[:, c], minlength=n_v * n_u)
    return out.reshape(n_v, n_u, -1)


def trace_ripples(scene, post_index: int = 0, t: float = 0.0, hours: float = 2.0, *, method: str = "beams",
                  cell: float | None = None, rays: int = 1 << 18, texels: int = 48, bandwidth: float | None = None,
                  seed: int = 0, shadows: bool = True, refine: int = 0) -> RippleTexture:
    """Trace the sunlight off a patch of water onto one post of ``scene`` at time ``t`` (the sun ``hours`` before
    sunset), as a mesh of beams or as photons.

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
    method : {"beams", "photons"}
        The density estimate (module docstring).
    cell : float, optional
        Beams: the side of a cell of the mesh on the water, metres (at most
        :data:`~sunset.constants.RIPPLE_MAX_RAYS` corners; by default
        :data:`~sunset.constants.RIPPLE_CELL`, or larger where the patch would need more than
        :data:`~sunset.constants.RIPPLE_MESH` corners: a low sun's long patch).
    rays : int
        Photons: how many (1 to :data:`~sunset.constants.RIPPLE_MAX_RAYS`).
    texels : int
        Texels up the post's height above the water; they are square, so there are about 2πρ/Δz around
        it, and under water as many per metre.
    bandwidth : float, optional
        Photons: the Epanechnikov kernel's radius h, metres (default
        :data:`~sunset.constants.RIPPLE_BANDWIDTH_TEXELS` texel heights; 0: count each photon in its texel).
    seed : int
        Photons: the seed of their jittered grid (the same seed gives the same texture).
    shadows : bool
        Whether crests shadow the water behind them (:func:`sunset.light.sunrays.visible`).
    refine : int
        Beams: how many times a beam that lands at a glance may be halved (0 to
        :data:`~sunset.light.caustics.MAX_REFINE`; :func:`sunset.light.caustics.trace_beams`).
    """
    require_int_range("post_index", post_index, 0, max(len(scene.posts) - 1, 0))
    if not scene.posts:
        raise SunsetError("the scene has no posts to light")
    require_finite("t", t)
    require_finite("hours", hours)
    if method not in METHODS:
        raise SunsetError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    require_int_range("texels", texels, 2, 4096)
    receiver = PostReceiver(scene, post_index, float(t), float(hours), int(texels), bool(shadows))
    post = receiver.post
    phi_edges, z_edges, zb_edges = receiver.phi_edges, receiver.z_edges, receiver.zb_edges
    dz = z_edges[1] - z_edges[0]
    h = 0.0
    if method == "beams":
        if cell is None:               # the default: RIPPLE_CELL, coarser where the patch would need more corners
            cell = max(RIPPLE_CELL, math.sqrt(receiver.area / RIPPLE_MESH))
        books, rays = beams_on(receiver, receiver.L, 2.0 * receiver.W, cell, refine)
    else:
        require_int_range("rays", rays, 1, RIPPLE_MAX_RAYS)
        h = photon_bandwidth(bandwidth, dz)
        dzb = zb_edges[1] - zb_edges[0]

        def splat(u, v, flux, shape):
            if h == 0:
                return histogram(u, v, flux, shape)
            edges = z_edges if shape[0] == len(z_edges) - 1 else zb_edges
            step = dz if shape[0] == len(z_edges) - 1 else dzb
            return _splat(np.mod(u * (phi_edges[1] - phi_edges[0]), 2.0 * math.pi), edges[0] + v * step, flux,
                          phi_edges, edges, post.radius, h)

        books = trace_photons(receiver, int(rays), int(seed), splat)
    dphi = phi_edges[1] - phi_edges[0]
    return RippleTexture(
        phi=0.5 * (phi_edges[1:] + phi_edges[:-1]), z=0.5 * (z_edges[1:] + z_edges[:-1]),
        z_below=0.5 * (zb_edges[1:] + zb_edges[:-1]), above=books.reflected / (post.radius * dphi * dz),
        below=books.refracted / (post.radius * dphi * (zb_edges[1] - zb_edges[0])), accounts=books.accounts,
        rays=int(rays), bandwidth=h, method=method, cell=float(cell) if method == "beams" else 0.0)


def beams_on(receiver, length: float, width: float, cell, refine):
    """(the beams' accounts, their corners) for a length × width patch of ``receiver`` in cells of ``cell`` metres."""
    require_finite("cell", cell)
    n_a, n_b = _mesh(length, width, float(cell))
    require_int_range("refine", refine, 0, MAX_REFINE)
    return trace_beams(receiver, n_a, n_b, levels=int(refine)), (n_a + 1) * (n_b + 1)


def photon_bandwidth(bandwidth, texel: float) -> float:
    """The photons' splat width, metres: ``bandwidth``, or RIPPLE_BANDWIDTH_TEXELS texels of ``texel`` metres."""
    h = RIPPLE_BANDWIDTH_TEXELS * texel if bandwidth is None else float(bandwidth)
    require_finite("bandwidth", h)
    if h < 0:
        raise SunsetError(f"bandwidth must be positive or 0 (a histogram), got {h!r}")
    return h


def _mesh(length: float, width: float, cell: float) -> tuple[int, int]:
    """Cells (n_a, n_b) of about ``cell`` metres on a length × width patch, within RIPPLE_MAX_RAYS vertices."""
    if not cell > 0:
        raise SunsetError(f"cell must be positive, got {cell!r}")
    n_a, n_b = max(1, math.ceil(length / cell)), max(1, math.ceil(width / cell))
    if (n_a + 1) * (n_b + 1) > RIPPLE_MAX_RAYS:
        raise SunsetError(f"cell: {cell:g} m cells on a {length:.3g} x {width:.3g} m patch make "
                          f"{(n_a + 1) * (n_b + 1):,} beams' corners (at most {RIPPLE_MAX_RAYS:,}): use larger cells")
    return n_a, n_b


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


def ripple_source(scene, t: float, hours: float, light, texels: int = 48, cell: float | None = None):
    """An extra light source for the RGB back end: the ripples of light on the scene's posts at time ``t``.

    Traces one texture per post (:func:`trace_ripples`, beams) and returns
    ``source(points, normals, part)`` for :attr:`sunset.light.lighting.Lighting.extra_irradiance`:
    at island points that lie on a post's side (direct rays; the points in
    eye coordinates), the texture's irradiance times the wood's albedo and the
    direct sun of the hour over π, in XYZ.
    """
    from ..constants import PART_CLIFF

    textures = [trace_ripples(scene, j, t, hours, texels=texels, cell=cell) for j in range(len(scene.posts))]
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
