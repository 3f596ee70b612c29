"""Numba twins of :func:`sunset.tape.codes.encode_rows` and :func:`sunset.tape.codes.encode_sea_rows`: the codes in
one pass over the pixels.

The rules of :func:`sunset.tape.codes.encode_pixels`, pixel by pixel, with
the dither's numbers computed in the loop (:func:`_dither_at`, the integer
arithmetic of :func:`sunset.tape.codes.dither`, so the same numbers). The
codes agree with the NumPy reference's wherever the two paths' frames agree
and no value lies within a rounding of a code boundary (tests, and the
table of chapter 10). Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..constants import HALO_FACTOR, PART_BEACH, PART_CLIFF, PART_HILL, SEA, TRACK_DITHER
from ..errors import SunsetError
from ..kernels import jit as _jit
from .codes import SPLITMIX_GAMMA, SPLITMIX_M1, SPLITMIX_M2, dither as _dither, track_elevation_max

_U64 = np.uint64
_GAMMA, _M1, _M2 = _U64(SPLITMIX_GAMMA), _U64(SPLITMIX_M1), _U64(SPLITMIX_M2)


@_jit
def _dither_at(seed, n, which):
    """Pixel n's dither number (which = 0: u, 1: v), :func:`sunset.tape.codes.dither`'s SplitMix64 output 2n + which."""
    z = _U64(seed) + (_U64(2) * _U64(n) + _U64(1 + which)) * _GAMMA
    z = (z ^ (z >> _U64(30))) * _M1
    z = (z ^ (z >> _U64(27))) * _M2
    z = z ^ (z >> _U64(31))
    return np.float64(z >> _U64(11)) * (1.0 / 9007199254740992.0)


@_jit
def _dither_fill(seed, start, which, out):
    """out[i] = pixel (start + i)'s dither number, for the tests."""
    for i in range(out.shape[0]):
        out[i] = _dither_at(seed, start + i, which)


@_jit
def island_code(n0, n1, n2, p, uu, U, V, part_codes, island_start, island_size):
    """An island pixel's code from its (float64) normal, its part ``p`` and its dither ``uu``; −1 for an unknown part.

    ρ̂(N) (:func:`sunset.tape.codemap.rho_hat`) and the island offset (:func:`sunset.tape.codemap.island_offsets`).
    """
    a = n0 * U[0] + n1 * U[1] + n2 * U[2]
    b = n0 * V[0] + n1 * V[1] + n2 * V[2]
    r = math.hypot(a, b)
    rho = -a / r if r > 1e-12 else 1.0
    if rho < -1.0:
        rho = -1.0
    elif rho > 1.0:
        rho = 1.0
    rh = rho if b > 0 else 2.0 - rho
    if rh >= 3.0:
        rh = rh - 4.0
    j = -1
    for i in range(len(part_codes)):
        if part_codes[i] == p:
            j = i
    if j < 0:
        return np.int64(-1)
    size = island_size[j]
    off = np.int64(np.floor((rh + 1.0) * (size / 4.0) + uu)) % size
    return island_start[j] + off


@_jit
def sky_code(x, y, z, bounced, seed, n, uu, w0, w1, w2, sky_start, sky_size, track_start, track_size, halo_start,
             halo_size, dither, sin_d, sin_halo, e_max):
    """The code of pixel ``n`` whose (float64) final ray (x, y, z) reaches the sky: by its z, and, for a reflected
    ray (``bounced``), the sun's track or its halo when |W·R| is small (the rules of
    :func:`sunset.tape.codes.encode_pixels`)."""
    zc = min(max(z, 0.0), 1.0)
    k = np.int64(np.floor(math.sqrt(zc) * sky_size + uu))
    code = sky_start + min(max(k, 0), sky_size - 1)
    if bounced:
        vv = _dither_at(seed, n, 1)
        dot = x * w0 + y * w1 + z * w2
        wr = abs(dot) + (vv - 0.5) * dither
        if wr < sin_d:
            k = np.int64(np.floor(math.asin(zc) * (track_size / e_max) + uu))
            code = track_start + min(max(k, 0), track_size - 1)
        elif wr < sin_halo:
            k = np.int64(np.floor(math.asin(zc) * (halo_size / e_max) + uu))
            code = halo_start + min(max(k, 0), halo_size - 1)
    return code


@_jit
def _encode_pixels(codes, surf, part, normal, ray, bounces, seed, first, cycle, still, surface, U, V, W,
                   part_codes, island_start, island_size, sky_start, sky_size, track_start, track_size, halo_start,
                   halo_size, dither, sin_d, sin_halo, e_max):
    """The codes of :func:`sunset.tape.codes.encode_pixels`, pixel by pixel; (whether an island part was unknown, the
    first such part, the pixels left to the caller: posts and clouds).

    The dither of pixel (y, x) is that of the frame's pixel ``first`` + y·W + x
    (:func:`_dither_at` of ``seed``). With ``cycle``: a cycle's frame
    (:func:`sunset.tape.codes.encode_sea_rows`), whose pixels off the sea
    (``surface``) take the ``still`` codes and whose final fields are read on
    the sea alone. Each pixel by :func:`island_code` or :func:`sky_code`.
    """
    H, Wd = surf.shape
    others = 0
    for y in range(H):
        for x in range(Wd):
            if cycle and surface[y, x] != SEA:
                codes[y, x] = still[y, x]
                continue
            n = first + y * Wd + x
            uu = _dither_at(seed, n, 0)
            s = surf[y, x]
            if s >= 1:
                p = part[y, x]
                code = island_code(np.float64(normal[y, x, 0]), np.float64(normal[y, x, 1]),
                                   np.float64(normal[y, x, 2]), p, uu, U, V, part_codes, island_start, island_size)
                if code < 0:
                    return True, p, others
                codes[y, x] = code
            elif s == -1:
                codes[y, x] = sky_code(np.float64(ray[y, x, 0]), np.float64(ray[y, x, 1]), np.float64(ray[y, x, 2]),
                                       bounces[y, x] > 0, seed, n, uu, W[0], W[1], W[2], sky_start, sky_size,
                                       track_start, track_size, halo_start, halo_size, dither, sin_d, sin_halo, e_max)
            else:
                others += 1
    return False, 0, others


_NO_STILL = np.zeros((1, 1), np.uint8), np.zeros((1, 1), np.int8)


def _floats(v) -> tuple:
    return tuple(float(x) for x in np.asarray(v, float))


@functools.lru_cache(maxsize=64)
def code_constants(sun, cmap) -> tuple:
    """The arguments of :func:`_encode_pixels` that come from the sun and the code map (the same every strip).

    The sun's axes and the parts' code ranges are tuples, not arrays: a compiled function takes and drops a
    reference to each array it is given, an atomic operation, on every pixel that :func:`island_code` codes.
    """
    part_ids = (PART_HILL, PART_CLIFF, PART_BEACH)
    ranges = [cmap.for_part(p) for p in part_ids]
    return (_floats(sun.U), _floats(sun.V), _floats(sun.W), tuple(int(p) for p in part_ids),
            tuple(int(r.start) for r in ranges), tuple(int(r.size) for r in ranges), cmap.sky.start, cmap.sky.size, cmap.track.start,
            cmap.track.size, cmap.halo.start, cmap.halo.size, float(TRACK_DITHER * math.sin(sun.delta)),
            float(math.sin(sun.delta)), float(math.sin(HALO_FACTOR * sun.delta)), float(track_elevation_max(sun)))


def _encode(codes, frame, seed: int, r0: int, sun, cmap, still=None):
    """Run :func:`_encode_pixels` on a frame's rows from ``r0`` (the dither of ``seed`` at those rows);
    ``still``: (the still codes, the frame's direct surface) of a cycle's frame.

    Raises for an unknown island part; returns the pixels left to the caller (posts, clouds).
    """
    failed, bad, others = _encode_pixels(
        codes, np.ascontiguousarray(frame.final_surface), np.ascontiguousarray(frame.final_part),
        np.ascontiguousarray(frame.final_normal), np.ascontiguousarray(frame.ray),
        np.ascontiguousarray(frame.bounces), int(seed), int(r0) * codes.shape[1], still is not None,
        *[np.ascontiguousarray(a) for a in (still or _NO_STILL)], *code_constants(sun, cmap))
    if failed:
        raise SunsetError(f"frame.final_part must be 1 (beach), 2 (cliff) or 3 (hill) on islands, got {bad}")
    return int(others)


def encode_rows(codes, frame, seed: int, r0: int, sun, cmap):
    """:func:`sunset.tape.codes.encode_rows` with the dither computed inside the compiled loop (no u, v arrays).

    Returns None when the rows have no posts or clouds, else their u (the caller codes those pixels).
    """
    others = _encode(codes, frame, seed, r0, sun, cmap)
    return _dither(seed, r0 * codes.shape[1], codes.shape, 0) if others else None


def encode_sea_rows(codes, frame, still, seed: int, r0: int, sun, cmap) -> None:
    """:func:`sunset.tape.codes.encode_sea_rows` in the compiled pass of :func:`encode_rows`: the still codes off the
    sea, the sea pixels' final fields coded (read on the sea pixels alone)."""
    _encode(codes, frame, seed, r0, sun, cmap, still=(still, frame.surface))
