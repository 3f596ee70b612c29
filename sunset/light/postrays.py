"""A post as the receiver of the ripples of light: its patch of water, its side, and where each sun ray goes.

:mod:`sunset.light.ripples` says what the patch is and why; this module
traces a sun ray from each point of it, for both tracers of
:mod:`sunset.light.caustics` (the beams' corners and the photons). At the
water point (x, y) of the patch's parameters (a, b), :func:`post_rays` finds
the sea's height and normal (eq. 1 with Stokes' harmonics, as the table of
cosines of :func:`sunset.light.sunrays.sea_table`), the sunlight's flux ω,
Fresnel's R, the reflected and the refracted ray, and where each meets the
post's side extended up and down (:func:`sunset.light.ripples.side`): the
texture coordinates of the landing point (φ/Δφ, (z − z₀)/Δz), the cosine of
incidence there, and the refracted ray's path through the water. Only then
are the crests' shadows looked for, at the points whose light lands
(:func:`sunset.light.sunrays.in_shadow`).
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import RIPPLE_MAX_REACH, RIPPLE_SLOPE_SIGMAS, WATER_REFRACTIVE_INDEX
from ..errors import SunsetError
from ..kernels import twin
from ..model.sky import spectral_data
from .caustics import LIT, Nodes
from .sunrays import in_shadow, sea_table
from .water import absorption, scattering

__all__ = ["PostReceiver", "post_rays", "patch_geometry", "rms_slope", "GEOMETRY"]

#: The scalars :func:`post_rays` reads, in this order.
GEOMETRY = ("x", "y", "radius", "toward_x", "toward_y", "across_x", "across_y", "L", "W", "px", "py", "pz",
            "z0", "dz", "zb0", "dzb", "dphi", "n")


def _side(cx, cy, rho, qx, qy, rx, ry):
    """Distance along rays (q, r) to the vertical cylinder of radius rho about (cx, cy), +inf for a miss."""
    u, v = qx - cx, qy - cy
    a = rx * rx + ry * ry
    b = 2.0 * (u * rx + v * ry)
    c = u * u + v * v - rho * rho
    disc = b * b - 4.0 * a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        qq = -0.5 * (b + np.copysign(np.sqrt(np.maximum(disc, 0.0)), b))
        t = np.fmin(qq / a, c / qq)
    return np.where((disc > 0.0) & (a > 0.0) & (c > 0.0) & (t > 0.0), t, np.inf)


@twin("sunset.light.postrays_numba")
def post_rays(a, b, amp, kx, ky, c, geo):
    """Trace the sun ray at each patch point (a, b) (n,) onto the post (module docstring).

    ``amp``, ``kx``, ``ky``, ``c``: the sea's table of cosines; ``geo``: the scalars :data:`GEOMETRY`. Returns
    ``code`` (n,) int64 (2 under the post, else LIT + 10 × the reflected ray's code + the refracted ray's:
    0 lands, 1 passes, 2 the reflected ray heads back down), ``omega``, ``R``, the landing coordinates
    ``ur``, ``vr``, ``ut``, ``vt`` (texels, NaN where the ray does not land), ``path`` (m), ``glance`` and the
    water points ``qx``, ``qy``, ``qz``.
    """
    g = dict(zip(GEOMETRY, geo))
    x = g["x"] + g["toward_x"] * a * g["L"] + g["across_x"] * (2.0 * b - 1.0) * g["W"]
    y = g["y"] + g["toward_y"] * a * g["L"] + g["across_y"] * (2.0 * b - 1.0) * g["W"]
    eta, fx, fy = np.zeros(x.shape), np.zeros(x.shape), np.zeros(x.shape)
    for h in range(len(amp)):
        theta = kx[h] * x + ky[h] * y + c[h]
        eta += amp[h] * np.cos(theta)
        s = amp[h] * np.sin(theta)
        fx -= kx[h] * s
        fy -= ky[h] * s
    px, py, pz = g["px"], g["py"], g["pz"]
    inv = 1.0 / np.sqrt(fx * fx + fy * fy + 1.0)
    nx, ny, nz = -fx * inv, -fy * inv, inv
    omega = np.maximum(pz - px * fx - py * fy, 0.0)
    pn = px * nx + py * ny + pz * nz
    ci = np.clip(pn, 0.0, 1.0)
    n = g["n"]
    ct = np.sqrt(1.0 - (1.0 - ci * ci) / (n * n))
    R = 0.5 * (((ci - n * ct) / (ci + n * ct)) ** 2 + ((n * ci - ct) / (n * ci + ct)) ** 2)
    # reflected: −P + 2(P·N)N; refracted: −P/n + (cos i/n − cos t)N
    rx, ry, rz = -px + 2.0 * pn * nx, -py + 2.0 * pn * ny, -pz + 2.0 * pn * nz
    k = ci / n - ct
    tx, ty, tz = -px / n + k * nx, -py / n + k * ny, -pz / n + k * nz
    blocked = np.hypot(x - g["x"], y - g["y"]) <= g["radius"]
    t_r = _side(g["x"], g["y"], g["radius"], x, y, rx, ry)
    t_t = _side(g["x"], g["y"], g["radius"], x, y, tx, ty)
    code_r = np.where(rz <= 0.0, 2, np.where(np.isfinite(t_r), 0, 1))
    code_t = np.where(np.isfinite(t_t), 0, 1)
    code = np.where(blocked, 2, LIT + 10 * code_r + code_t).astype(np.int64)
    on_r, on_t = ~blocked & (code_r == 0), ~blocked & (code_t == 0)
    ur, vr, ut, vt = (np.full(x.shape, np.nan) for _ in range(4))
    path, glance = np.zeros(x.shape), np.ones(x.shape)
    for on, t, dx, dy, dz, u, v, z0, step in ((on_r, t_r, rx, ry, rz, ur, vr, g["z0"], g["dz"]),
                                              (on_t, t_t, tx, ty, tz, ut, vt, g["zb0"], g["dzb"])):
        hx, hy = x[on] + t[on] * dx[on] - g["x"], y[on] + t[on] * dy[on] - g["y"]
        phi = np.mod(np.arctan2(hy, hx), 2.0 * math.pi)
        u[on] = phi / g["dphi"]
        v[on] = (eta[on] + t[on] * dz[on] - z0) / step
        glance[on] = np.minimum(glance[on], -(np.cos(phi) * dx[on] + np.sin(phi) * dy[on]))
    path[on_t] = t_t[on_t]
    return code, omega, R, ur, vr, ut, vt, path, glance, x, y, eta


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


class PostReceiver:
    """A post's patch and side for :func:`sunset.light.caustics.trace_beams` and ``trace_photons``."""

    dark_names = {1: "in the waves' shadow", 2: "blocked by the post"}
    reflected_names = {0: "reflected onto the post", 1: "reflected past it", 2: "reflected back into the water"}
    refracted_names = {0: "refracted onto the post", 1: "refracted past it"}
    reflected_clipped = "reflected over the post's top"
    refracted_clipped = "refracted past it"

    def __init__(self, scene, post_index: int, t: float, hours: float, texels: int, shadows: bool = True):
        self.post, sea = scene.posts[post_index], scene.sea
        self.p = scene.sun.position(float(hours))
        self.toward, self.across, self.L, self.W = patch_geometry(self.post, sea, self.p)
        self.table = sea_table(sea, t)
        self.shadows = shadows
        top, depth, d = self.post.top, self.post.depth, sea.max_elevation
        self.z_edges = np.linspace(-d, top, texels + 1)
        dz = self.z_edges[1] - self.z_edges[0]
        n_phi = max(8, int(round(2.0 * math.pi * self.post.radius / dz)))
        n_zb = max(1, int(math.ceil((depth + d) / dz)))
        self.zb_edges = np.linspace(-max(depth, dz) if depth + d <= 0 else -depth, d, n_zb + 1)
        self.phi_edges = np.linspace(0.0, 2.0 * math.pi, n_phi + 1)
        lam = spectral_data().wavelengths
        self.attenuation = absorption(lam) + scattering(lam)
        self.shape_reflected = (texels, n_phi)
        self.shape_refracted = (n_zb, n_phi, len(lam))
        post = self.post
        self.geo = np.array([post.x, post.y, post.radius, self.toward[0], self.toward[1], self.across[0],
                             self.across[1], self.L, self.W, *self.p, self.z_edges[0], dz, self.zb_edges[0],
                             self.zb_edges[1] - self.zb_edges[0], self.phi_edges[1], WATER_REFRACTIVE_INDEX])

    @property
    def area(self) -> float:
        """The patch's horizontal area J, m²."""
        return 2.0 * self.W * self.L

    def evaluate(self, a, b) -> Nodes:
        """The mesh's nodes at parameters (a, b): :func:`post_rays`, then the crests' shadows where light lands."""
        a = np.ascontiguousarray(a, dtype=float)
        b = np.ascontiguousarray(b, dtype=float)
        tab = self.table
        code, omega, R, ur, vr, ut, vt, path, glance, x, y, eta = post_rays(a, b, tab.a, tab.kx, tab.ky, tab.c,
                                                                            self.geo)
        lands = np.isfinite(ur) | np.isfinite(ut)
        if self.shadows and tab.top > 0 and np.any(lands):
            dark = in_shadow(tab, x, y, eta, omega, self.p, lands)
        else:
            dark = ~(omega > 0) & lands
        code = np.where(dark & lands, 1, code)
        dropped = code < LIT
        for arr in (ur, vr, ut, vt):
            arr[dropped] = np.nan
        return Nodes(a, b, code, omega * self.area, R, ur, vr, ut, vt, np.where(dropped, 0.0, path),
                     np.where(dropped, 1.0, glance))
