"""Clouds by height functions: a double-valued layer over part of the plane (the paper's last proposal).

The paper ends: clouds could be rendered "by the height function techniques",
as deviations from a mean cloud level given by formulas, double valued and
defined only over part of the plane, shaded not by a normal but by depth below
the mean cloud level. This module is that cloud layer.

The layer
---------
A cloud layer has a mean level z = Z (metres above the sea) and cells. Cell j
occupies the ellipse

    q_j(x, y) = 1 − ((x − X_j)/a_j)² − ((y − Y_j)/b_j)² > 0

and, above it, the vertical segment Z − B_j ≤ z ≤ Z + T_j with

    T_j = top_j √q_j (1 + w_j),   B_j = bottom_j √q_j (1 + w_j),
    w_j = Σ_i c_i cos(ℓ_i x + m_i y),   Σ_i |c_i| < 1,

a lens that is thickest at the centre and closes to the mean level at its rim
(the square root gives it a rounded edge, the cosines its billows). Every
segment contains the mean level, so where cells overlap their union is again
one segment, Z − max_j B_j ≤ z ≤ Z + max_j T_j: the layer is the pair of
height functions T(x, y) = max_j T_j and B(x, y) = max_j B_j over the union D
of the ellipses (:meth:`Clouds.thickness`), zero outside D.

Depth and light
---------------
A point of a cloud is shaded by its depth d = Z − z below the mean level
(negative above it): sunlight enters from above, so the deeper a point, the
more cloud the light has crossed. :func:`cloud_radiance` is the light leaving
the cloud towards the eye, from the physical sky model
(:mod:`sunset.model.sky`): the direct sun at the cloud's own altitude (so
that clouds still glow after the sun has set at the sea), attenuated as
exp(−max(d, 0)/ℓ), plus the skylight, times the cloud's albedo over π.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..constants import (CLOUD_ALBEDO, CLOUD_ATTENUATION_LENGTH, CLOUD_MAX_CELLS, CLOUD_MAX_LEVEL, EARTH_RADIUS,
                         CLOUD_MULTIPLE_SCATTERING)
from ..constants import CLOUD_MIN_SIZE, MAX_DISTANCE, MAX_HILL_WAVENUMBER
from ..errors import (require_items, require_scalars, SunsetError, require_finite, require_length, require_positive,
                      require_range)

__all__ = ["Billow", "CloudCell", "Clouds", "cloud_radiance"]


@dataclass(frozen=True)
class Billow:
    """One billow term c cos(ℓx + my) of a cell's thickness: ``amplitude`` c is a fraction (|c| < 1), l, m in rad m⁻¹."""

    amplitude: float
    l: float
    m: float

    def __post_init__(self):
        require_scalars(self)
        require_finite("amplitude", self.amplitude)
        require_range("l", self.l, -MAX_HILL_WAVENUMBER, MAX_HILL_WAVENUMBER, "rad/m")
        require_range("m", self.m, -MAX_HILL_WAVENUMBER, MAX_HILL_WAVENUMBER, "rad/m")
        if not abs(self.amplitude) < 1.0:
            raise SunsetError(f"amplitude must lie in (-1, 1), got {self.amplitude!r}")


@dataclass(frozen=True)
class CloudCell:
    """One elliptical cloud: centre (x, y) and semi-axes a, b in metres; ``top`` and ``bottom`` the greatest
    height above and depth below the mean level, metres; ``billows`` modulate both."""

    x: float
    y: float
    a: float
    b: float
    top: float
    bottom: float
    billows: tuple[Billow, ...] = field(default_factory=tuple)

    def __post_init__(self):
        require_scalars(self)
        object.__setattr__(self, "billows", require_items("billows", self.billows, Billow))
        for name in ("x", "y"):
            require_range(name, getattr(self, name), -MAX_DISTANCE, MAX_DISTANCE, "m")
        for name in ("a", "b"):
            require_length(name, getattr(self, name), CLOUD_MIN_SIZE, MAX_DISTANCE)
        for name in ("top", "bottom"):             # none, or a thickness of at least a metre (not 5e-324 m)
            require_length(name, getattr(self, name), CLOUD_MIN_SIZE, CLOUD_MAX_LEVEL, zero=True)
        if self.top + self.bottom <= 0.0:
            raise SunsetError("top or bottom must be positive: a cloud needs some thickness")
        if sum(abs(b.amplitude) for b in self.billows) >= 1.0:
            raise SunsetError("billows: the sum of |amplitude| must be below 1, so the cloud stays closed")

    @property
    def swell(self) -> float:
        """The largest factor (1 + w) the billows can reach."""
        return 1.0 + sum(abs(b.amplitude) for b in self.billows)

    def q(self, x, y) -> np.ndarray:
        """1 − ((x − X)/a)² − ((y − Y)/b)²: positive inside the ellipse."""
        u = (np.asarray(x, dtype=float) - self.x) / self.a
        v = (np.asarray(y, dtype=float) - self.y) / self.b
        return 1.0 - u * u - v * v

    def profile(self, x, y) -> np.ndarray:
        """√q (1 + w), zero outside the ellipse: T = top × profile, B = bottom × profile."""
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        w = np.ones(np.broadcast(x, y).shape)
        for b in self.billows:
            w = w + b.amplitude * np.cos(b.l * x + b.m * y)
        return np.sqrt(np.maximum(self.q(x, y), 0.0)) * w

    def chord(self, s) -> tuple[np.ndarray, np.ndarray]:
        """Where the vertical plane x = s·y crosses the ellipse: (y0, y1), NaN where it misses or lies behind the eye."""
        s = np.asarray(s, dtype=float)
        A = s * s / self.a**2 + 1.0 / self.b**2
        B = -2.0 * (s * self.x / self.a**2 + self.y / self.b**2)
        C = (self.x / self.a) ** 2 + (self.y / self.b) ** 2 - 1.0
        disc = B * B - 4.0 * A * C
        root = np.sqrt(np.maximum(disc, 0.0))
        y0 = (-B - root) / (2.0 * A)
        y1 = (-B + root) / (2.0 * A)
        ok = (disc > 0.0) & (y1 > 0.0)
        return np.where(ok, np.maximum(y0, 0.0), np.nan), np.where(ok, y1, np.nan)


@dataclass(frozen=True)
class Clouds:
    """A cloud layer: the mean level (metres above the sea) and its cells."""

    level: float
    cells: tuple[CloudCell, ...] = field(default_factory=tuple)

    def __post_init__(self):
        require_scalars(self)
        object.__setattr__(self, "cells", require_items("cells", self.cells, CloudCell))
        require_positive("level", self.level)
        if self.level > CLOUD_MAX_LEVEL:
            raise SunsetError(f"level must be at most {CLOUD_MAX_LEVEL:g} m (the troposphere), got {self.level!r}")
        if not 1 <= len(self.cells) <= CLOUD_MAX_CELLS:
            raise SunsetError(f"cells must hold 1 to {CLOUD_MAX_CELLS} clouds, got {len(self.cells)}")
        for k, c in enumerate(self.cells):
            if c.bottom * c.swell >= self.level:
                raise SunsetError(f"cells[{k}].bottom reaches the sea: it must stay below the level "
                                  f"{self.level:g} m (with its billows)")

    @property
    def max_top(self) -> float:
        """The greatest height any cloud rises above the mean level, metres."""
        return max(c.top * c.swell for c in self.cells)

    @property
    def max_bottom(self) -> float:
        """The greatest depth any cloud reaches below the mean level, metres."""
        return max(c.bottom * c.swell for c in self.cells)

    @property
    def base(self) -> float:
        """The lowest point of the layer above the sea, metres."""
        return self.level - self.max_bottom

    def thickness(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """(T, B): heights above and below the layer's mean level at (x, y), metres.

        0 outside D.
        """
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        T = np.zeros(np.broadcast(x, y).shape)
        B = np.zeros_like(T)
        for c in self.cells:
            p = c.profile(x, y)
            T = np.maximum(T, c.top * p)
            B = np.maximum(B, c.bottom * p)
        return T, B

    def inside(self, x, y, z) -> np.ndarray:
        """Whether the points (x, y, z) (z above the sea) lie inside a cloud."""
        T, B = self.thickness(x, y)
        z = np.asarray(z, dtype=float)
        return (T + B > 0.0) & (z >= self.level - B) & (z <= self.level + T)


def cloud_radiance(depth, sun_dir, clouds: Clouds, delta: float) -> np.ndarray:
    """Spectral radiance leaving a cloud at ``depth`` below its mean level.

    Shape (..., n_λ).

    Per unit E₀.

    L = (ϖ/π) [E_sun(z) (exp(−max(d, 0)/ℓ) + κ) + E_sky], with ϖ the cloud's
    albedo (:data:`~sunset.constants.CLOUD_ALBEDO`), ℓ its attenuation length
    (:data:`~sunset.constants.CLOUD_ATTENUATION_LENGTH`), κ the share of
    multiply scattered light that reaches any depth
    (:data:`~sunset.constants.CLOUD_MULTIPLE_SCATTERING`), E_sun(z) the direct
    sun through the atmosphere above the point's altitude z = Z − d, with the
    visible fraction of the disk seen from there, and E_sky the sky's
    irradiance on a horizontal surface at sea level.

    Parameters
    ----------
    depth : array_like
        Depth below the mean cloud level, metres (negative above it).
    sun_dir : array_like (3,)
        Unit vector towards the sun (z up).
    clouds : Clouds
    delta : float
        The sun's angular radius, radians.
    """
    from .sky import island_lighting, slant_columns, spectral_data, visible_fraction

    d = np.asarray(depth, dtype=float)
    require_finite("depth", d)
    p = np.asarray(sun_dir, dtype=float)
    z = np.maximum(clouds.level - d, 0.0)
    e = math.asin(max(-1.0, min(1.0, float(p[2]))))
    sp = spectral_data()
    col = slant_columns(z, math.sin(e))                                  # (..., 3)
    trans = np.exp(-np.einsum("...k,kl->...l", col, sp.tau))  # (..., n_λ)
    # the horizon dips below the horizontal by √(2z/R) seen from altitude z
    dip = np.sqrt(2.0 * z / EARTH_RADIUS)
    vis = visible_fraction(e + dip, delta)[..., None]
    direct = sp.sun * trans * vis
    _, sky = island_lighting(p, delta)
    lit = np.exp(-np.maximum(d, 0.0) / CLOUD_ATTENUATION_LENGTH)[..., None]
    lit = lit + CLOUD_MULTIPLE_SCATTERING
    return CLOUD_ALBEDO / math.pi * (direct * lit + sky)
