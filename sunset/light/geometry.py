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

import threading
from dataclasses import dataclass

import numpy as np

from ..constants import CLOUD, SKY, WATER_REFRACTIVE_INDEX
from ..errors import SunsetError
from ..kernels import row_strips, run_strips
from .paths import lookups, trace_paths
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
    glitter: object | None = None           # a wind sea's sea pixels for the sun's glitter (sunset.light.glitter.Glitter)

    @property
    def nbytes(self) -> int:
        arrays = [self.final_dir, self.final_kind, self.island_normal, self.throughput, self.sky_index, self.sky_dir,
                  self.sky_r0, self.sky_fr, self.sky_azimuth, self.island_index, self.island_g, self.island_f,
                  self.water_index, self.water_up, self.water_mu, self.water_weight, self.water_sky]
        arrays += [a for a in (self.sky_cloud, self.island_point) if a is not None]
        return int(sum(a.nbytes for a in arrays)) + (0 if self.glitter is None else self.glitter.nbytes)

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
        """Build from a traced frame that recorded the sea's bounces (``sunset.render(..., sea_bounces=True)``).

        The frame's rows are cut into strips (:func:`sunset.kernels.row_strips`)
        handed to the threads; each strip's paths are the kernel
        :func:`sunset.light.paths.trace_paths` (NumPy, or its Numba twin), and the
        strips' lists are joined in order, so the geometry is the same bytes
        for any number of threads. ``final_dir`` is the frame's ``ray`` array
        itself (a view, not a copy).
        """
        if frame.final_surface is None:
            raise SunsetError("frame: it has no reflected rays: render it with sunset.render(..., sea_bounces=True)")
        if frame.incidence is None:
            raise SunsetError("frame: it has no sea bounces, which the RGB back end shades: render it with "
                              "sunset.render(..., sea_bounces=True)")
        h, w = frame.shape
        npx = h * w
        flat = {name: getattr(frame, name).reshape((npx,) + getattr(frame, name).shape[2:])
                for name in ("surface", "final_surface", "final_part", "final_normal", "direction", "normal",
                             "incidence", "sea_rays", "ray", "bounces", "point")}
        depth = None if frame.cloud_depth is None else frame.cloud_depth.reshape(-1)
        final_dir = flat["ray"]            # the frame's final rays, not copied (float32 already)
        kind = np.empty(npx, np.int8)
        throughput = np.empty(npx, np.float32)
        mu_bar = diffuse_mean_cosine(n)

        bands = row_strips(h, w)
        lists = _Lists(npx, [r0 for r0, _ in bands])

        def rows(r0: int, r1: int) -> None:
            a, b = r0 * w, r1 * w
            try:
                part = {k: v[a:b] for k, v in flat.items()}
                kind[a:b], normal, throughput[a:b], layers = trace_paths(
                    part["surface"], part["final_surface"], part["final_part"], part["final_normal"],
                    part["direction"], part["normal"], part["incidence"], part["sea_rays"], float(n))
                out = lookups(part["ray"], part["final_surface"], part["bounces"], part["point"], kind[a:b], normal,
                              a, None if depth is None else depth[a:b])
                for k, (i, up, wt) in enumerate(layers):
                    out.update({(key, k): v for key, v in zip(_WATER, _water(i + a, up, wt, mu_bar))})
            except BaseException:
                lists.append(r0, None)      # the strips after it are not kept waiting
                raise
            lists.append(r0, out)

        rows(*bands[0])     # here: the lists' arrays are made by this thread, from the memory it has freed
        run_strips(rows, bands[1:])
        fields, counts = lists.joined()
        starts = np.cumsum([0] + counts[:2]).astype(np.intp)
        return cls(shape=(h, w), final_dir=final_dir, final_kind=kind, throughput=throughput,
                   water_starts=starts, n=float(n), **fields)


class _Lists:
    """The lists of one frame's geometry, each strip's appended in the strips' order into arrays made once.

    Joining the strips' lists after all of them are made holds them twice (the strips' pieces and the
    joined copies: a 4-sample RGB frame's geometry is some 250 MB). Here each strip, once made, waits
    for the strip before it to be appended and appends its own, in place, into arrays with room for
    every pixel (the first bounce's water for all three bounces), so its pieces are freed (and their
    memory reused by the next strips) as it goes, and only the pages written are touched. The values are
    those of ``np.concatenate`` of the strips' lists, in order, in views of those arrays.
    """

    def __init__(self, npx: int, firsts: list):
        self.npx = npx
        self.order = {r0: i for i, r0 in enumerate(firsts)}      # a strip by its first row
        self.arrays = {}
        self.ends = {}
        self.turn = 0
        self.failed = False
        self.cond = threading.Condition()

    def append(self, r0: int, out: dict | None) -> None:
        """Append the lists of the strip from row ``r0`` (``None``: it failed) after the strip before it's."""
        i = self.order[r0]
        with self.cond:
            self.cond.wait_for(lambda: self.turn == i or self.failed)
            try:
                if out is None or self.failed:
                    self.failed = True      # a strip failed: none more appended, none kept waiting
                    return
                for key, v in out.items():
                    arr = self.arrays.get(key)
                    if arr is None:
                        room = self.npx * (3 if isinstance(key, tuple) and key[1] == 0 else 1)
                        arr = self.arrays[key] = np.empty((room,) + v.shape[1:], v.dtype)
                        self.ends[key] = 0
                    e = self.ends[key]
                    arr[e:e + len(v)] = v
                    self.ends[key] = e + len(v)
                self.turn = i + 1
            finally:
                self.cond.notify_all()

    def joined(self) -> tuple[dict, list]:
        """The lists (the water's three bounces one after the other) and the water entries of each bounce."""
        fields = {key: arr[:self.ends[key]] for key, arr in self.arrays.items() if isinstance(key, str)}
        counts = [self.ends[(_WATER[0], k)] for k in range(3)]
        for key in _WATER:
            arr, end = self.arrays[(key, 0)], counts[0]
            for k in (1, 2):
                arr[end:end + counts[k]] = self.arrays[(key, k)][:counts[k]]
                end += counts[k]
            fields[key] = arr[:end]
        return fields, counts


#: The water lists' fields, in the order :func:`_water` gives them.
_WATER = ("water_index", "water_up", "water_weight", "water_mu", "water_sky")


def _water(index, up, weight, mu_bar: float) -> tuple:
    """One strip's water of one bounce, with μ = max(up_z, 0) and the skylight's factor weight (1/4π)/(μ̄ + μ)."""
    mu = np.maximum(up[:, 2], np.float32(0))
    sky = (weight.astype(np.float64) / (4.0 * np.pi) / (mu_bar + mu.astype(np.float64))).astype(np.float32)
    return index, up, weight, mu, sky
