"""The frame: what the vector stage knows about every pixel.

A :class:`Frame` is filled in two steps, mirroring the paper's pipeline:

1. direct rays (``sunset.vector.heightfield`` and ``sunset.model.islands``): what the ray
   from the eye through each pixel centre meets first;
2. reflected rays (``sunset.vector.pierce``): for sea pixels, where the ray goes after
   one or two reflections on the water, and what it finally meets.

Arrays are (height, width) or (height, width, 3), row 0 at the top of the
picture, column 0 at the left (the first scan line).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..constants import SEA, SKY
from ..errors import SunsetError, real_number, require_int_range, require_time, shown


#: Each array of a frame: its shape after (H, W) and the kinds of its dtype (float, integer).
_FIELDS = {"direction": ((3,), "f"), "surface": ((), "i"), "part": ((), "i"), "distance": ((), "f"),
           "point": ((3,), "f"), "normal": ((3,), "f"), "bounces": ((), "u"), "ray": ((3,), "f"),
           "final_surface": ((), "i"), "final_part": ((), "i"), "final_normal": ((3,), "f"),
           "cloud_depth": ((), "f"), "incidence": ((2,), "f"), "sea_rays": ((2, 3), "f")}
#: (The stages make frames of some fields only, such as a strip's sea: every array but ``surface`` may be None.)
_REQUIRED = ("surface",)


@dataclass(repr=False)
class Frame:
    """Per-pixel results of the vector stage for one scene at one time.

    Attributes
    ----------
    t : float
        Time, seconds.
    reflections : int
        The reflection mode it was rendered with (0, 1 or 2).
    direction : ndarray (H, W, 3) float32
        Unit direction D of the direct ray through the pixel centre.
    surface : ndarray (H, W) int8
        What the direct ray meets: −1 sky, 0 sea, k >= 1 island k (1-based);
        −2 a cloud, −3 a post (scenes with clouds or posts).
    part : ndarray (H, W) int8
        For islands, which part: 1 beach, 2 cliff, 3 hill; for posts, the
        post's index from 1; 0 otherwise.
    distance : ndarray (H, W) float32
        Distance along the direct ray to the hit, metres; +inf for sky.
    point : ndarray (H, W, 3) float32
        The hit point, metres (eye at the origin); NaN for sky.
    normal : ndarray (H, W, 3) float32
        Unit surface normal at the hit; NaN for sky.
    bounces : ndarray (H, W) uint8
        Number of water reflections the ray made (0, 1 or 2).
    ray : ndarray (H, W, 3) float32
        The final ray direction: D for sky and island pixels, the (last)
        reflected ray for sea pixels (with ``|R_z|`` applied where the mode says).
    final_surface : ndarray (H, W) int8
        What the ray finally meets: −1 sky or k >= 1 island k.
    final_part : ndarray (H, W) int8
        The island part of the final hit; 0 for sky.
    final_normal : ndarray (H, W, 3) float32
        Unit normal at the final hit (for islands); NaN for sky.
    cloud_depth : ndarray (H, W) float32 or None
        Only for a scene with clouds: the depth below the mean cloud level of
        the cloud the ray finally meets, metres (negative above the level); NaN
        where it meets none. ``surface`` and ``final_surface`` are
        :data:`~sunset.constants.CLOUD` (−2) there.
    incidence : ndarray (H, W, 2) float32
        Cosine of the angle of incidence at the first and the second sea
        hit (−D·N, then −R₁·N₂); NaN where the ray made no such reflection.
        Slightly negative where a sampled hit sees a wave's back at grazing
        incidence. What Fresnel's law needs (:mod:`sunset.light`); the 8-bit
        codes do not use it.
    sea_rays : ndarray (H, W, 2, 3) float32
        The ray leaving the first and the second sea hit, R₁ and R₂, before
        the ``|R_z|`` of the reflection modes; NaN where there is no such bounce.
        With ``direction`` they give each bounce's normal,
        N_k ∝ R_k − I_k, I₁ = D, I₂ = R₁ (:mod:`sunset.light`).
        ``incidence`` and ``sea_rays`` are None unless the frame was rendered
        with them (``render(..., sea_bounces=True)``, as the RGB back end asks;
        the 8-bit tape does without them).
    """

    t: float
    reflections: int
    direction: np.ndarray
    surface: np.ndarray
    part: np.ndarray
    distance: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    bounces: np.ndarray | None = None
    ray: np.ndarray | None = None
    final_surface: np.ndarray | None = None
    final_part: np.ndarray | None = None
    final_normal: np.ndarray | None = None
    cloud_depth: np.ndarray | None = None
    incidence: np.ndarray | None = None
    sea_rays: np.ndarray | None = None

    def __post_init__(self):
        require_time("t", real_number("t", self.t))
        require_int_range("reflections", self.reflections, 0, 2)
        if not isinstance(self.surface, np.ndarray) or self.surface.ndim != 2 or self.surface.dtype.kind != "i":
            raise SunsetError(f"surface must be an (H, W) integer array, got {shown(self.surface)}")
        H, W = self.surface.shape
        for name, (tail, kinds) in _FIELDS.items():
            value = getattr(self, name)
            if value is None and name not in _REQUIRED:
                continue
            if (not isinstance(value, np.ndarray) or value.shape != (H, W) + tail
                    or value.dtype.kind not in kinds):
                want = "a float" if kinds == "f" else "an integer"
                raise SunsetError(f"{name} must be {want} array of shape {(H, W) + tail} (the surface's "
                                  f"{H}×{W}), got {shown(value)}")

    @property
    def shape(self) -> tuple[int, int]:
        """(height, width) in pixels."""
        return self.surface.shape

    def __repr__(self) -> str:
        h, w = self.shape
        n = max(1, h * w)
        sky = 100.0 * np.count_nonzero(self.surface == SKY) / n
        sea = 100.0 * np.count_nonzero(self.surface == 0) / n
        return (f"Frame(t={self.t:g} s, {w}×{h}, reflections={self.reflections}: "
                f"{sky:.0f}% sky, {sea:.0f}% sea, {100.0 - sky - sea:.0f}% islands)")

    def finish_direct(self, sea_bounces: bool = True, *, sea_rows: bool = True) -> "Frame":
        """Fill the final-ray fields as if no ray reflected (direct rays only): :meth:`allocate_final`, then
        :meth:`finish_rows` over all rows.

        Sky and island pixels end where the direct ray ends; sea pixels keep
        ``final_surface`` = 0 until :mod:`sunset.vector.reflect` traces them.
        ``sea_bounces``: also make ``incidence`` and ``sea_rays`` (NaN until
        the sea's rays are traced), which the RGB back end reads and the
        8-bit codes do not (32 bytes a pixel). ``sea_rows=False``: leave
        ``ray`` and ``final_normal`` unset in the rows that are all sea, for
        :func:`sunset.vector.reflect.trace_sea_rays`, which writes them in
        every sea pixel (24 bytes a pixel not copied there). The pipeline
        does the same strip by strip on its threads.
        """
        self.allocate_final(sea_bounces)
        self.finish_rows(0, self.shape[0], sea_rows=sea_rows)
        return self

    def allocate_final(self, sea_bounces: bool = True) -> "Frame":
        """Make the final-ray fields (unset; :meth:`finish_rows` fills them), with the sea's bounces if asked."""
        self.bounces = np.empty(self.shape, np.uint8)
        self.ray = np.empty_like(self.direction)
        self.final_surface = np.empty_like(self.surface)
        self.final_part = np.empty_like(self.part)
        self.final_normal = np.empty_like(self.normal)
        if sea_bounces:
            self.incidence = np.empty(self.shape + (2,), np.float32)
            self.sea_rays = np.empty(self.shape + (2, 3), np.float32)
        return self

    def finish_rows(self, r0: int, r1: int, *, sea_rows: bool = True) -> None:
        """The rows ``r0:r1`` of :meth:`finish_direct` (after :meth:`allocate_final`)."""
        self.bounces[r0:r1] = 0
        self.final_surface[r0:r1] = self.surface[r0:r1]
        self.final_part[r0:r1] = self.part[r0:r1]
        if sea_rows:
            self.ray[r0:r1] = self.direction[r0:r1]
            self.final_normal[r0:r1] = self.normal[r0:r1]
        else:
            keep = r0 + np.flatnonzero(~np.all(self.surface[r0:r1] == SEA, axis=1))
            if len(keep) == r1 - r0:
                self.ray[r0:r1] = self.direction[r0:r1]
                self.final_normal[r0:r1] = self.normal[r0:r1]
            elif len(keep):
                self.ray[keep] = self.direction[keep]
                self.final_normal[keep] = self.normal[keep]
        if self.incidence is not None:
            self.incidence[r0:r1] = np.nan
            self.sea_rays[r0:r1] = np.nan

    def rows(self, r0: int, r1: int) -> "Frame":
        """The rows ``r0 … r1 − 1`` as a frame of views into this one (writing to it writes here)."""
        views = {}
        for f in fields(self):
            value = getattr(self, f.name)
            views[f.name] = value[r0:r1] if isinstance(value, np.ndarray) else value
        return Frame(**views)

    @property
    def sky(self) -> np.ndarray:
        """Boolean mask of pixels whose direct ray meets the sky."""
        return self.surface == SKY
