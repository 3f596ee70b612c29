"""Numba twin of :func:`sunset.tape.codes.encode_pixels`: the codes in one pass over the pixels.

The same rules and the same arithmetic as the NumPy reference, pixel by
pixel; the tests check that both give the same bytes. Chosen by
:mod:`sunset.kernels`.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import HALO_FACTOR, PART_BEACH, PART_CLIFF, PART_HILL, TRACK_DITHER
from ..errors import SunsetError
from ..kernels import jit as _jit
from .codes import track_elevation_max


@_jit
def _encode_pixels(codes, surf, part, normal, ray, bounces, u, v, U, V, W, part_codes, island_start, island_size,
                   sky_start, sky_size, track_start, track_size, halo_start, halo_size, dither, sin_d, sin_halo,
                   e_max):
    H, Wd = surf.shape
    for y in range(H):
        for x in range(Wd):
            s = surf[y, x]
            uu = u[y, x]
            if s >= 1:
                # ρ̂(N) (sunset.tape.codes.rho_hat) and the island offset (sunset.tape.codes.island_offsets)
                n0 = np.float64(normal[y, x, 0])
                n1 = np.float64(normal[y, x, 1])
                n2 = np.float64(normal[y, x, 2])
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
                p = part[y, x]
                j = -1
                for i in range(part_codes.shape[0]):
                    if part_codes[i] == p:
                        j = i
                if j < 0:
                    return p
                size = island_size[j]
                off = np.int64(np.floor((rh + 1.0) * (size / 4.0) + uu)) % size
                codes[y, x] = island_start[j] + off
            elif s == -1:
                z = np.float64(ray[y, x, 2])
                zc = min(max(z, 0.0), 1.0)
                k = np.int64(np.floor(math.sqrt(zc) * sky_size + uu))
                code = sky_start + min(max(k, 0), sky_size - 1)
                if bounces[y, x] > 0:
                    dot = np.float64(ray[y, x, 0]) * W[0] + np.float64(ray[y, x, 1]) * W[1] + z * W[2]
                    wr = abs(dot) + (v[y, x] - 0.5) * dither
                    if wr < sin_d:
                        k = np.int64(np.floor(math.asin(zc) * (track_size / e_max) + uu))
                        code = track_start + min(max(k, 0), track_size - 1)
                    elif wr < sin_halo:
                        k = np.int64(np.floor(math.asin(zc) * (halo_size / e_max) + uu))
                        code = halo_start + min(max(k, 0), halo_size - 1)
                codes[y, x] = code
    return -1


def _encode(codes, frame, u, v, sun, cmap, part_ids, dither: float, sin_d: float, sin_halo: float,
                  e_max: float):
    """The codes of :func:`sunset.tape.codes.encode` in one pass over the pixels, into ``codes`` (uint8, in place).

    ``u`` and ``v`` are encode's dither arrays; ``part_ids`` the island parts
    in the order of their code ranges. Returns -1, or the first unknown island
    part met (the caller raises).
    """
    ranges = [cmap.for_part(p) for p in part_ids]
    return int(_encode_pixels(
        codes, np.ascontiguousarray(frame.final_surface), np.ascontiguousarray(frame.final_part),
        np.ascontiguousarray(frame.final_normal), np.ascontiguousarray(frame.ray),
        np.ascontiguousarray(frame.bounces), u, v, np.asarray(sun.U, float), np.asarray(sun.V, float),
        np.asarray(sun.W, float), np.asarray(part_ids, np.int64), np.array([r.start for r in ranges], np.int64),
        np.array([r.size for r in ranges], np.int64), cmap.sky.start, cmap.sky.size, cmap.track.start,
        cmap.track.size, cmap.halo.start, cmap.halo.size, float(dither), float(sin_d), float(sin_halo),
        float(e_max)))


def encode_pixels(codes, frame, u, v, sun, cmap) -> None:
    """:func:`sunset.tape.codes.encode_pixels` in one compiled pass over the pixels."""
    bad = _encode(codes, frame, u, v, sun, cmap, (PART_HILL, PART_CLIFF, PART_BEACH),
                  TRACK_DITHER * math.sin(sun.delta), math.sin(sun.delta), math.sin(HALO_FACTOR * sun.delta),
                  track_elevation_max(sun))
    if bad >= 0:
        raise SunsetError(f"frame.final_part must be 1 (beach), 2 (cliff) or 3 (hill) on islands, got {bad}")
