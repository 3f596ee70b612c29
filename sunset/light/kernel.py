"""The shader's per-pixel loops, as NumPy reference kernels with Numba twins (:mod:`sunset.kernels`).

:func:`sunset.light.shade.shade` calls three kernels on the compressed pixel
lists of a :class:`~sunset.light.geometry.Geometry`, with the hour's tables
from a :class:`~sunset.light.lighting.Lighting`:

* :func:`sky_pixels`: the sky's radiance along each final ray that reaches the
  sky, read bilinearly from the hour's linear sky table at the ray's
  (precomputed) row and its column from the azimuth relative to the sun's,
  plus the sun's disk where the ray falls in it;
* :func:`island_pixels`: albedo × (max(N·P, 0) E_sun + E_sky(N)) / π, the
  skylight read bilinearly from the part's table of normals;
* :func:`combine`: the final radiances scattered into the frame, times the
  path's throughput, and the water seen at each bounce added,
  w (ω E'_sun p(ψ)/(μ' + μ_u)) + w_sky ω E'_sky.

Everything is float32. The twins in :mod:`sunset.light.kernel_numba` compute
the same formulas one pixel at a time; they agree with these references within
:data:`~sunset.light.kernel_numba.RADIANCE_RTOL` (the radiances) and
:data:`~sunset.light.kernel_numba.DISPLAY_ATOL` (the display values), measured
and tested, and each path gives the same bytes on every run.
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels import twin
from .water import PHASE_ANISOTROPY

__all__ = ["sky_pixels", "island_pixels", "combine", "display_pixels", "display_box", "PHASE_NORM"]

#: 1/(4π (1 + 0.835/3)): the normalisation of the water's phase function (:func:`sunset.light.water.phase`).
PHASE_NORM = 1.0 / (4.0 * math.pi * (1.0 + PHASE_ANISOTROPY / 3.0))

_f = np.float32


@twin("sunset.light.kernel_numba")
def sky_pixels(r0, fr, az, dirs, table, sun_azimuth, col_scale, sun_dir, cos_delta, sun_xyz) -> np.ndarray:
    """Sky (+ sun disk) radiance (S, 3) float32 of S final rays.

    Parameters
    ----------
    r0, fr : (S,) int32, float32
        Table row below each ray and the fraction towards the next.
    az : (S,) float32
        The rays' azimuths, radians.
    dirs : (S, 3) float32
        The rays (for the sun's disk).
    table : (R, C, 3) float32
        Linear sky radiance, columns by √(φ/π) (φ the azimuth from the sun's).
    sun_azimuth, col_scale, cos_delta : float
        The sun's azimuth, the columns per unit of √(φ/π), cos δ.
    sun_dir, sun_xyz : (3,)
        The unit vector to the sun and its disk's radiance.
    """
    c_max = table.shape[1] - 1
    d = az - _f(sun_azimuth)
    d = np.where(d > _f(math.pi), d - _f(2 * math.pi), d)
    d = np.where(d < _f(-math.pi), d + _f(2 * math.pi), d)
    col = np.sqrt(np.abs(d) * _f(1 / math.pi)) * _f(col_scale)
    col = np.minimum(col, _f(c_max))
    c0 = np.minimum(col.astype(np.int32), c_max - 1)
    fc = (col - c0.astype(np.float32))[:, None]
    f = fr[:, None]
    one = _f(1)
    top = table[r0, c0] * (one - fc) + table[r0, c0 + 1] * fc
    bottom = table[r0 + 1, c0] * (one - fc) + table[r0 + 1, c0 + 1] * fc
    out = top * (one - f) + bottom * f
    inside = (dirs @ np.asarray(sun_dir, np.float32) > _f(cos_delta)) & (dirs[:, 2] >= _f(0))
    out[inside] += np.asarray(sun_xyz, np.float32)
    return out


@twin("sunset.light.kernel_numba")
def island_pixels(normals, part, g0, g1, fx, fy, sun_dir, direct, table) -> np.ndarray:
    """Island radiance (I, 3) float32 of I final hits.

    Parameters
    ----------
    normals : (I, 3) float32
    part : (I,) int8
        1 beach, 2 cliff, 3 hill (the index into ``direct`` and ``table``).
    g0, g1, fx, fy : (I,) int32, int32, float32, float32
        Cell and fractions of each normal in the grid over (N_x, N_y).
    sun_dir : (3,)
    direct : (4, 3) float32
        Albedo × direct normal irradiance / π per part (row 0 unused).
    table : (4, G, G, 3) float32
        Albedo × skylight / π per part and normal.
    """
    cos = np.maximum(normals @ np.asarray(sun_dir, np.float32), _f(0))[:, None]
    p = part.astype(np.intp)
    one = _f(1)
    x = fx[:, None]
    y = fy[:, None]
    top = table[p, g0, g1] * (one - y) + table[p, g0, g1 + 1] * y
    bottom = table[p, g0 + 1, g1] * (one - y) + table[p, g0 + 1, g1 + 1] * y
    return cos * direct[p] + (top * (one - x) + bottom * x)


@twin("sunset.light.kernel_numba")
def combine(n_pixels, throughput, sky_index, sky, island_index, island,
            layer_starts, w_index, w_up, w_mu, w_weight, w_sky, beam, mu_beam,
            water_sun, water_sky) -> np.ndarray:
    """The frame's radiance (N, 3) float32.

    Final radiances × throughput, plus the water at each bounce.

    The water entries are the layers of the geometry one after the other
    (``layer_starts`` their first entries); within a layer a pixel appears
    once, and the layers are added in order.
    """
    out = np.zeros((n_pixels, 3), np.float32)
    out[sky_index] = sky
    out[island_index] = island
    out *= throughput[:, None]
    ws = np.asarray(water_sun, np.float32)
    wk = np.asarray(water_sky, np.float32)
    cos_psi = w_up @ np.asarray(beam, np.float32)
    phase = (_f(1) + _f(PHASE_ANISOTROPY) * cos_psi * cos_psi) * _f(PHASE_NORM)
    f_sun = phase / (_f(mu_beam) + w_mu) * w_weight
    add = f_sun[:, None] * ws + w_sky[:, None] * wk
    ends = list(layer_starts[1:]) + [len(w_index)]
    for start, end in zip(layer_starts, ends):
        idx = w_index[start:end]
        out[idx] += add[start:end]
    return out


@twin("sunset.light.kernel_numba")
def display_pixels(xyz, scale, m, exponent, semi_saturation) -> np.ndarray:
    """XYZ (N, 3) → linear display RGB (N, 3) float64 in [0, 1]: :func:`sunset.model.eye.xyz_response`, per pixel.

    The same response (the eye's Naka–Rushton curve on Y, chromaticity kept,
    bleaching towards white above full scale) with the XYZ → sRGB matrix ``m``
    (:func:`sunset.light.tone.xyz_to_rgb_matrix`). The twin computes it in one
    pass, yⁿ with the C library's ``pow``.
    """
    x = np.asarray(xyz, np.float64) / scale
    lin = np.maximum(x @ m, 0.0)
    y = np.maximum(x[:, 1], 0.0)
    return _respond(lin, y, np.power(y, exponent), semi_saturation ** exponent)


@twin("sunset.light.kernel_numba")
def display_box(xyz, scale, m, exponent, semi_saturation, k: int) -> np.ndarray:
    """XYZ (kH, kW, 3) → linear display RGB (H, W, 3) float64: :func:`display_pixels`, then the mean of each k × k block.

    The twin fuses the two steps pixel by pixel and never holds the
    full-resolution response.
    """
    hk, wk = xyz.shape[:2]
    rgb = display_pixels.reference(np.asarray(xyz).reshape(-1, 3), scale, m, exponent, semi_saturation)
    return rgb.reshape(hk // k, k, wk // k, k, 3).mean(axis=(1, 3))


def _respond(lin, y, a, s_n):
    resp = a / (a + s_n)
    safe = np.where(y > 1e-12, y, 1.0)
    k = np.where(y > 1e-12, resp / safe, 0.0)
    rgb = lin * k[:, None]
    top = np.maximum(np.maximum(rgb[:, 0], rgb[:, 1]), rgb[:, 2])
    big = top > 1.0
    t = np.where(big, (top - 1.0) / np.where(big, top - resp, 1.0), 0.0)[:, None]
    rgb = (1.0 - t) * rgb + t * resp[:, None]
    return np.minimum(np.maximum(rgb, 0.0), 1.0)
