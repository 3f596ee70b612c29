"""Posts standing in the water: small vertical cylinders that catch the ripples of light.

The paper's second proposal for the future: sunlight reflected from rippled
water, and refracted into it, falls on "a small object extending above and
below the water line" as moving ripples of light. A :class:`Post` is that
object: a vertical circular cylinder of radius ρ about (x, y), from ``depth``
metres below the mean sea level to ``top`` metres above it, a pile or a
weathered mooring post. Its surface is parametrised by the azimuth φ of the
outward normal (0 along +x, counter-clockwise) and the height z above mean
sea level, the coordinates of its texture of light
(:mod:`sunset.light.ripples`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import MAX_DISTANCE, POST_MAX_RADIUS, POST_MAX_TOP, POST_MIN_SIZE
from ..errors import require_scalars, SunsetError, require_finite, require_length, require_range

__all__ = ["Post"]


@dataclass(frozen=True)
class Post:
    """A vertical cylinder in the water: centre (x, y), ``radius``, ``top`` above and ``depth`` below mean sea
    level, all in metres; ``albedo`` its grey diffuse reflectance (0–1)."""

    x: float
    y: float
    radius: float
    top: float
    depth: float
    albedo: float = 0.35

    def __post_init__(self):
        require_scalars(self)
        require_range("x", self.x, -MAX_DISTANCE, MAX_DISTANCE, "m")
        require_range("y", self.y, -MAX_DISTANCE, MAX_DISTANCE, "m")
        require_length("radius", self.radius, POST_MIN_SIZE, POST_MAX_RADIUS)   # a post, not an island
        require_length("top", self.top, POST_MIN_SIZE, POST_MAX_TOP)
        require_length("depth", self.depth, POST_MIN_SIZE, POST_MAX_TOP, zero=True)
        require_finite("albedo", self.albedo)
        if not 0.0 <= self.albedo <= 1.0:
            raise SunsetError(f"albedo must lie in [0, 1], got {self.albedo!r}")
        if math.hypot(self.x, self.y) <= self.radius:
            raise SunsetError("puts the eye inside the post: its axis must be farther than its radius from the eye")

    def pierce(self, q, r) -> np.ndarray:
        """Distance t along rays q + t r to the post's side (+inf: a miss).

        Eye-independent coordinates, z above mean sea level. A ray also misses
        where it meets the side only behind its origin or beyond top and depth.

        The side (x − X)² + (y − Y)² = ρ² gives a t² + b t + c = 0 with
        a = r_x² + r_y², b = 2(u r_x + v r_y), c = u² + v² − ρ²,
        (u, v) = (q_x − X, q_y − Y); the entry is the smaller root, kept when it
        is ahead (t > 0) and between −depth and top.
        """
        q = np.asarray(q, dtype=float)
        r = np.asarray(r, dtype=float)
        u, v = q[..., 0] - self.x, q[..., 1] - self.y
        a = r[..., 0] ** 2 + r[..., 1] ** 2
        b = 2.0 * (u * r[..., 0] + v * r[..., 1])
        c = u * u + v * v - self.radius ** 2
        disc = b * b - 4.0 * a * c
        with np.errstate(divide="ignore", invalid="ignore"):
            root = np.sqrt(np.maximum(disc, 0.0))
            qq = -0.5 * (b + np.copysign(root, b))
            t1, t2 = qq / a, c / qq
        t_in = np.fmin(t1, t2)
        z = q[..., 2] + t_in * r[..., 2]
        ok = (disc > 0.0) & (a > 0.0) & (c > 0.0) & (t_in > 0.0)
        ok &= (z <= self.top) & (z >= -self.depth)
        return np.where(ok, t_in, np.inf)

    def surface_coordinates(self, p) -> tuple[np.ndarray, np.ndarray]:
        """(φ in [0, 2π), z) of points p on the side: the outward normal's azimuth and the height."""
        p = np.asarray(p, dtype=float)
        phi = np.mod(np.arctan2(p[..., 1] - self.y, p[..., 0] - self.x), 2.0 * math.pi)
        return phi, p[..., 2]

    def normal(self, p) -> np.ndarray:
        """The outward unit normal (horizontal) at points p on the side."""
        p = np.asarray(p, dtype=float)
        d = np.stack([p[..., 0] - self.x, p[..., 1] - self.y, np.zeros(p.shape[:-1])], axis=-1)
        return d / np.linalg.norm(d, axis=-1, keepdims=True)
