"""What stays still through a wave cycle's tape, computed once: then each frame codes only its sea.

In a wave cycle only the sea moves. The islands' share of the direct rays
(:func:`sunset.vector.direct.island_pass`) does not change with time, and
neither does anything the 8-bit code of a pixel depends on where the sea does
not reach it: a direct ray that ends in the sky is coded by its direction
alone, one that ends on an island by the island's part and normal there, and
the dither is reset to the same seed for every frame
(:mod:`sunset.tape.codes`). So :func:`cycle_pass` codes, once per cycle, the
frame of the islands and the sky alone (:func:`sunset.vector.direct.islands_alone`,
then :func:`sunset.tape.codes.encode`): every pixel the sea does not take has
that code in every frame. A frame of the cycle (:func:`code_sea`) then traces
and codes only its sea pixels: the sea's depth buffer
(:func:`sunset.vector.direct.sea_depth`), then strip by strip of rows the sea
pixels' points and normals (:func:`sunset.vector.direct.sea_strip`), their
reflected rays (:func:`sunset.vector.reflect.trace_sea_rays`) and their codes
(:func:`encode_sea_rows`); on one path the codes are byte-identical to
those of :func:`sunset.vector.render.render` and :func:`sunset.tape.codes.encode` (tests).

Scenes with clouds or posts in the water are coded the whole way
(:func:`sunset.tape.cycle.code_frame`): their sky and posts are not still in
the same sense.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..constants import SEA
from ..errors import SunsetError, require_finite, require_int_range
from ..kernels import run_strips, strips, twin
from ..model.sun import Sun
from ..vector.direct import IslandPass, island_key, island_pass, islands_alone, sea_depth, sea_strip
from ..vector.frame import Frame
from ..vector.reflect import trace_sea_rays
from .codes import CodeMap, code_map, dither, encode, encode_pixels

__all__ = ["CyclePass", "cycle_pass", "still_key", "code_sea", "encode_sea_rows"]


@dataclass(frozen=True)
class CyclePass:
    """What every frame of a wave cycle's tape shares (:func:`cycle_pass`); read only.

    Attributes
    ----------
    key : tuple
        What it depends on (:func:`still_key`): the island pass's key, the sun and the dither's seed.
    islands : IslandPass
        The islands' depth buffer of every scan line.
    direction : ndarray (H, W, 3) float32
        Every pixel's direct ray D (the frames' ``direction``).
    codes : ndarray (H, W) uint8
        Each pixel's code when the sea does not take it: its direct ray's, on an island or in the sky.
    seed : int
        The dither's seed (:func:`sunset.tape.codes.dither`).
    """

    key: tuple
    islands: IslandPass
    direction: np.ndarray
    codes: np.ndarray
    seed: int


def still_key(scene, seed: int) -> tuple:
    """What a :class:`CyclePass` depends on: the islands' pass, the sun (the codes) and the seed (the dither)."""
    return (island_key(scene), scene.sun, int(seed))


def cycle_pass(scene, seed: int = 0, islands: IslandPass | None = None) -> CyclePass:
    """The still part of every frame of ``scene``'s wave cycle coded with ``seed`` (:class:`CyclePass`).

    ``islands``: the scene's island pass, when it is already there.
    """
    require_int_range("seed", seed, 0, 2**32 - 1)
    if islands is None:
        islands = island_pass(scene)
    frame = islands_alone(scene, islands).finish_direct(False)
    codes = encode(scene, frame, seed=seed)
    for a in (frame.direction, codes):
        a.flags.writeable = False
    return CyclePass(key=still_key(scene, seed), islands=islands, direction=frame.direction, codes=codes,
                     seed=int(seed))


def code_sea(scene, t: float, reflections: int, seed: int, still: CyclePass) -> np.ndarray:
    """The codes (H, W) uint8 of ``scene`` at ``t``: the sea's pixels traced and coded, the others from ``still``.

    The same bytes as ``encode(scene, render(scene, t, reflections), seed)``
    for a scene without clouds or posts. After the depth buffer
    (:func:`sunset.vector.direct.sea_depth`), the frame is made strip by
    strip of rows (:data:`SEA_STRIP_PIXELS`), on all threads: a strip's sea
    geometry (:func:`sunset.vector.direct.sea_strip`), its reflected rays
    (:func:`sunset.vector.reflect.trace_sea_rays`) and its codes
    (:func:`encode_sea_rows`) one after the other, while its arrays are in
    the cache; no array of the whole frame is made but the codes.
    """
    require_finite("t", t)
    require_int_range("reflections", reflections, 0, 2)
    if still.key != still_key(scene, seed):
        raise SunsetError("islands: this cycle pass was computed for another camera, islands, sea height, sun or seed")
    if scene.clouds is not None or scene.posts:
        raise SunsetError("a scene with clouds or posts is coded the whole way (sunset.tape.cycle.code_frame)")
    t = float(t)
    depth = sea_depth(scene, t, still.islands)
    H, W = still.codes.shape
    codes = np.empty((H, W), np.uint8)
    sun, cmap = scene.sun, code_map(scene)

    def rows(r0: int, r1: int) -> None:
        part = sea_strip(scene, t, depth, still.direction, r0, r1)
        shape = part.shape
        # the final fields: written by the reflections on the sea pixels, read only there
        part.reflections = reflections
        part.bounces = np.empty(shape, np.uint8)
        part.ray = np.empty(shape + (3,), np.float32)
        part.final_surface = np.empty(shape, np.int8)
        part.final_part = np.empty(shape, np.int8)
        part.final_normal = np.empty(shape + (3,), np.float32)
        if np.any(part.surface == SEA):
            trace_sea_rays(scene, part, reflections)
        encode_sea_rows(codes[r0:r1], part, still.codes[r0:r1], seed, r0, sun, cmap)

    run_strips(rows, strips(H, max(1, SEA_STRIP_PIXELS // W)))
    return codes


#: Pixels in a strip of :func:`code_sea` at most: its arrays (about 80 bytes a pixel) stay in a core's cache.
SEA_STRIP_PIXELS = 1 << 15


@twin("sunset.tape.codes_numba")
def encode_sea_rows(codes, frame: Frame, still, seed: int, r0: int, sun: Sun, cmap: CodeMap) -> None:
    """Code the rows ``r0 …`` of a cycle's frame (``frame``, ``still`` and ``codes`` hold those rows).

    Off the sea (``frame.surface``), the still codes; on it,
    :func:`sunset.tape.codes.encode_pixels` of the final fields with the
    rows' dither numbers of ``seed`` (:func:`sunset.tape.codes.dither`).
    """
    codes[...] = still
    sea = np.asarray(frame.surface) == SEA
    if not np.any(sea):
        return
    shape = codes.shape
    # the final fields are read on the sea pixels alone: the others are marked as no surface to code
    only = replace(frame, final_surface=np.where(sea, frame.final_surface, SEA).astype(np.int8))
    out = np.zeros(shape, np.uint8)
    u = dither(seed, r0 * shape[1], shape, 0)
    v = dither(seed, r0 * shape[1], shape, 1)
    encode_pixels(out, only, u, v, sun, cmap)
    codes[sea] = out[sea]
