"""The geometry of one frame, kept for re-shading: what each pixel's light path does, without the light.

The colour tables let one tape be exposed at any hour because the codes hold
only geometry. :class:`Geometry` is the same idea for the RGB back end: from a
:class:`~sunset.frame.Frame` it keeps, per pixel, everything that does not
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

Shading a Geometry for an hour (:func:`sunset.light.shade.shade`) is then a
handful of array operations per pixel, with no ray traced again.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import SEA, SKY, WATER_REFRACTIVE_INDEX
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
    """Per-pixel light paths of one frame (flattened, row-major), independent of the hour."""

    shape: tuple
    final_dir: np.ndarray      # (N, 3) float32
    final_kind: np.ndarray     # (N,) int8: −1 sky, 1 beach, 2 cliff, 3 hill
    final_normal: np.ndarray   # (N, 3) float32 (islands; 0 elsewhere)
    throughput: np.ndarray     # (N,) float32: product of the Fresnel reflectances
    water: list                # of WaterLayer
    sky_rows: np.ndarray       # (S,) float32: sky-grid row of the sky pixels (√z scaled)
    sky_azimuth: np.ndarray    # (S,) float32: azimuth of their final rays
    sky_index: np.ndarray      # (S,) intp: which pixels end in the sky
    n: float = WATER_REFRACTIVE_INDEX

    @property
    def nbytes(self) -> int:
        arrays = [self.final_dir, self.final_kind, self.final_normal, self.throughput, self.sky_rows,
                  self.sky_azimuth, self.sky_index]
        arrays += [a for w in self.water for a in (w.index, w.up, w.weight)]
        return int(sum(a.nbytes for a in arrays))

    @classmethod
    def from_frame(cls, frame, n: float = WATER_REFRACTIVE_INDEX) -> "Geometry":
        """Build from a traced frame (after :func:`sunset.render`)."""
        from .lighting import sky_row

        if frame.final_surface is None or frame.incidence is None:
            raise SunsetError("the frame has no reflected rays: render it with sunset.render first")
        h, w = frame.shape
        npx = h * w
        surface = frame.surface.reshape(-1)
        final_surface = frame.final_surface.reshape(-1)
        final_part = frame.final_part.reshape(-1)
        final_dir = np.ascontiguousarray(frame.ray.reshape(-1, 3), np.float32).copy()
        kind = np.where(final_surface == SKY, SKY, final_part).astype(np.int8)
        normal = np.nan_to_num(frame.final_normal.reshape(-1, 3).astype(np.float32), nan=0.0)
        throughput = np.ones(npx, np.float64)
        layers = []

        sea = np.flatnonzero(surface == SEA)
        inc = frame.incidence.reshape(-1, 2)[sea].astype(np.float64)
        rays = frame.sea_rays.reshape(-1, 2, 3)[sea].astype(np.float64)
        d = frame.direction.reshape(-1, 3)[sea].astype(np.float64)
        n1 = frame.normal.reshape(-1, 3)[sea].astype(np.float64)
        # bounce 1: the eye's ray D on the wave normal N₁
        c1 = np.clip(inc[:, 0], 0.0, 1.0)
        layers.append(_water(sea, d, n1, c1, throughput[sea], n))
        throughput[sea] *= reflectance(c1, n)
        last = rays[:, 0]
        # bounce 2: R₁ on N₂ = (R₂ − R₁)/(2 cos i₂)
        two = np.isfinite(inc[:, 1])
        if np.any(two):
            c2 = np.clip(inc[two, 1], 0.0, 1.0)
            r1, r2 = rays[two, 0], rays[two, 1]
            n2 = r2 - r1
            n2 /= np.maximum(np.linalg.norm(n2, axis=-1, keepdims=True), 1e-300)
            idx = sea[two]
            layers.append(_water(idx, r1, n2, c2, throughput[idx], n))
            throughput[idx] *= reflectance(c2, n)
            last = last.copy()
            last[two] = r2
        # the fold: a ray still heading down reflects off the mean surface
        down = last[:, 2] < 0.0
        if np.any(down):
            idx = sea[down]
            ld = last[down]
            c3 = np.clip(-ld[:, 2], 0.0, 1.0)
            up = np.broadcast_to(np.array([0.0, 0.0, 1.0]), ld.shape)
            layers.append(_water(idx, ld, up, c3, throughput[idx], n))
            throughput[idx] *= reflectance(c3, n)

        sky_index = np.flatnonzero(kind == SKY)
        fd = final_dir[sky_index].astype(np.float64)
        rows = sky_row(fd[:, 2]).astype(np.float32)
        az = np.arctan2(fd[:, 1], fd[:, 0]).astype(np.float32)
        return cls(shape=(h, w), final_dir=final_dir, final_kind=kind, final_normal=normal,
                   throughput=throughput.astype(np.float32), water=layers, sky_rows=rows, sky_azimuth=az,
                   sky_index=sky_index, n=float(n))


def _water(index, incident, normal, cos_i, before, n) -> WaterLayer:
    t = refract(incident, normal, cos_i, n)
    up = -t / np.linalg.norm(t, axis=-1, keepdims=True)
    weight = before * (1.0 - reflectance(cos_i, n)) / (n * n)
    return WaterLayer(index=np.asarray(index, np.intp), up=up.astype(np.float32), weight=weight.astype(np.float32))
