"""The film recorder stage: three colour passes through the tables, and the sun's disk.

The Dicomed D-48 saw the tape three times, once through each of its red,
green and blue filters, each time through a 256-entry translation table
(:mod:`sunset.recorder.colour_tables`). It knew nothing of the scene: only the
code of each pixel, its raster position and, through the tables, the sun's
position P(θ) = U cos θ + V sin θ with θ = 15° per hour before sunset. This
module is that machine. It reads codes (:mod:`sunset.tape.codemap`), the
scene's camera (raster position → direction) and its sun, and never a
:class:`~sunset.vector.frame.Frame`. Its strip kernel is :func:`lookup` (a
strip of rows of codes through the table); the pipeline exposes a frame
(:func:`sunset.pipeline.frame.expose`: :func:`exposure_table`, :func:`lookup`
over the strips, :func:`add_sun`).

The sun-disk rule
-----------------
A pixel above the horizon, wholly inside the sun's disk, whose code is a sky
code, is exposed in the sun's colour (the paper, *Color Specification for the
Sky*, paraphrased); near the rim, a mix weighted by the fraction of the pixel
(above the horizon) covered by the disk, found by sub-sampling the pixel's
footprint.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import SUN_SUPERSAMPLE
from ..errors import SunsetError, real_number, shown
from ..kernels import twin
from ..model.eye import DECODE_LUT, srgb_encode, to_uint8
from ..model.sun import Sun
from ..tape.codemap import code_map
from .colour_tables import sun_colour, tables

__all__ = ["PASSES", "sun_coverage", "lookup", "check_codes", "exposure_table", "add_sun", "expose_frame"]

#: The three passes of the film recorder, in order.
PASSES = ("red", "green", "blue")


# --------------------------------------------------------------------------- spectral data


# --------------------------------------------------------------------------- air mass and columns


# --------------------------------------------------------------------------- the tables


# --------------------------------------------------------------------------- the sun disk
def _dirs(s, z) -> np.ndarray:
    d = np.stack(np.broadcast_arrays(s, np.ones_like(s * z), z), axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def sun_coverage(camera, sun: Sun, hours: float,
                 supersample: int = SUN_SUPERSAMPLE):
    """Fraction of each pixel covered by the sun's disk above the horizon.

    Only pixels near the sun are examined. A pixel whose four corners lie
    inside the disk (a convex spherical cap, so the whole pixel does) and
    whose lower edge is above the horizon ζ = 0 is covered fully; a pixel
    whose centre is farther than δ plus its half-diagonal from the sun's
    centre, or that lies below the horizon, not at all; the rest are
    sub-sampled on a ``supersample`` × ``supersample`` grid.

    Returns
    -------
    (slice, slice, ndarray)
        The rows and columns of the examined box and the coverage in [0, 1]
        of each pixel in it (an empty box when the sun is out of view).
    """
    empty = (slice(0, 0), slice(0, 0), np.zeros((0, 0)))
    p = sun.position(hours)
    delta = sun.delta
    if p[1] <= math.sin(delta):
        return empty
    s_c, z_c = p[0] / p[1], p[2] / p[1]
    ds, dz = camera.pixel_pitch
    reach = 1.1 * math.tan(delta) * (1.0 + s_c * s_c + z_c * z_c) + ds + dz
    c0 = max(0, int(math.floor((s_c - reach - camera.s_min) / ds)))
    c1 = min(camera.width, int(math.ceil((s_c + reach - camera.s_min) / ds)) + 1)
    r0 = max(0, int(math.floor((camera.zy_max - (z_c + reach)) / dz)))
    r1 = int(math.ceil((camera.zy_max - (z_c - reach)) / dz)) + 1
    r1 = min(camera.height, r1)
    if c0 >= c1 or r0 >= r1 or z_c + reach <= 0.0:
        return empty
    s = camera.s_centres()[c0:c1][None, :]
    z = camera.zy_centres()[r0:r1][:, None]
    cos_d = math.cos(delta)
    centre = _dirs(s, z)
    ang = np.arccos(np.clip(centre @ p, -1.0, 1.0))
    corners_in = np.ones(ang.shape, bool)
    half_diag = np.zeros(ang.shape)
    for fs in (-0.5, 0.5):
        for fz in (-0.5, 0.5):
            corner = _dirs(s + fs * ds, z + fz * dz)
            corners_in &= corner @ p > cos_d
            cos_corner = np.clip(np.sum(corner * centre, -1), -1.0, 1.0)
            corner_angle = np.arccos(cos_corner)
            half_diag = np.maximum(half_diag, corner_angle)
    above = (z - 0.5 * dz) >= 0.0
    below = (z + 0.5 * dz) <= 0.0
    cov = np.where(corners_in & above, 1.0, 0.0)
    rim = ~(corners_in & above) & ~below & (ang - half_diag < delta)
    if np.any(rim):
        rows, cols = np.nonzero(rim)
        n = supersample
        f = (np.arange(n) + 0.5) / n - 0.5
        ss = (s[0, cols][:, None, None] + f[None, None, :] * ds)
        zz = (z[rows, 0][:, None, None] + f[None, :, None] * dz)
        sub = _dirs(ss, zz)
        inside = (sub @ p > cos_d) & (zz > 0.0)
        cov[rows, cols] = inside.reshape(len(rows), -1).mean(axis=1)
    return slice(r0, r1), slice(c0, c1), cov


# --------------------------------------------------------------------------- exposing
@twin("sunset.recorder.dicomed_numba")
def lookup(lut, codes, out) -> None:
    """The three passes at once: ``out[..., :] = lut[codes]``, each code's (red, green, blue), in place.

    ``lut`` (256, 3) uint8, ``codes`` (h, W) uint8, ``out`` (h, W, 3) uint8.
    """
    np.take(lut, codes, axis=0, out=out)


def check_codes(scene, codes) -> None:
    """Raise :class:`SunsetError` unless ``codes`` is a uint8 array of the camera's (H, W)."""
    if not isinstance(codes, np.ndarray):
        raise SunsetError(f"codes must be a uint8 array, got {shown(codes)}")
    cam = scene.camera
    if codes.dtype != np.uint8:
        raise SunsetError(f"codes must be uint8, got {codes.dtype}")
    shape = (cam.height, cam.width)
    if codes.shape != shape:
        raise SunsetError(f"codes must have the camera's shape {shape}, "
                          f"got {codes.shape}")


def exposure_table(scene, hours: float) -> np.ndarray:
    """The three passes' tables as one (256, 3) uint8 table: each code's (red, green, blue) at ``hours``."""
    real_number("hours", hours)
    return np.ascontiguousarray(tables(scene.sun, hours, scene.clouds).T)


def add_sun(scene, codes, hours: float, rgb) -> None:
    """The sun's disk on the exposed frame ``rgb`` (H, W, 3) uint8, in place: the sun-disk rule.

    Sky codes wholly inside the disk take the sun's colour; near its rim a
    mix, in linear light, weighted by the fraction of the pixel the disk
    covers (:func:`sun_coverage`). Only the few pixels the disk touches are read.
    """
    cam = scene.camera
    clouds = scene.clouds
    rows, cols, cov = sun_coverage(cam, scene.sun, hours)
    if cov.size:
        to_sky = code_map(scene).reaches_sky(codes[rows, cols])
        weight = np.where(to_sky, cov, 0.0)[..., None]
        if np.any(weight > 0):
            sun_lin = sun_colour(scene.sun, hours, clouds)
            box = DECODE_LUT[rgb[rows, cols]]
            mixed = (1.0 - weight) * box + weight * sun_lin
            rgb[rows, cols] = np.where(weight > 0, to_uint8(srgb_encode(mixed)),
                                       rgb[rows, cols])


def expose_frame(scene, codes, hours: float):
    """One frame of codes exposed in one piece (no threads: :func:`sunset.pipeline.frame.expose` cuts a frame
    into strips on its threads; a film exposes whole frames side by side): the table, :func:`lookup`, the sun."""
    check_codes(scene, codes)
    rgb = np.empty(codes.shape + (3,), np.uint8)
    lookup(exposure_table(scene, hours), codes, rgb)
    add_sun(scene, codes, hours, rgb)
    return rgb
