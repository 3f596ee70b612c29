"""Numba twin of :mod:`sunset.vector.windsea_crests`: a wind sea's second reflections, one ray at a time.

:func:`wind_march` takes the reference's steps for each ray in turn (the
safe step max(−F/ρ, δ), the same bracket, the same halvings), with the
trains' compiled bilinear interpolation
(:func:`sunset.vector.windsea_scan_numba._bilinear`); the reflection off
the sea's normal at the hit is the reference's (:func:`~sunset.vector.windsea_crests.bounce_off`).

:func:`wind_sea_rays`, the strip kernel: with one reflection (or none) nothing
of the sea is read but the frame's normals, and the strip goes through the
compiled pass that reflects, pierces the islands and writes the final fields
(:func:`sunset.vector.reflect_numba.strip_pass`, with no crest); with two,
:func:`sunset.vector.reflect.sea_rays` with the compiled march. Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import numpy as np

from ..kernels import jit as _jit
from . import windsea_crests as _reference
from .frame import Frame
from .reflect import sea_rays
from .reflect_numba import strip_pass
from .windsea_crests import MARCH_BISECTIONS, check_second_reflections, march_constants
from .windsea_scan_numba import _bilinear


@_jit
def _gap(z, spacing, h, qx, qy, qz, rx, ry, rz, s):
    return (_bilinear(z, spacing, qx + s * rx, qy + s * ry) - h) - (qz + s * rz)


@_jit
def _march_all(z, spacing, h, q, r, top, sx, sy, delta, longest, bisections, out):
    for j in range(q.shape[0]):
        out[j] = np.inf
        qx, qy, qz = q[j, 0], q[j, 1], q[j, 2]
        rx, ry, rz = r[j, 0], r[j, 1], r[j, 2]
        rate = sx * abs(rx) + sy * abs(ry) - rz
        end = (top - qz) / rz if rz > 0.0 else np.inf
        end = min(end, longest)
        if not (rate > 0.0 and end > delta):
            continue
        s = delta
        f = _gap(z, spacing, h, qx, qy, qz, rx, ry, rz, s)
        if not f < 0.0:
            continue
        while True:
            nxt = min(s + max(-f / rate, delta), end)
            fn = _gap(z, spacing, h, qx, qy, qz, rx, ry, rz, nxt)
            if fn >= 0.0:
                lo, hi = s, nxt
                for _ in range(bisections):
                    mid = 0.5 * (lo + hi)
                    if _gap(z, spacing, h, qx, qy, qz, rx, ry, rz, mid) >= 0.0:
                        hi = mid
                    else:
                        lo = mid
                out[j] = hi
                break
            if not nxt < end:
                break
            s, f = nxt, fn


def wind_march(tile, t: float, h: float, q, r) -> np.ndarray:
    """:func:`sunset.vector.windsea_crests.wind_march` compiled."""
    q = np.ascontiguousarray(q, dtype=np.float64)
    r = np.ascontiguousarray(r, dtype=np.float64)
    top, sx, sy, delta, longest = march_constants(tile, t, h)
    out = np.empty(len(q))
    _march_all(tile.fields(t)["z"], tile.spacing, float(h), q, r, top, sx, sy, delta, longest, MARCH_BISECTIONS,
               out)
    return out


def wind_secondary_reflections(sea, t: float, q, r, h: float):
    """:func:`sunset.vector.windsea_crests.wind_secondary_reflections` with the compiled march."""
    return _reference.bounce_off(sea, t, q, r, h, wind_march)


def wind_sea_rays(scene, frame: Frame, reflections: int) -> Frame:
    """:func:`sunset.vector.windsea_crests.wind_sea_rays` compiled: the compiled strip pass, or the compiled march."""
    check_second_reflections(scene.sea, reflections)
    if reflections < 2:
        return strip_pass(scene, frame, reflections)
    h = scene.camera.eye_height
    return sea_rays(scene, frame, reflections, lambda q, r: wind_secondary_reflections(scene.sea, frame.t, q, r, h))
