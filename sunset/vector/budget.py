"""The work of one frame, predicted from the scene before any ray is traced.

The height field's samples are spaced evenly in u = 1/y, σ pixels apart on
the mean sea plane (:func:`sunset.vector.heightfield.sampling`), from the
farthest, just below the horizon, to the nearest, whose projection lies below
the bottom pixel even on a crest. Their number n per scan line is

    n ≈ |ζ₀| / (σ Δζ) · h / (h − d),

with ζ₀ the bottom pixel's centre, Δζ the pixel pitch, h the eye height and d
the sea's largest elevation: it depends on the picture window, not on the
number of pixels. A window far below the horizon and only a sliver tall asks
for millions of samples per pixel (hours of work and gigabytes of memory for
a 64 × 64 picture); :func:`check_work` refuses it, naming the fields to
change, before any work is done. Each island adds at most
``ISLAND_SAMPLE_BUDGET · max(n, H)`` samples per scan line (the refinement is
lowered to respect it). Memory is :data:`FRAME_BYTES_PER_PIXEL` per pixel
plus the sea's samples of one strip of scan lines
(:data:`SCANLINE_CHUNK_ELEMENTS`, or one scan line's n if larger);
:func:`sunset.bench.memory.measure_bytes_per_pixel` measures the first term.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..constants import (FRAME_BYTES_PER_PIXEL, ISLAND_SAMPLE_BUDGET, MAX_FRAME_BYTES, MAX_SEA_SAMPLES_PER_PIXEL,
                         SCANLINE_CHUNK_ELEMENTS)
from ..errors import SunsetError
from .heightfield import sampling

__all__ = ["Work", "predict_work", "check_work", "SAMPLE_BYTES"]

#: Bytes per sample of the sea's strip of scan lines (the float64 lattice u and
#: the float32 elevation, phase, sum and profile arrays).
SAMPLE_BYTES = 32


@dataclass(frozen=True)
class Work:
    """What rendering one frame of a scene costs, predicted.

    Attributes
    ----------
    sea_samples_per_line : int
        n, the sea's samples on every scan line (exact: the renderer uses this n).
    sea_samples : int
        n × width, the sea's samples in the frame (exact).
    island_samples_bound : int
        The most island samples the frame can take (every island at its budget).
    bytes : int
        The memory bound: pixels × FRAME_BYTES_PER_PIXEL + one strip of sea samples.
    """

    width: int
    height: int
    sea_samples_per_line: int
    sea_samples: int
    island_samples_bound: int
    bytes: int

    @property
    def sea_samples_per_pixel(self) -> float:
        """n / height: the sea's samples per pixel."""
        return self.sea_samples_per_line / self.height


def predict_work(scene) -> Work:
    """Predict the samples and the memory of one frame of ``scene`` (no rendering)."""
    cam = scene.camera
    W, H = cam.width, cam.height
    n = sampling(cam, scene.sea.max_elevation).n
    islands = len(scene.islands) * ISLAND_SAMPLE_BUDGET * max(n, H) * W
    strip = max(SCANLINE_CHUNK_ELEMENTS, n) * SAMPLE_BYTES
    return Work(width=W, height=H, sea_samples_per_line=n, sea_samples=n * W, island_samples_bound=islands,
                bytes=W * H * FRAME_BYTES_PER_PIXEL + strip)


def check_work(scene) -> Work:
    """Raise :class:`SunsetError` when a frame of ``scene`` would exceed the budgets; else its :class:`Work`.

    The sea may take at most MAX_SEA_SAMPLES_PER_PIXEL samples per pixel, and
    the frame at most MAX_FRAME_BYTES of memory.
    """
    work = predict_work(scene)
    cam = scene.camera
    if work.sea_samples_per_pixel > MAX_SEA_SAMPLES_PER_PIXEL:
        raise SunsetError(
            f"camera: the picture window asks for {work.sea_samples_per_pixel:.3g} sea samples per pixel (at most "
            f"{MAX_SEA_SAMPLES_PER_PIXEL}): zy_min = {cam.zy_min:g} .. zy_max = {cam.zy_max:g} is a sliver "
            f"{abs(cam.zy_min) / (cam.zy_max - cam.zy_min):.3g} times its own height below the horizon; "
            f"make the window taller or raise sigma")
    if work.bytes > MAX_FRAME_BYTES:
        raise SunsetError(f"camera: a {work.width}x{work.height} frame needs about "
                          f"{math.ceil(work.bytes / 2**20):,} MiB (at most {MAX_FRAME_BYTES // 2**20:,} MiB): "
                          f"use a smaller picture")
    return work

