"""Numba twin of :func:`sunset.tape.codes.encode_pixels`: the codes in one pass over the pixels.

The same rules and the same arithmetic as the NumPy reference, pixel by
pixel; the tests check that both give the same bytes. Chosen by
:mod:`sunset.kernels`.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from ..constants import HALO_FACTOR, PART_BEACH, PART_CLIFF, PART_HILL, SEA, TRACK_DITHER
from ..errors import SunsetError
from ..kernels import jit as _jit
from .codes import dither as _dither, track_elevation_max


# --------------------------------------------------------------------------- the dither inside the loop
#: PCG64's multiplier (O'Neill's 128-bit default, NumPy's ``PCG_DEFAULT_MULTIPLIER_128``).
_PCG_MULT = (2549297995355413924 << 64) | 4865540595714422341
_U64 = types.uint64


@intrinsic
def _pcg_step(typingctx, hi, lo, inc_hi, inc_lo):
    """PCG64's state step s·M + inc mod 2¹²⁸ on (high, low) 64-bit halves, as one 128-bit multiply-add."""
    sig = types.UniTuple(_U64, 2)(_U64, _U64, _U64, _U64)

    def codegen(context, builder, signature, args):
        i128 = ir.IntType(128)
        i64 = ir.IntType(64)
        shift = ir.Constant(i128, 64)
        h, l, ih, il = [builder.zext(a, i128) for a in args]
        state = builder.or_(builder.shl(h, shift), l)
        inc = builder.or_(builder.shl(ih, shift), il)
        state = builder.add(builder.mul(state, ir.Constant(i128, _PCG_MULT)), inc)
        out = [builder.trunc(builder.lshr(state, shift), i64), builder.trunc(state, i64)]
        return context.make_tuple(builder, signature.return_type, out)
    return sig, codegen


@_jit
def _pcg_double(hi, lo, inc_hi, inc_lo):
    """The next number of ``Generator(PCG64).random()``: step, XSL-RR output, 53 bits; (hi, lo, x)."""
    hi, lo = _pcg_step(hi, lo, inc_hi, inc_lo)
    value = hi ^ lo
    rot = hi >> np.uint64(58)
    out = (value >> rot) | (value << ((np.uint64(64) - rot) & np.uint64(63)))
    return hi, lo, np.float64(out >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@_jit
def _pcg_fill(hi, lo, inc_hi, inc_lo, out):
    """out[i] = the stream's next numbers (:func:`sunset.tape.codes.dither`), for the tests."""
    for i in range(out.shape[0]):
        hi, lo, out[i] = _pcg_double(hi, lo, inc_hi, inc_lo)


def _stream(seed: int, skip: int) -> np.ndarray:
    """PCG64(seed) advanced by ``skip`` (:func:`sunset.tape.codes.dither`) as uint64 (state hi, lo, inc hi, lo)."""
    bits = np.random.PCG64(seed)
    bits.advance(int(skip))
    st = bits.state["state"]
    m = (1 << 64) - 1
    return np.array([st["state"] >> 64, st["state"] & m, st["inc"] >> 64, st["inc"] & m], np.uint64)


@_jit
def _encode_pixels(codes, surf, part, normal, ray, bounces, u, v, su, sv, draw, cycle, still, surface, U, V, W,
                   part_codes, island_start, island_size, sky_start, sky_size, track_start, track_size, halo_start, halo_size,
                   dither, sin_d, sin_halo, e_max):
    """The codes of :func:`sunset.tape.codes.encode_pixels`, pixel by pixel; (whether an island part was unknown, the
    first such part, the pixels left to the caller: posts and clouds).

    With ``draw`` the dither u, v is drawn pixel by pixel from the PCG64 streams ``su``, ``sv`` (state high,
    low, increment high, low; :func:`_stream`) instead of read from the arrays ``u``, ``v``. With ``cycle``: a
    cycle's frame (:func:`sunset.tape.still.encode_sea_rows`), whose pixels off the sea (``surface``) take the
    ``still`` codes and whose final fields are read on the sea alone.
    """
    H, Wd = surf.shape
    uh, ul, uih, uil = su[0], su[1], su[2], su[3]
    vh, vl, vih, vil = sv[0], sv[1], sv[2], sv[3]
    others = 0
    for y in range(H):
        for x in range(Wd):
            if draw:
                uh, ul, uu = _pcg_double(uh, ul, uih, uil)
                vh, vl, vv = _pcg_double(vh, vl, vih, vil)
            if cycle and surface[y, x] != SEA:
                codes[y, x] = still[y, x]
                continue
            if not draw:
                uu = u[y, x]
                vv = v[y, x]
            s = surf[y, x]
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
                    return True, p, others
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
                    wr = abs(dot) + (vv - 0.5) * dither
                    if wr < sin_d:
                        k = np.int64(np.floor(math.asin(zc) * (track_size / e_max) + uu))
                        code = track_start + min(max(k, 0), track_size - 1)
                    elif wr < sin_halo:
                        k = np.int64(np.floor(math.asin(zc) * (halo_size / e_max) + uu))
                        code = halo_start + min(max(k, 0), halo_size - 1)
                codes[y, x] = code
            else:
                others += 1
    return False, 0, others


_NO_STREAM = np.zeros(4, np.uint64)
_NO_DITHER = np.zeros((1, 1))
_NO_STILL = np.zeros((1, 1), np.uint8), np.zeros((1, 1), np.int8)


@functools.lru_cache(maxsize=64)
def _constants(sun, cmap) -> tuple:
    """The arguments of :func:`_encode_pixels` that come from the sun and the code map (the same every strip)."""
    part_ids = (PART_HILL, PART_CLIFF, PART_BEACH)
    ranges = [cmap.for_part(p) for p in part_ids]
    return (np.asarray(sun.U, float), np.asarray(sun.V, float), np.asarray(sun.W, float),
            np.asarray(part_ids, np.int64), np.array([r.start for r in ranges], np.int64),
            np.array([r.size for r in ranges], np.int64), cmap.sky.start, cmap.sky.size, cmap.track.start,
            cmap.track.size, cmap.halo.start, cmap.halo.size, float(TRACK_DITHER * math.sin(sun.delta)),
            float(math.sin(sun.delta)), float(math.sin(HALO_FACTOR * sun.delta)), float(track_elevation_max(sun)))


def _encode(codes, frame, sun, cmap, u=None, v=None, streams=None, still=None):
    """Run :func:`_encode_pixels` on a frame's rows: with the dither arrays ``u``, ``v`` or the two ``streams``;
    ``still``: (the still codes, the frame's direct surface) of a cycle's frame.

    Raises for an unknown island part; returns the pixels left to the caller (posts, clouds).
    """
    draw = streams is not None
    su, sv = streams if draw else (_NO_STREAM, _NO_STREAM)
    failed, bad, others = _encode_pixels(
        codes, np.ascontiguousarray(frame.final_surface), np.ascontiguousarray(frame.final_part),
        np.ascontiguousarray(frame.final_normal), np.ascontiguousarray(frame.ray),
        np.ascontiguousarray(frame.bounces), _NO_DITHER if draw else u, _NO_DITHER if draw else v, su, sv, draw,
        still is not None, *[np.ascontiguousarray(a) for a in (still or _NO_STILL)], *_constants(sun, cmap))
    if failed:
        raise SunsetError(f"frame.final_part must be 1 (beach), 2 (cliff) or 3 (hill) on islands, got {bad}")
    return int(others)


def encode_pixels(codes, frame, u, v, sun, cmap) -> None:
    """:func:`sunset.tape.codes.encode_pixels` in one compiled pass over the pixels."""
    _encode(codes, frame, sun, cmap, u=np.ascontiguousarray(u, np.float64), v=np.ascontiguousarray(v, np.float64))


def encode_rows(codes, frame, seed: int, r0: int, H: int, sun, cmap):
    """:func:`sunset.tape.codes.encode_rows` with the dither drawn inside the compiled loop (no u, v arrays).

    Returns None when the rows have no posts or clouds, else their u (the caller codes those pixels).
    """
    h, Wd = codes.shape
    others = _encode(codes, frame, sun, cmap, streams=(_stream(seed, r0 * Wd), _stream(seed, (H + r0) * Wd)))
    return _dither(seed, r0 * Wd, (h, Wd)) if others else None


def encode_sea_rows(codes, frame, still, u, v, sun, cmap) -> None:
    """:func:`sunset.tape.still.encode_sea_rows` in the compiled pass of :func:`encode_pixels`: the still codes off the
    sea, the sea pixels' final fields coded with the cycle pass's dither (read on the sea pixels alone)."""
    _encode(codes, frame, sun, cmap, u=np.ascontiguousarray(u, np.float64), v=np.ascontiguousarray(v, np.float64),
            still=(still, frame.surface))
