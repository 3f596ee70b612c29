"""The light one cosine wave throws on a post's front, from its ray map in closed form: the beams' oracle.

A single long-crested wave η = A cos(k s + θ₀) travelling towards the sun (s
the horizontal distance from the post's axis towards the sun) reflects the
sun in vertical planes along s, so the light on the post's front (the
generator that faces the sun) follows from a 1-D ray map, with no mesh and
no photons. The water at s is tilted towards the sun by
β = atan(A k sin(k s + θ₀)); its sunlight per unit area, ω = sin e − cos e dη/ds
(:mod:`sunset.light.sunrays`), is reflected with Fresnel's R(P·N) at
elevation e + 2β and meets the generator at azimuth δ from the sun's at the
height

    z(s) = A cos(k s + θ₀) + (s − ρ cos δ) tan(e + 2β).

The wave is the same across, so per unit of width across a texel of height
Δz receives ∫ ωR ds over the s whose z(s) falls in it (ρ dφ = db/cos δ on the
side): its irradiance is that integral times cos δ over Δz. The caustics lie
where the map folds, z'(s) = 0. :func:`front_line` sums the integral on a
fine grid of s (each step's light into the texel its middle lands in).

Where a texture puts a fold
---------------------------
A fold's light is an edge, not a peak: near the fold height z_f the two
sheets of the map that meet there give E ≈ c |z − z_f|^(−1/2) on one side and
nothing on the other, over the smooth light of the other sheets. A texel that
holds the fold gets 2c√(its part on the bright side)/Δz, so the brightest
texel is the fold's only while the fold lies in the third of it away from the
bright side; otherwise it is the next one, and its centre is up to 5/6 of a
texel from the fold even in the exact texture. :func:`locate_fold` reads the
fold's height to a fraction of a texel instead: it fits the texel means of
b₀ + b₁(z − z̄) + c|z − z_f|^(−1/2) (bright above or below, c > 0) to the
five texels about a bright texel, by least squares for each z_f of a fine
grid, and keeps the best. It uses only the fold's universal shape (every
fold of a smooth map has it), nothing of the wave that made it.
"""

from __future__ import annotations

import math

import numpy as np

from .fresnel import reflectance

__all__ = ["front_line", "locate_fold", "fold_profile"]

#: Candidate fold heights tried per texel by :func:`locate_fold`.
FOLD_STEPS = 100


def front_line(post, sun_dir, amplitude: float, wavelength: float, phase: float, edges, phi: float, reach: float,
               steps: int = 2_000_000):
    """The irradiance (relative to E) of the texels between ``edges`` (heights, m) on the post's generator at
    azimuth ``phi``, lit by the wave η = A cos(k(u·(x, y)) + phase) (u the sun's horizontal direction) on the
    water from the post's side out to ``reach`` metres towards the sun; and the heights of the folds and the
    distances s they come from."""
    p = np.asarray(sun_dir, dtype=float)
    e, k = math.asin(p[2]), 2 * math.pi / wavelength
    u = p[:2] / math.hypot(p[0], p[1])
    theta0 = k * (u @ [post.x, post.y]) + phase
    delta = phi - math.atan2(p[1], p[0])
    s = np.linspace(post.radius, reach, steps + 1)
    sm = 0.5 * (s[1:] + s[:-1])
    slope = -amplitude * k * np.sin(k * sm + theta0)                     # dη/ds
    z = amplitude * np.cos(k * sm + theta0) + (sm - post.radius * math.cos(delta)) * np.tan(e - 2 * np.arctan(slope))
    omega = math.sin(e) - math.cos(e) * slope
    w = omega * reflectance(omega / np.sqrt(1 + slope ** 2)) * (s[1] - s[0])
    edges = np.asarray(edges, dtype=float)
    light = np.histogram(z, bins=edges, weights=w)[0] / np.diff(edges) * math.cos(delta)
    turn = np.flatnonzero(np.sign(np.diff(z[1:])) != np.sign(np.diff(z[:-1]))) + 1
    return light, z[turn], sm[turn]


def fold_profile(edges, fold, side: int) -> np.ndarray:
    """The texel means between ``edges`` (m) of |z − ``fold``|^(−1/2) on the fold's bright ``side`` (+1 above,
    −1 below), 0 on the other: 2(√(hi − z_f) − √(lo − z_f))/Δz clipped at the fold. ``fold`` may be an array
    (…,): the result is (…, texels)."""
    edges = np.asarray(edges, dtype=float)
    d = side * (edges - np.asarray(fold, dtype=float)[..., None])         # distance into the bright side
    root = 2.0 * np.sqrt(np.maximum(d, 0.0))
    return side * np.diff(root, axis=-1) / np.diff(edges)


def locate_fold(column, edges, near: float, half: int = 2) -> float:
    """The height (m) of the fold whose caustic lights the texel of ``column`` (texel means between ``edges``)
    that holds ``near``: the best fit of a fold's light over a linear background to the 2·``half`` + 1 texels
    about it (module docstring), the fold sought from 1.5 texels below that texel to 1.5 above it."""
    column, edges = np.asarray(column, dtype=float), np.asarray(edges, dtype=float)
    dz = edges[1] - edges[0]
    k = int(np.clip(np.floor((near - edges[0]) / dz), half, len(column) - half - 1))
    y, e = column[k - half:k + half + 1], edges[k - half:k + half + 2]
    zc = 0.5 * (e[1:] + e[:-1])
    fold = np.linspace(edges[k] - 1.5 * dz, edges[k + 1] + 1.5 * dz, 4 * FOLD_STEPS + 1)
    best, where = np.inf, float(near)
    for side in (1, -1):
        X = np.stack(np.broadcast_arrays(np.ones_like(zc), (zc - zc.mean()) / dz, fold_profile(e, fold, side)),
                     axis=-1)                                                        # (folds, texels, 3)
        coef = np.linalg.pinv(X) @ y                                                 # (folds, 3)
        residual = np.sum((np.einsum("ftc,fc->ft", X, coef) - y) ** 2, axis=1)
        residual = np.where(coef[:, 2] > 0, residual, np.inf)
        i = int(np.argmin(residual))
        if residual[i] < best:
            best, where = residual[i], float(fold[i])
    return where
