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
"""

from __future__ import annotations

import math

import numpy as np

from .fresnel import reflectance

__all__ = ["front_line"]


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
