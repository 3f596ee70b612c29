"""Exposure and the eye: spectral radiance → the display's linear value and sRGB bytes.

Shared by both back ends of the :class:`~sunset.vector.frame.Frame`, the 1981
colour tables (:mod:`sunset.recorder.colour_tables`) and the RGB light of the
future work: CIE 1931 XYZ relative to a white horizontal card in full sun at
30° (:func:`reference_white`, and to an exposure key that follows the light as
it fades, :func:`exposure_key`), a compressive response of the eye to
luminance (Naka–Rushton, :func:`eye_response`) that keeps each colour's
chromaticity, bleaching towards white only what would pass full scale
(:func:`film_response`), then linear sRGB and its encoding.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .. import kernels
from ..constants import (EXPOSURE_FOLLOW, EXPOSURE_SUN_ELEVATION, EYE_RESPONSE_EXPONENT, EYE_SEMI_SATURATION,
                         SUN_TRUE_RADIUS)
from .sky import island_lighting, sky_radiance, spectral_data

__all__ = [
    "spectrum_to_xyz", "xyz_to_linear_srgb", "srgb_encode", "srgb_decode", "to_uint8", "DECODE_LUT",
    "reference_white", "film_white", "exposure_key", "eye_response", "film_response", "xyz_response",
]


def xyz_to_linear_srgb(xyz: np.ndarray) -> np.ndarray:
    """CIE XYZ → linear sRGB, adapted (CAT02) from the film's white (:func:`film_white`) to D65.

    colour-science's ``XYZ_to_sRGB`` with that white.
    """
    import colour

    return colour.XYZ_to_sRGB(xyz, illuminant=film_white(), chromatic_adaptation_transform="CAT02",
                              apply_cctf_encoding=False)


def spectrum_to_xyz(spec: np.ndarray) -> np.ndarray:
    """Integrate spectra (..., n) against the CMFs: XYZ (..., 3), 10 nm steps."""
    return spec @ spectral_data().cmfs * 10.0


def srgb_encode(lin: np.ndarray) -> np.ndarray:
    """Linear [0, 1] → sRGB-encoded [0, 1] (IEC 61966-2-1)."""
    lin = np.clip(lin, 0.0, 1.0)
    return np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * np.power(lin, 1 / 2.4) - 0.055)


def srgb_decode(enc: np.ndarray) -> np.ndarray:
    """sRGB-encoded [0, 1] → linear [0, 1]."""
    enc = np.clip(enc, 0.0, 1.0)
    return np.where(enc <= 0.04045, enc / 12.92, np.power((enc + 0.055) / 1.055, 2.4))


def to_uint8(enc: np.ndarray) -> np.ndarray:
    return np.clip(np.rint(enc * 255.0), 0, 255).astype(np.uint8)


#: sRGB byte → linear value, for mixing in linear light.
DECODE_LUT = srgb_decode(np.arange(256) / 255.0)


def reference_white() -> np.ndarray:
    """XYZ of a white horizontal card in full sun at the reference elevation (sun + sky).

    Kept once per process and path of :mod:`sunset.kernels` (the two paths' skies agree within a
    tolerance, not to the bit, and a run's colours come from one of them).
    """
    return _reference_white(kernels.enabled())


@functools.lru_cache(maxsize=None)
def _reference_white(compiled: bool) -> np.ndarray:
    e = math.radians(EXPOSURE_SUN_ELEVATION)
    p = np.array([0.0, math.cos(e), math.sin(e)])
    direct, diffuse = island_lighting(p, SUN_TRUE_RADIUS)
    out = spectrum_to_xyz((direct * math.sin(e) + diffuse) / math.pi)
    out.setflags(write=False)
    return out


def film_white() -> tuple[float, float]:
    """CIE xy chromaticity the film is balanced for: daylight on a white card (sun at 30° plus sky)."""
    xyz = reference_white()
    return (float(xyz[0] / xyz.sum()), float(xyz[1] / xyz.sum()))


def exposure_key(sun_dir) -> float:
    """The luminance the film is exposed for, relative to the white card.

    (L_key)^k with L_key the sky's luminance 5° above the horizon along the
    camera's axis, relative to the reference white card, and
    k = :data:`~sunset.constants.EXPOSURE_FOLLOW`: the camera opens up as the
    light fades, but not all the way, so the sunset still darkens.
    """
    e = math.radians(5.0)
    key = float(spectrum_to_xyz(sky_radiance(np.array([[0.0, math.cos(e), math.sin(e)]]), sun_dir))[0, 1])
    key = max(key / float(reference_white()[1]), 1e-6)
    return key ** EXPOSURE_FOLLOW


def eye_response(x) -> np.ndarray:
    """The display's response to relative luminance x >= 0: a Naka–Rushton curve.

    Values lie in [0, 1).

    y = xⁿ / (xⁿ + σⁿ) with n = :data:`~sunset.constants.EYE_RESPONSE_EXPONENT`
    and σ = :data:`~sunset.constants.EYE_SEMI_SATURATION` (Naka & Rushton 1966):
    the photoreceptors' compressive response, which is why the eye, adapted to a
    sunset sky, still sees the islands in their shadow that a photograph
    exposed for the same sky shows black. Below σ it is nearly the power law
    (x/σ)ⁿ, so a ratio of 300 in luminance becomes a ratio of at most
    300ⁿ ≈ 31.
    """
    x = np.clip(np.asarray(x, dtype=float), 0.0, None)
    a = np.power(x, EYE_RESPONSE_EXPONENT)
    return a / (a + EYE_SEMI_SATURATION ** EYE_RESPONSE_EXPONENT)


def film_response(radiance: np.ndarray, key: float) -> np.ndarray:
    """Spectral radiance (..., n_λ) → the linear display value in each pass (..., 3).

    XYZ relative to the white card and the exposure key, then
    :func:`xyz_response`.
    """
    return xyz_response(spectrum_to_xyz(radiance) / (float(reference_white()[1]) * key))


def xyz_response(xyz: np.ndarray, to_linear_srgb=xyz_to_linear_srgb) -> np.ndarray:
    """Exposed XYZ (..., 3), relative to the white card, → the linear display value (..., 3) in [0, 1].

    The eye's response (:func:`eye_response`) applied to the luminance Y, and
    linear sRGB scaled by y/Y, so the compression keeps each colour's
    chromaticity. A colour that would pass 1 in some pass is mixed towards the
    grey of the same luminance until it fits: very bright light (the sun, its
    glitter) bleaches towards white, as it does on film and in the eye. The
    RGB back end (:mod:`sunset.light`) calls it per pixel with a matrix for
    ``to_linear_srgb``.
    """
    xyz = np.asarray(xyz, dtype=float)
    lin = np.clip(to_linear_srgb(xyz), 0.0, None)
    y = np.clip(xyz[..., 1], 0.0, None)
    resp = eye_response(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(y > 1e-12, resp / np.where(y > 1e-12, y, 1.0), 0.0)
    rgb = lin * scale[..., None]
    top = rgb.max(axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(top > 1.0, (top - 1.0) / np.where(top > 1.0, top - resp, 1.0), 0.0)
    rgb = (1.0 - t[..., None]) * rgb + t[..., None] * resp[..., None]
    return np.clip(rgb, 0.0, 1.0)
