"""The sun's glitter off a wind sea: the slopes the tile cannot resolve, as a Cox–Munk distribution of facets.

A wind sea's tile holds the waves longer than two of its grid spacings; the
shorter waves, down to capillaries, hold most of the sea's slope variance
(:meth:`sunset.model.windsea.WindSea.unresolved_slopes`). A mirror at the
resolved normal would show the sun's disk only where that normal happens to
point it at the eye: a few bright pixels, and a glitter pattern as narrow as
the grid's slopes. Instead each sea pixel is taken as a patch of facets about
its resolved normal n₀, their slopes relative to it Gaussian with the
variances the rendering leaves out (along and across the wind), and the
sun's light reflected by the facets that point it at the eye (Cox and Munk
1954, their eq. for the glitter's radiance):

    L = ρ(ω) E_sun p(ζ_u, ζ_c) / (4 μ_v μ_h⁴),

with h = (s − d)/|s − d| the normal that reflects the eye's ray d into the
sun's direction s, μ_v = −d·n₀, μ_h = h·n₀, cos ω = h·s, ζ the slopes of h
in the frame of n₀ (along the wind's direction projected on the patch, and
across), p :func:`sunset.model.coxmunk.facet_density`, ρ the Fresnel
reflectance and E_sun = L_disk · 2π(1 − cos δ) the sun's irradiance. The sun
is a point here: its disk (δ ≈ 0.013 rad) is small beside the facets' spread
(σ ≈ 0.1–0.25). The disk is then not drawn in the sea's mirror reflections
(:func:`sunset.light.shade.shade`), which would count the sun twice.

**Which variance.** What the picture holds of the tile's slopes is the
bilinear interpolant of the FFT gradient grids, whose mean square is
Σ k² Ψ Δk² A(θ_x) A(θ_y) with A(θ) = (2 + cos θ)/3 (θ = k Δ, the phase
across one grid cell; :meth:`sunset.model.ocean.OceanTile.interpolation_error`),
a little less than the tile's own; the facets get the rest of the wind's total
(:func:`facet_variances`), so that the resolved and the facets' slopes add up
to the wind's, not to the grid's (tests).

Left out: the glitter of a second bounce (rare on a wind sea), the facets'
shadowing and hiding (as in Cox and Munk's formula), the reflected sky's
spread by the facets (its radiance changes slowly; only the sun's, 10⁴ times
the sky's, is spread), and skewness and peakedness (the Gram–Charlier terms).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import SEA, WATER_REFRACTIVE_INDEX
from ..model.coxmunk import facet_density
from ..model.ocean import lattice
from .fresnel import reflectance

__all__ = ["Glitter", "facet_variances", "glitter_radiance", "sun_irradiance"]

#: The least facet variance (slope², per direction): a tile that resolves nearly all the wind's slopes keeps
#: this much, so the distribution stays a density (its glitter is then the disk's, spread by 0.01 rad).
MIN_FACET_VARIANCE = 1e-4


def facet_variances(wind) -> tuple[float, float]:
    """(σ_u², σ_c²) of the facets: the wind's total slope variances less what
    the rendered tile holds.

    The rendered tile's share is the expected mean square of the bilinearly
    interpolated FFT gradient, Σ k_u² Ψ Δk² A(θ_x) A(θ_y) (and k_c²),
    A(θ) = (2 + cos θ)/3, θ = k Δ with Δ the tile's grid spacing.
    """
    step = wind.tile.spacing
    kx, ky = lattice(wind.tile_points, wind.tile_size)
    shrink = (2.0 + np.cos(kx * step)) / 3.0 * (2.0 + np.cos(ky * step)) / 3.0
    d = math.radians(wind.direction)
    ku = kx * math.cos(d) + ky * math.sin(d)
    kc = -kx * math.sin(d) + ky * math.cos(d)
    v = wind.component_variance * shrink
    tu, tc = wind.total_slopes()
    return (max(tu - float(np.sum(ku * ku * v)), MIN_FACET_VARIANCE),
            max(tc - float(np.sum(kc * kc * v)), MIN_FACET_VARIANCE))


@dataclass
class Glitter:
    """The sea pixels of a frame of a wind sea, for the sun's glitter: kept with its :class:`Geometry`.

    ``index`` (G,) the pixels (flat, row-major) whose direct ray meets the
    sea, ``view`` (G, 3) their rays d, ``normal`` (G, 3) the resolved
    normals n₀ there; the facets' variances and the wind's direction
    (degrees, toward which it blows).
    """

    index: np.ndarray
    view: np.ndarray
    normal: np.ndarray
    var_upwind: float
    var_crosswind: float
    wind_direction: float
    n: float = WATER_REFRACTIVE_INDEX

    @classmethod
    def from_frame(cls, frame, wind) -> "Glitter":
        """From a traced frame (its direct fields) of a sea given by ``wind`` (:class:`~sunset.model.windsea.WindSea`)."""
        index = np.flatnonzero(frame.surface.reshape(-1) == SEA)
        vu, vc = facet_variances(wind)
        return cls(index=index, view=frame.direction.reshape(-1, 3)[index].astype(np.float32),
                   normal=frame.normal.reshape(-1, 3)[index].astype(np.float32), var_upwind=vu, var_crosswind=vc,
                   wind_direction=float(wind.direction))

    @property
    def nbytes(self) -> int:
        return int(self.index.nbytes + self.view.nbytes + self.normal.nbytes)


def sun_irradiance(sun_xyz, delta: float) -> np.ndarray:
    """E_sun (3,), XYZ: the disk's radiance times its solid angle 2π(1 − cos δ)."""
    return np.asarray(sun_xyz, dtype=float) * (2.0 * math.pi * (1.0 - math.cos(delta)))


def glitter_radiance(view, normal, sun_dir, e_sun, var_upwind: float, var_crosswind: float,
                     wind_direction: float, n: float = WATER_REFRACTIVE_INDEX) -> np.ndarray:
    """L = ρ E_sun p / (4 μ_v μ_h⁴) (see the module's docstring), (G, 3) float32; 0 where the sun is down or unseen.

    Parameters
    ----------
    view, normal : (G, 3)
        The eye's rays d (unit, towards the sea) and the resolved unit normals n₀.
    sun_dir : (3,)
        The unit vector to the sun.
    e_sun : (3,)
        The sun's irradiance (:func:`sun_irradiance`).
    var_upwind, var_crosswind, wind_direction
        The facets' slope variances and the wind's direction (degrees).
    """
    d = np.asarray(view, dtype=float).reshape(-1, 3)
    n0 = np.asarray(normal, dtype=float).reshape(-1, 3)
    s = np.asarray(sun_dir, dtype=float)
    h = s[None, :] - d
    h /= np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)     # 0: the eye looks straight at the sun
    mu_v = -np.sum(d * n0, axis=-1)
    mu_h = np.sum(h * n0, axis=-1)
    cos_i = h @ s
    a = math.radians(wind_direction)
    w = np.array([math.cos(a), math.sin(a), 0.0])
    t1 = w[None, :] - (n0 @ w)[:, None] * n0          # the wind's direction on the patch
    t1 /= np.linalg.norm(t1, axis=-1, keepdims=True)
    t2 = np.cross(n0, t1)
    ok = (mu_v > 0) & (mu_h > 0) & (s[2] > 0)
    safe = np.where(ok, mu_h, 1.0)
    zu, zc = -np.sum(h * t1, axis=-1) / safe, -np.sum(h * t2, axis=-1) / safe
    p = facet_density(zu, zc, var_upwind, var_crosswind, 0.0)
    k = np.where(ok, reflectance(cos_i, n) * p / (4.0 * np.where(ok, mu_v, 1.0) * safe ** 4), 0.0)
    return (k[:, None] * np.asarray(e_sun, dtype=float)[None, :]).astype(np.float32)
