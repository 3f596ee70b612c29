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

from ..constants import CLOUD, SKY, WATER_REFRACTIVE_INDEX
from ..errors import SunsetError
from ..kernels import row_strips, run_strips
from .paths import trace_paths
from .water import diffuse_mean_cosine

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
    throughput: np.ndarray     # (N,) float32: product of the Fresnel reflectances
    sky_index: np.ndarray      # (S,) intp: which pixels end in the sky
    sky_dir: np.ndarray        # (S, 3) float32: their final rays
    sky_r0: np.ndarray         # (S,) int32: the refined sky table's row below each ray
    sky_fr: np.ndarray         # (S,) float32: and the fraction towards the next
    sky_azimuth: np.ndarray    # (S,) float32: azimuth of their final rays
    island_index: np.ndarray   # (I,) intp: which pixels end on an island
    island_normal: np.ndarray  # (I, 3) float32: their normals
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
        arrays = [self.final_dir, self.final_kind, self.island_normal, self.throughput, self.sky_index, self.sky_dir,
                  self.sky_r0, self.sky_fr, self.sky_azimuth, self.island_index, self.island_g, self.island_f,
                  self.water_index, self.water_up, self.water_mu, self.water_weight, self.water_sky]
        arrays += [a for a in (self.sky_cloud, self.island_point) if a is not None]
        return int(sum(a.nbytes for a in arrays))

    @property
    def final_normal(self) -> np.ndarray:
        """(N, 3) float32: the final hit's normal at island pixels, 0 elsewhere (made from ``island_normal``)."""
        out = np.zeros_like(self.final_dir)
        out[self.island_index] = self.island_normal
        return out

    @property
    def water(self) -> list:
        """The water of each bounce as :class:`WaterLayer` views into the compressed lists."""
        ends = list(self.water_starts[1:]) + [len(self.water_index)]
        return [WaterLayer(index=self.water_index[a:b], up=self.water_up[a:b], weight=self.water_weight[a:b])
                for a, b in zip(self.water_starts, ends)]

    @classmethod
    def from_frame(cls, frame, n: float = WATER_REFRACTIVE_INDEX) -> "Geometry":
        """Build from a traced frame (after :func:`sunset.render`).

        The frame's rows are cut into strips (:func:`sunset.kernels.row_strips`)
        handed to the threads; each strip's paths are the kernel
        :func:`sunset.light.paths.trace_paths` (NumPy, or its Numba twin), and the
        strips' lists are joined in order, so the geometry is the same bytes
        for any number of threads. ``final_dir`` is the frame's ``ray`` array
        itself (a view, not a copy).
        """
        if frame.final_surface is None or frame.incidence is None:
            raise SunsetError("the frame has no reflected rays: render it with sunset.render first")
        h, w = frame.shape
        npx = h * w
        flat = {name: getattr(frame, name).reshape((npx,) + getattr(frame, name).shape[2:])
                for name in ("surface", "final_surface", "final_part", "final_normal", "direction", "normal",
                             "incidence", "sea_rays", "ray", "bounces", "point")}
        depth = None if frame.cloud_depth is None else frame.cloud_depth.reshape(-1)
        final_dir = flat["ray"]            # the frame's final rays, not copied (float32 already)
        kind = np.empty(npx, np.int8)
        throughput = np.empty(npx, np.float32)

        def rows(r0: int, r1: int) -> dict:
            a, b = r0 * w, r1 * w
            part = {k: v[a:b] for k, v in flat.items()}
            kind[a:b], normal, throughput[a:b], layers = trace_paths(
                part["surface"], part["final_surface"], part["final_part"], part["final_normal"],
                part["direction"], part["normal"], part["incidence"], part["sea_rays"], float(n))
            out = {"layers": [(i + a, up, wt) for i, up, wt in layers]}
            out.update(_lookups(part, kind[a:b], normal, a, None if depth is None else depth[a:b]))
            return out

        strips = run_strips(rows, row_strips(h, w))
        join = lambda key: np.concatenate([s[key] for s in strips])  # noqa: E731
        layers = [tuple(np.concatenate([s["layers"][k][j] for s in strips]) for j in range(3)) for k in range(3)]
        w_index = np.concatenate([layer[0] for layer in layers])
        w_up = np.ascontiguousarray(np.concatenate([layer[1] for layer in layers]))
        w_weight = np.concatenate([layer[2] for layer in layers])
        starts = np.cumsum([0] + [len(layer[0]) for layer in layers[:-1]]).astype(np.intp)
        w_mu = np.maximum(w_up[:, 2], np.float32(0))
        mu_bar = diffuse_mean_cosine(n)
        w_sky = (w_weight.astype(np.float64) / (4.0 * np.pi) / (mu_bar + w_mu.astype(np.float64))).astype(np.float32)
        return cls(shape=(h, w), final_dir=final_dir, final_kind=kind, throughput=throughput,
                   sky_index=join("sky_index"), sky_dir=join("sky_dir"), sky_r0=join("sky_r0"),
                   sky_fr=join("sky_fr"), sky_azimuth=join("sky_azimuth"),
                   island_index=join("island_index"), island_normal=join("island_normal"),
                   island_g=join("island_g"),
                   island_f=join("island_f"), water_starts=starts, water_index=w_index, water_up=w_up,
                   water_mu=w_mu, water_weight=w_weight, water_sky=w_sky, n=float(n),
                   sky_cloud=None if depth is None else join("sky_cloud"),
                   island_point=join("island_point"))


def _lookups(part: dict, kind, normal, offset: int, depth) -> dict:
    """A strip's sky and island lists: which pixels, and where their rays and normals fall in the hour's tables.

    Plain NumPy on both paths (its arcsin and arctan2 are NumPy's, so either
    kernel path gives the same bytes).
    """
    from .lighting import NORMAL_GRID, SKY_REFINE, SKY_ROWS, sky_row

    sky_local = np.flatnonzero(kind == SKY)
    fd = part["ray"][sky_local]
    r_max = (SKY_ROWS - 1) * SKY_REFINE[0]
    rows = np.clip(sky_row(fd[:, 2]) * SKY_REFINE[0], 0, r_max)
    r0 = np.minimum(rows.astype(np.int32), r_max - 1)
    isl_local = np.flatnonzero(kind > 0)
    g = (np.clip(normal[isl_local, :2].astype(np.float64), -1, 1) + 1.0) * (0.5 * (NORMAL_GRID - 1))
    g0 = np.minimum(g.astype(np.int32), NORMAL_GRID - 2)
    direct_hit = part["bounces"][isl_local] == 0
    out = {"sky_index": sky_local + offset, "sky_dir": fd, "sky_r0": r0, "sky_fr": (rows - r0).astype(np.float32),
           "sky_azimuth": np.arctan2(fd[:, 1], fd[:, 0]), "island_index": isl_local + offset,
           "island_normal": normal[isl_local], "island_g": g0,
           "island_f": (g - g0).astype(np.float32),
           "island_point": np.where(direct_hit[:, None], part["point"][isl_local], np.nan).astype(np.float32)}
    if depth is not None:
        out["sky_cloud"] = np.where(part["final_surface"][sky_local] == CLOUD, depth[sky_local],
                                    np.nan).astype(np.float32)
    return out
