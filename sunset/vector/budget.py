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
``2 · ISLAND_SAMPLE_BUDGET · max(n, H)`` samples per scan line: its probe
holds at most the budget (a chord spanning more of the sea's samples is
probed on a coarser lattice, :func:`sunset.vector.island_samples.probe_refinement`),
and the refinement is lowered to keep the cut probe within the budget plus
one sample per probe interval. A cloud layer (:mod:`sunset.vector.clouds`) takes, per cell, its
lattice's samples and the (sample, pixel) pairs they cover: the samples are
counted exactly and the pairs bounded (:func:`sunset.vector.clouds.cell_work`)
without evaluating a cloud; a cloud far taller than its height above the eye
covers hundreds of pixels with every sample. Each post tests at most every
pixel twice (its box of direct rays, then the sea's reflected rays).

The frame's predicted work is the sum of these counts; :func:`check_work`
refuses a frame whose work exceeds :data:`~sunset.constants.MAX_FRAME_SAMPLES`
(naming the islands, the clouds or the window), as it refuses a window whose
sea takes more than :data:`~sunset.constants.MAX_SEA_SAMPLES_PER_PIXEL`.

Memory, for either path (the compiled kernels or the NumPy reference, which
holds whole strips where its twin holds one scan line: the prediction is the
reference's, the larger)::

    bytes = FRAME_FIXED_BYTES + W·H·FRAME_BYTES_PER_PIXEL + threads·strip + clouds

with ``threads`` the frame's threads (:func:`sunset.kernels.threads`, at
most the usable CPUs) each holding one strip: the larger of the sea's
samples of a strip of scan lines (:data:`~sunset.constants.SCANLINE_CHUNK_ELEMENTS`,
or one scan line's n if larger, :data:`SAMPLE_BYTES` each), the islands'
(their budget per scan line, the probe and the samples padded to twice it,
:data:`ISLAND_STRIP_BYTES`) and a strip of rows (:data:`~sunset.constants.STRIP_PIXELS`,
:data:`ROW_STRIP_BYTES` each); ``clouds`` the largest strip of a cloud
cell's samples and pairs (at most :data:`~sunset.constants.CLOUD_STRIP_PAIRS`;
:data:`~sunset.constants.CLOUD_BYTES_PER_SAMPLE`,
:data:`~sunset.constants.CLOUD_BYTES_PER_PAIR`). The interpreter's own
memory, :data:`~sunset.constants.INTERPRETER_BYTES`, comes on top:
:func:`check_work` refuses a frame whose total exceeds
:data:`~sunset.constants.MAX_FRAME_BYTES`.
:func:`sunset.bench.memory.measure_bytes_per_pixel` measures the per-pixel
term; :func:`sunset.bench.memory.measure_command_peak` a whole command's
peak in a fresh process (``tests/test_memory_peak.py`` checks it against
``bytes`` over windows from 10⁻⁶ tall to the whole view).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..constants import (CLOUD_BYTES_PER_PAIR, CLOUD_BYTES_PER_SAMPLE, FRAME_BYTES_PER_PIXEL, FRAME_FIXED_BYTES,
                         INTERPRETER_BYTES, ISLAND_SAMPLE_BUDGET, MAX_FRAME_BYTES, MAX_FRAME_SAMPLES,
                         MAX_SEA_SAMPLES_PER_PIXEL, SCANLINE_CHUNK_ELEMENTS, STRIP_PIXELS)
from ..errors import SunsetError
from .heightfield import Sampling, sampling

__all__ = ["Work", "predict_work", "check_work", "SAMPLE_BYTES", "ISLAND_STRIP_BYTES", "ROW_STRIP_BYTES"]

#: Bytes per sample of the sea's strip of scan lines (the float64 lattice u and
#: the float32 elevation, phase, sum and profile arrays; 16–25 measured on a full strip).
SAMPLE_BYTES = 32

#: Bytes per sample of the islands' budget in a strip of the NumPy reference
#: (the probe and its steps, the padded samples, their profile and scan; up to 82 measured).
ISLAND_STRIP_BYTES = 128

#: Bytes per pixel of a strip of rows in flight on a thread (reflections, codes, the film recorder).
ROW_STRIP_BYTES = 256


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
        The most island samples the frame can take (every island at twice its budget: see above).
    cloud_samples : int
        The cloud layer's samples, all cells (exact).
    cloud_pairs_bound : int
        The most (sample, pixel) pairs the cloud layer's samples cover.
    post_tests_bound : int
        The most ray–post tests (2 × posts × pixels).
    bytes : int
        The memory bound of the work, on top of the interpreter's INTERPRETER_BYTES: FRAME_FIXED_BYTES +
        pixels × FRAME_BYTES_PER_PIXEL + a strip per thread + the largest strip of a cloud cell.
    threads : int
        The threads the prediction counts, each with a strip in flight.
    sampling : Sampling
        Where the sea is sampled along every scan line (:func:`sunset.vector.heightfield.sampling`): the
        renderer's lattice, computed once here and passed down by the pipeline (:mod:`sunset.pipeline.budget`).
    """

    width: int
    height: int
    sea_samples_per_line: int
    sea_samples: int
    island_samples_bound: int
    bytes: int
    cloud_samples: int = 0
    cloud_pairs_bound: int = 0
    post_tests_bound: int = 0
    threads: int = 1
    sampling: Sampling | None = None

    @property
    def total_bytes(self) -> int:
        """The command's memory: the interpreter's (INTERPRETER_BYTES) and the work's."""
        return INTERPRETER_BYTES + self.bytes

    @property
    def sea_samples_per_pixel(self) -> float:
        """n / height: the sea's samples per pixel."""
        return self.sea_samples_per_line / self.height

    @property
    def samples(self) -> int:
        """The frame's predicted work: sea and island samples, cloud samples and pairs, post tests (a bound)."""
        return (self.sea_samples + self.island_samples_bound + self.cloud_samples + self.cloud_pairs_bound
                + self.post_tests_bound)


def _cloud_work(scene) -> tuple[int, int, int]:
    """(samples, pairs bound, bytes of the largest cell) of the scene's cloud layer."""
    if scene.clouds is None:
        return 0, 0, 0
    from .clouds import cloud_strips, column_work

    cam = scene.camera
    dz = cam.pixel_pitch[1]
    zeta0 = cam.zy_min + 0.5 * dz
    level_h = scene.clouds.level - cam.eye_height
    s = cam.s_centres()
    samples = pairs = biggest = 0
    for cell in scene.clouds.cells:
        count, bound = column_work(cell, level_h, s, zeta0, dz, cam.height, cam.sigma)
        samples, pairs = samples + int(count.sum()), pairs + int(bound.sum())
        for c0, c1 in cloud_strips(count, bound):           # the strips cloud_scan takes
            biggest = max(biggest, int(count[c0:c1].sum()) * CLOUD_BYTES_PER_SAMPLE
                          + int(bound[c0:c1].sum()) * CLOUD_BYTES_PER_PAIR)
    return samples, pairs, biggest


def strip_bytes(scene, samp: Sampling | None = None) -> int:
    """The most one thread holds at once of a frame of ``scene``: a strip of sea samples, of island samples, of rows.

    ``samp``: the scene's sampling, when it is already there.
    """
    cam = scene.camera
    n = (samp or sampling(cam, scene.sea.max_elevation)).n
    budget = ISLAND_SAMPLE_BUDGET * max(n, cam.height)
    sea = max(SCANLINE_CHUNK_ELEMENTS, n) * SAMPLE_BYTES
    islands = max(SCANLINE_CHUNK_ELEMENTS, budget) * ISLAND_STRIP_BYTES if scene.islands else 0
    return max(sea, islands, min(STRIP_PIXELS, cam.width * cam.height) * ROW_STRIP_BYTES)


def predict_work(scene, threads: int | None = None) -> Work:
    """Predict the samples and the memory of one frame of ``scene`` (no rendering).

    ``threads``: the frame's threads (default :func:`sunset.kernels.threads`).
    """
    from ..kernels import threads as current_threads

    cam = scene.camera
    W, H = cam.width, cam.height
    samp = sampling(cam, scene.sea.max_elevation)
    n = samp.n
    islands = len(scene.islands) * 2 * ISLAND_SAMPLE_BUDGET * max(n, H) * W
    threads = min(int(current_threads() if threads is None else threads), W)
    cloud_samples, cloud_pairs, cloud_bytes = _cloud_work(scene)
    memory = FRAME_FIXED_BYTES + W * H * FRAME_BYTES_PER_PIXEL + threads * strip_bytes(scene, samp) + cloud_bytes
    return Work(width=W, height=H, sea_samples_per_line=n, sea_samples=n * W, island_samples_bound=islands,
                bytes=memory, cloud_samples=cloud_samples, cloud_pairs_bound=cloud_pairs,
                post_tests_bound=2 * len(scene.posts) * W * H, threads=threads, sampling=samp)


def check_work(scene) -> Work:
    """Raise :class:`SunsetError` when a frame of ``scene`` would exceed the budgets; else its :class:`Work`.

    The sea may take at most MAX_SEA_SAMPLES_PER_PIXEL samples per pixel, the
    frame at most MAX_FRAME_SAMPLES samples in all (sea, islands, clouds,
    posts) and at most MAX_FRAME_BYTES of memory.
    """
    work = predict_work(scene)
    cam = scene.camera
    if work.sea_samples_per_pixel > MAX_SEA_SAMPLES_PER_PIXEL:
        raise SunsetError(
            f"camera: the picture window asks for {work.sea_samples_per_pixel:.3g} sea samples per pixel (at most "
            f"{MAX_SEA_SAMPLES_PER_PIXEL}): zy_min = {cam.zy_min:g} .. zy_max = {cam.zy_max:g} is a sliver "
            f"{abs(cam.zy_min) / (cam.zy_max - cam.zy_min):.3g} times its own height below the horizon; "
            f"make the window taller or raise sigma")
    if work.samples > MAX_FRAME_SAMPLES:
        size = f"{work.width}x{work.height}"
        terms = {"islands": work.island_samples_bound, "clouds": work.cloud_samples + work.cloud_pairs_bound,
                 "posts": work.post_tests_bound, "camera": work.sea_samples}
        biggest = max(terms, key=terms.get)
        what, fix = {
            "islands": (f"{len(scene.islands)} islands", "use fewer islands or a smaller picture"),
            "clouds": ("the cloud layer", "use fewer or thinner cells (top, bottom), a higher level or a smaller "
                                          "picture"),
            "posts": (f"{len(scene.posts)} posts", "use fewer posts or a smaller picture"),
            "camera": ("the sea", "use a smaller picture, a taller window or a larger sigma")}[biggest]
        what = f"{biggest}: {what} at {size} may take up to {work.samples:.3g} samples"
        raise SunsetError(f"{what} per frame (at most {MAX_FRAME_SAMPLES:.3g}): {fix}")
    if work.total_bytes > MAX_FRAME_BYTES:
        raise SunsetError(f"camera: a {work.width}x{work.height} frame on {work.threads} threads needs about "
                          f"{math.ceil(work.total_bytes / 2**20):,} MiB with the interpreter's "
                          f"{INTERPRETER_BYTES // 2**20} (at most {MAX_FRAME_BYTES // 2**20:,} MiB): "
                          f"use a smaller picture, a taller window or fewer threads (SUNSET_THREADS)")
    return work
