"""From radiance to the display: the film's exposure and the eye's response, in colour.

The RGB back end produces CIE XYZ radiance per pixel (in units of the
top-of-atmosphere solar spectrum, as the sky model's radiance). It is turned
into display values by the package's eye (:mod:`sunset.model.eye`), exactly
as the colour tables turn their spectra into table entries: XYZ relative to a
white card in full sun and to the hour's exposure key, the Naka–Rushton
response applied to the luminance Y with each colour's chromaticity kept,
bleaching towards white only what would pass full scale, then linear sRGB
(adapted, CAT02, from the film's white to D65). Only the input differs: XYZ
per pixel instead of a spectrum per code, and the XYZ → sRGB transform is
applied as its 3 × 3 matrix.
"""

from __future__ import annotations

import functools

import numpy as np

from ..constants import EYE_RESPONSE_EXPONENT, EYE_SEMI_SATURATION
from ..model.eye import exposure_key, film_white, reference_white, srgb_decode, srgb_encode

__all__ = ["xyz_to_rgb_matrix", "exposure", "scene_linear", "display_linear", "encode_srgb", "decode_srgb"]

#: sRGB transfer curve both ways (IEC 61966-2-1), as the film recorder uses them.
encode_srgb = srgb_encode
decode_srgb = srgb_decode


def xyz_to_rgb_matrix() -> np.ndarray:
    """M (3, 3) with linear sRGB = XYZ @ M: colour-science's XYZ → sRGB, CAT02 from the film's white to D65.

    The transform is linear, so its matrix is its image of the unit vectors.
    """
    return _xyz_to_rgb_matrix(film_white())


@functools.lru_cache(maxsize=8)
def _xyz_to_rgb_matrix(white: tuple[float, float]) -> np.ndarray:
    import colour

    m = colour.XYZ_to_sRGB(np.eye(3), illuminant=white, chromatic_adaptation_transform="CAT02",
                           apply_cctf_encoding=False)
    m = np.array(m, dtype=float)
    m.setflags(write=False)
    return m


def exposure(sun_dir) -> float:
    """The divisor of XYZ for the hour: the white card's Y times the exposure key (:func:`sunset.model.eye.exposure_key`)."""
    return float(reference_white()[1]) * exposure_key(sun_dir)


def scene_linear(xyz, scale: float) -> np.ndarray:
    """Exposed scene-referred linear sRGB (no response curve, unclipped): for grading, float output."""
    return (np.asarray(xyz, dtype=float) / scale) @ xyz_to_rgb_matrix()


def display_linear(xyz, scale: float) -> np.ndarray:
    """XYZ radiance (..., 3) → linear display RGB in [0, 1] (..., 3): the film's response, per pixel.

    :func:`sunset.model.eye.xyz_response` with the XYZ → sRGB matrix, as the
    kernel :func:`sunset.light.kernel.display_pixels` (the tests compare the two).

    Parameters
    ----------
    xyz : array_like (..., 3)
        Radiance in the sky model's units.
    scale : float
        :func:`exposure` of the hour.
    """
    from .kernel import display_pixels

    xyz = np.asarray(xyz)
    flat = display_pixels(xyz.reshape(-1, 3), float(scale), xyz_to_rgb_matrix(), EYE_RESPONSE_EXPONENT,
                          EYE_SEMI_SATURATION)
    return flat.reshape(xyz.shape)


def display_filtered(xyz, scale: float, k: int = 1) -> np.ndarray:
    """XYZ radiance (kH, kW, 3) → linear display RGB (H, W, 3) in [0, 1]: the film's response, then a k × k box.

    :func:`display_linear` followed by the mean of each k × k block (the
    anti-aliasing filter of :mod:`sunset.light.render`), computed strip by
    strip of rows on the threads (:func:`sunset.kernels.run_strips`) by the
    kernel :func:`sunset.light.kernel.display_box`, so that the full-resolution
    response is never held; the same bytes for any number of threads.
    """
    from ..kernels import row_strips, run_strips
    from .kernel import display_box

    xyz = np.asarray(xyz)
    k = int(k)
    h, w = xyz.shape[0] // k, xyz.shape[1] // k
    out = np.empty((h, w, 3))
    m = xyz_to_rgb_matrix()

    def rows(r0: int, r1: int) -> None:
        out[r0:r1] = display_box(xyz[r0 * k:r1 * k, :w * k], float(scale), m, EYE_RESPONSE_EXPONENT,
                                 EYE_SEMI_SATURATION, k)

    run_strips(rows, row_strips(h, w * k * k))
    return out
