"""The tape's codes, as a strip kernel: each pixel of a strip of rows coded into 8 bits by the code map.

The Cray wrote one byte per pixel; the film recorder turned bytes into colours
through translation tables (:mod:`sunset.recorder.dicomed`). What each code
means, and the rules from a pixel's final ray to its code, are the code map
(:mod:`sunset.tape.codemap`); :func:`encode_strip` applies them to a strip of
rows of a traced frame (:func:`encode_rows`, :func:`encode_pixels`, then the
posts and the clouds), and the pipeline runs it over a frame's strips
(:func:`sunset.pipeline.frame.encode`).

The random numbers (:func:`dither`) are a counter-based generator: pixel n's
two numbers are SplitMix64's outputs 2n and 2n + 1 from the seed, each a hash
of the seed and its counter alone. Any strip of rows computes its own
numbers, and the compiled coder computes them inside its loop, in the same
64-bit integer arithmetic (it wraps modulo 2⁶⁴ in NumPy and in Numba alike):
the two paths use the same numbers, exactly, and no one has to draw a stream
of a frame's length first.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..constants import CLOUD, HALO_FACTOR, PART_BEACH, PART_CLIFF, PART_HILL, POST, SEA, SKY, TRACK_DITHER
from ..errors import SunsetError, require_instance
from ..kernels import twin
from ..model.sun import Sun
from ..vector.frame import Frame
from .codemap import (CLOUDY_CODE_MAP, CODE_MAP, CodeMap, CodeRange, cloud_code_depths, cloud_index,  # noqa: F401
                      code_map, elevation_index, island_code_rho, island_offsets, rho, rho_hat, sky_code_z, sky_index,
                      sun_plane_angle, track_code_elevations, track_elevation_max)

__all__ = ["check_frame", "encode_strip", "encode_rows", "encode_pixels", "encode_sea_rows", "dither", "SPLITMIX_GAMMA",
           "SPLITMIX_M1", "SPLITMIX_M2"]


def check_frame(frame: Frame, shape: tuple[int, int]) -> None:
    """Raise :class:`SunsetError` unless ``frame`` is a traced frame of ``shape`` (its final fields filled)."""
    require_instance("frame", frame, Frame)
    for name in ("ray", "final_surface", "final_part", "final_normal", "bounces"):
        if getattr(frame, name) is None:
            raise SunsetError(f"frame.{name} is not filled: trace the frame's reflections before coding it")
    if frame.shape != shape:
        raise SunsetError(f"frame shape {frame.shape} does not match the scene's camera {shape}")
    if np.any(frame.final_surface == SEA):
        raise SunsetError("frame.final_surface has sea pixels: trace the frame's reflections before coding it")


def _rows(field, mask) -> np.ndarray:
    """``field[mask]`` as float64 (N, 3) for an (H, W, 3) field: compress first (np.take by rows), then widen."""
    flat = np.asarray(field).reshape(-1, 3)
    return np.take(flat, np.flatnonzero(mask), axis=0).astype(float)


def encode_strip(scene, frame: Frame, seed: int, r0: int, cmap: CodeMap,
                 codes) -> None:
    """Code the rows ``r0 …`` of a traced frame into 8 bits: ``frame`` and
    ``codes`` hold just those rows.

    Reads only the frame's final fields: ``final_surface``, ``final_part``,
    ``final_normal``, ``ray`` and ``bounces`` (and ``cloud_depth`` under a
    cloud layer). The islands, the sky and the sea's reflections by
    :func:`encode_rows`; posts in the water as the cliff by ρ̂(N); clouds by
    their depth below the mean level. ``seed``: the dither's
    (:func:`dither`), the same for every frame, so a still scene codes the
    same way in every frame; ``cmap``: the scene's code map
    (:func:`sunset.tape.codemap.code_map`).
    """
    sun = scene.sun
    u = encode_rows(codes, frame, seed, r0, sun, cmap)
    if u is None:                        # no posts or clouds in these rows
        return
    post = np.asarray(frame.final_surface) == POST
    if np.any(post):  # posts in the water: wood, coded as the cliff by ρ̂(N)
        rh = rho_hat(_rows(frame.final_normal, post), sun)
        offsets = island_offsets(rh, cmap.cliff.size, u[post])
        codes[post] = cmap.cliff.start + offsets
    # clouds by depth below the mean level, seen directly or by reflection
    if cmap.cloud is not None:
        cloud = np.asarray(frame.final_surface) == CLOUD
        if np.any(cloud):
            clouds = scene.clouds
            index = cloud_index(frame.cloud_depth[cloud], cmap.cloud.size,
                                clouds.max_top, clouds.max_bottom, u[cloud])
            codes[cloud] = cmap.cloud.start + index


#: SplitMix64's constants (Steele, Lea and Flood 2014; Vigna's ``splitmix64.c``): the counter's step γ and the
#: two multipliers of the output's mixing.
SPLITMIX_GAMMA, SPLITMIX_M1, SPLITMIX_M2 = 0x9E3779B97F4A7C15, 0xBF58476D1CE4E5B9, 0x94D049BB133111EB


def dither(seed: int, start: int, shape, which: int) -> np.ndarray:
    """The dither numbers in [0, 1) of the pixels ``start`` … ``start + prod(shape) − 1`` (row-major in the frame).

    ``which`` = 0 gives u (added before every truncation), 1 gives v (added
    to |W·R|). Pixel n's u and v are the outputs 2n and 2n + 1 of SplitMix64
    seeded with ``seed``: with the counter c = seed + (2n + 1 + which)·γ
    (mod 2⁶⁴), z = c ⊕ (c ≫ 30), z = z·M₁, z = z ⊕ (z ≫ 27), z = z·M₂,
    z = z ⊕ (z ≫ 31), and the number is z's top 53 bits over 2⁵³. Each is
    a function of the seed and the pixel's index alone, so a strip of rows
    computes its own, and the compiled coder the same numbers in its loop.
    """
    count = math.prod(shape)
    n = np.arange(start, start + count, dtype=np.uint64)
    z = np.uint64(seed) + (np.uint64(2) * n + np.uint64(1 + which)) * np.uint64(SPLITMIX_GAMMA)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(SPLITMIX_M1)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(SPLITMIX_M2)
    z ^= z >> np.uint64(31)
    return ((z >> np.uint64(11)).astype(np.float64) * 2.0**-53).reshape(tuple(shape))


@twin("sunset.tape.codes_numba")
def encode_rows(codes, frame: Frame, seed: int, r0: int, sun: Sun, cmap: CodeMap):
    """Code the rows ``r0 …`` of a frame (``frame`` and ``codes`` hold just those rows), in place.

    The dither u and v are the rows' numbers of :func:`dither`. Returns u
    where the caller has more to code (posts, clouds); the compiled twin
    computes u and v inside its loop and returns None when the rows have
    neither.
    """
    shape = codes.shape
    u = dither(seed, r0 * shape[1], shape, 0)
    v = dither(seed, r0 * shape[1], shape, 1)
    encode_pixels(codes, frame, u, v, sun, cmap)
    return u


def encode_pixels(codes, frame: Frame, u, v, sun: Sun, cmap: CodeMap) -> None:
    """The coding rules, every pixel at once: fills ``codes`` (H, W) uint8 in place.

    ``u`` and ``v`` are :func:`encode`'s dither arrays (H, W) in [0, 1).
    Raises :class:`SunsetError` for an island pixel whose part is unknown.
    """
    surf = np.asarray(frame.final_surface)
    part = np.asarray(frame.final_part)

    # islands: the sun-plane angle of the final normal
    island = surf >= 1
    if np.any(island):
        normals = _rows(frame.final_normal, island)
        rh = rho_hat(normals, sun)
        parts = part[island]
        ui = u[island]
        out = np.empty(rh.shape, np.int64)
        known = np.zeros(rh.shape, bool)
        for p in (PART_HILL, PART_CLIFF, PART_BEACH):
            r = cmap.for_part(p)
            sel = parts == p
            out[sel] = r.start + island_offsets(rh[sel], r.size, ui[sel])
            known |= sel
        if not np.all(known):
            bad = int(parts[~known][0])
            raise SunsetError(f"frame.final_part must be 1 (beach), 2 (cliff) or 3 (hill) on islands, got {bad}")
        codes[island] = out

    # the sky: direct rays by z; reflected rays by the track test first
    sky = surf == SKY
    if np.any(sky):
        ray = _rows(frame.ray, sky)
        z = ray[:, 2]
        us = u[sky]
        idx = cmap.sky.start + sky_index(z, cmap.sky.size, us)
        reflected = np.asarray(frame.bounces)[sky] > 0
        wr = np.abs(ray @ sun.W) + (v[sky] - 0.5) * (TRACK_DITHER * math.sin(sun.delta))
        e_max = track_elevation_max(sun)
        on_track = reflected & (wr < math.sin(sun.delta))
        beside = reflected & ~on_track & (wr < math.sin(HALO_FACTOR * sun.delta))
        # the elevation codes only where they are used (the glitter is a small subset)
        for sel, rng_ in ((np.flatnonzero(on_track), cmap.track), (np.flatnonzero(beside), cmap.halo)):
            idx[sel] = rng_.start + elevation_index(z[sel], rng_.size, e_max, us[sel])
        codes[sky] = idx


@twin("sunset.tape.codes_numba")
def encode_sea_rows(codes, frame: Frame, still, seed: int, r0: int, sun: Sun, cmap: CodeMap) -> None:
    """Code the rows ``r0 …`` of a cycle's frame (``frame``, ``still`` and ``codes`` hold those rows).

    Off the sea (``frame.surface``), the still codes (the islands' and the
    sky's, the same in every frame: :class:`sunset.pipeline.cycle.CyclePass`);
    on it, :func:`encode_pixels` of the final fields with the rows' dither
    numbers of ``seed`` (:func:`dither`).
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
