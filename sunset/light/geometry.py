"""The geometry of one frame, kept for re-shading: what each pixel's light path does, without the light.

The colour tables let one tape be exposed at any hour because the codes hold
only geometry. :class:`Geometry` is the same idea for the RGB back end: from a
:class:`~sunset.vector.frame.Frame` it keeps, per pixel, everything that does not
depend on the sun:

* where the path finally goes (the final ray and what it meets: sky or an
  island part, and the island's normal);
* the product of the Fresnel reflectances along the path (its *throughput*);
* at each sea bounce, the direction of the light that comes up out of the
  water towards the eye (the eye's ray refracted into the sea, reversed) and
  the weight (1 − R)/n² times the throughput before that bounce.

A path is D, then up to two sea reflections (``Frame.incidence`` and
``Frame.sea_rays`` say what each did), then — in the vector stage's
reflection modes — the |R_z| fold of a ray still heading down. The fold is
a reflection off the mean surface, so here it is a third bounce with the
normal (0, 0, 1): its Fresnel factor and its water are counted too.

Posts standing in the water are shaded as brown wood with the cliff's
albedo, as the 8-bit codes code them; the points where direct rays meet an
island or a post are kept (``island_point``) for light that depends on the
place, such as the ripples of light (:mod:`sunset.light.ripples`). A ray that
the vector stage ends on a cloud keeps the cloud's depth below the mean level
(``sky_cloud``): the shader gives it the cloud's light of the hour instead of
the sky's (:meth:`~sunset.light.lighting.Lighting.with_clouds`).

Shading a Geometry for an hour (:func:`sunset.light.shade.shade`) is then a
handful of array operations per pixel, with no ray traced again.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import CLOUD, PART_CLIFF, POST, SEA, SKY, WATER_REFRACTIVE_INDEX
from ..errors import SunsetError
from .fresnel import reflectance, refract

__all__ = ["Geometry", "WaterLayer"]


@dataclass
class WaterLayer:
    """The water seen at one bounce by the pixels ``index`` (flat, row-major)."""

    index: np.ndarray      # (M,) intp
    up: np.ndarray         # (M, 3) float32: direction of the light in the water towards the surface
    weight: np.ndarray     # (M,) float32: throughput before the bounce × (1 − R)/n²


@dataclass
class Geometry:
    """Per-pixel light paths of one frame (flattened, row-major), independent of the hour.

    Besides the per-pixel fields it keeps the compressed lists the shader's
    kernels read (:mod:`sunset.light.kernel`): the pixels ending in the sky with
    their rays' table rows and azimuths, those ending on an island with their
    normals' cells in the skylight table, and the water entries of all bounces.
    """

    shape: tuple
    final_dir: np.ndarray      # (N, 3) float32
    final_kind: np.ndarray     # (N,) int8: −1 sky, 1 beach, 2 cliff, 3 hill
    final_normal: np.ndarray   # (N, 3) float32 (islands; 0 elsewhere)
    throughput: np.ndarray     # (N,) float32: product of the Fresnel reflectances
    water: list                # of WaterLayer
    sky_index: np.ndarray      # (S,) intp: which pixels end in the sky
    sky_dir: np.ndarray        # (S, 3) float32: their final rays
    sky_r0: np.ndarray         # (S,) int32: the refined sky table's row below each ray
    sky_fr: np.ndarray         # (S,) float32: and the fraction towards the next
    sky_azimuth: np.ndarray    # (S,) float32: azimuth of their final rays
    island_index: np.ndarray   # (I,) intp: which pixels end on an island
    island_g: np.ndarray       # (I, 2) int32: the cell of the normal in the skylight table
    island_f: np.ndarray       # (I, 2) float32: and the fractions inside it
    water_starts: np.ndarray   # (layers,) intp: first entry of each bounce's water
    water_index: np.ndarray    # (M,) intp
    water_up: np.ndarray       # (M, 3) float32
    water_mu: np.ndarray       # (M,) float32: max(up_z, 0)
    water_weight: np.ndarray   # (M,) float32
    water_sky: np.ndarray      # (M,) float32: weight × (1/4π)/(μ̄ + μ_u), the skylight's factor
    n: float = WATER_REFRACTIVE_INDEX
    sky_cloud: np.ndarray | None = None     # (S,) float32: depth of the cloud a sky ray ends on, NaN: none
    island_point: np.ndarray | None = None  # (I, 3) float32: the direct ray's hit (eye at the origin), NaN if reflected

    @property
    def nbytes(self) -> int:
        arrays = [self.final_dir, self.final_kind, self.final_normal, self.throughput, self.sky_index, self.sky_dir,
                  self.sky_r0, self.sky_fr, self.sky_azimuth, self.island_index, self.island_g, self.island_f,
                  self.water_index, self.water_up, self.water_mu, self.water_weight, self.water_sky]
        arrays += [a for w in self.water for a in (w.index, w.up, w.weight)]
        arrays += [a for a in (self.sky_cloud, self.island_point) if a is not None]
        return int(sum(a.nbytes for a in arrays))

    @classmethod
    def from_frame(cls, frame, n: float = WATER_REFRACTIVE_INDEX) -> "Geometry":
        """Build from a traced frame (after :func:`sunset.render`)."""
        from .lighting import NORMAL_GRID, SKY_REFINE, SKY_ROWS, sky_row
        from .water import diffuse_mean_cosine

        if frame.final_surface is None or frame.incidence is None:
            raise SunsetError("the frame has no reflected rays: render it with sunset.render first")
        h, w = frame.shape
        npx = h * w
        surface = frame.surface.reshape(-1)
        final_surface = frame.final_surface.reshape(-1)
        final_part = frame.final_part.reshape(-1)
        final_dir = np.ascontiguousarray(frame.ray.reshape(-1, 3), np.float32).copy()
        # posts in the water are brown wood, shaded as the cliff (as the 8-bit codes do); rays that end on a
        # cloud are sky rays that keep the cloud's depth (sky_cloud below)
        kind = np.where((final_surface == SKY) | (final_surface == CLOUD), SKY,
                        np.where(final_surface == POST, PART_CLIFF, final_part)).astype(np.int8)
        normal = np.nan_to_num(frame.final_normal.reshape(-1, 3).astype(np.float32), nan=0.0)
        throughput = np.ones(npx, np.float32)
        layers = []

        sea = np.flatnonzero(surface == SEA)
        # float32 throughout, as the frame stores them
        inc = frame.incidence.reshape(-1, 2)[sea]
        rays = frame.sea_rays.reshape(-1, 2, 3)[sea]
        d = frame.direction.reshape(-1, 3)[sea]
        n1 = frame.normal.reshape(-1, 3)[sea]
        # bounce 1: the eye's ray D on the wave normal N₁
        c1 = np.clip(inc[:, 0], 0.0, 1.0)
        layers.append(_water(sea, d, n1, c1, throughput[sea], n))
        throughput[sea] *= reflectance(c1, n).astype(np.float32)
        last = rays[:, 0]
        # bounce 2: R₁ on N₂ = (R₂ − R₁)/(2 cos i₂)
        two = np.isfinite(inc[:, 1])
        if np.any(two):
            c2 = np.clip(inc[two, 1], 0.0, 1.0)
            r1, r2 = rays[two, 0], rays[two, 1]
            n2 = r2 - r1
            n2 /= np.maximum(np.linalg.norm(n2, axis=-1, keepdims=True), np.float32(1e-30))
            idx = sea[two]
            layers.append(_water(idx, r1, n2, c2, throughput[idx], n))
            throughput[idx] *= reflectance(c2, n).astype(np.float32)
            last = last.copy()
            last[two] = r2
        # the fold: a ray still heading down reflects off the mean surface
        down = last[:, 2] < 0.0
        if np.any(down):
            idx = sea[down]
            ld = last[down]
            c3 = np.clip(-ld[:, 2], 0.0, 1.0)
            up = np.broadcast_to(np.array([0.0, 0.0, 1.0], np.float32), ld.shape)
            layers.append(_water(idx, ld, up, c3, throughput[idx], n))
            throughput[idx] *= reflectance(c3, n).astype(np.float32)

        sky_index = np.flatnonzero(kind == SKY)
        fd = final_dir[sky_index]
        r_max = (SKY_ROWS - 1) * SKY_REFINE[0]
        rows = np.clip(sky_row(fd[:, 2]) * SKY_REFINE[0], 0, r_max)
        r0 = np.minimum(rows.astype(np.int32), r_max - 1)
        az = np.arctan2(fd[:, 1], fd[:, 0])
        island_index = np.flatnonzero(kind > 0)
        g = (np.clip(normal[island_index, :2].astype(np.float64), -1, 1) + 1.0) * (0.5 * (NORMAL_GRID - 1))
        g0 = np.minimum(g.astype(np.int32), NORMAL_GRID - 2)
        mu_bar = diffuse_mean_cosine(n)
        w_up = np.concatenate([w.up for w in layers]) if layers else np.zeros((0, 3), np.float32)
        w_weight = np.concatenate([w.weight for w in layers]) if layers else np.zeros(0, np.float32)
        w_mu = np.maximum(w_up[:, 2], np.float32(0))
        w_sky = (w_weight.astype(np.float64) / (4.0 * np.pi) / (mu_bar + w_mu.astype(np.float64))).astype(np.float32)
        starts = np.cumsum([0] + [len(w.index) for w in layers[:-1]]).astype(np.intp) if layers else np.zeros(0, np.intp)
        sky_cloud = None
        if frame.cloud_depth is not None:
            depth = frame.cloud_depth.reshape(-1)[sky_index]
            sky_cloud = np.where(final_surface[sky_index] == CLOUD, depth, np.nan).astype(np.float32)
        direct_hit = (frame.bounces.reshape(-1)[island_index] == 0)
        island_point = np.where(direct_hit[:, None], frame.point.reshape(-1, 3)[island_index], np.nan).astype(np.float32)
        return cls(shape=(h, w), final_dir=final_dir, final_kind=kind, final_normal=normal,
                   throughput=throughput.astype(np.float32), water=layers, sky_index=sky_index,
                   sky_dir=np.ascontiguousarray(final_dir[sky_index]), sky_r0=r0, sky_fr=(rows - r0).astype(np.float32),
                   sky_azimuth=az, island_index=island_index, island_g=g0, island_f=(g - g0).astype(np.float32),
                   water_starts=starts, water_index=np.concatenate([w.index for w in layers]) if layers
                   else np.zeros(0, np.intp), water_up=np.ascontiguousarray(w_up), water_mu=w_mu,
                   water_weight=w_weight, water_sky=w_sky, n=float(n), sky_cloud=sky_cloud,
                   island_point=island_point)


def _water(index, incident, normal, cos_i, before, n) -> WaterLayer:
    t = refract(incident, normal, cos_i, np.float32(n))
    up = -t / np.linalg.norm(t, axis=-1, keepdims=True)
    weight = before * ((1.0 - reflectance(cos_i, n)) / (n * n)).astype(np.float32)
    return WaterLayer(index=np.asarray(index, np.intp), up=up.astype(np.float32), weight=weight.astype(np.float32))
