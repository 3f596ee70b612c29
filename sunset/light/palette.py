"""The paper's claim, tested: "an 8-bit colour table is inadequate" for an RGB frame.

Two 256-colour versions of one RGB frame are compared with it:

* **the best free palette**: 256 colours chosen for this frame alone, by
  median cut (Heckbert 1982, Pillow's implementation) refined by k-means
  (Lloyd iterations, ``scipy.cluster.vq.kmeans2`` seeded with the median-cut
  palette, so deterministic) on the sRGB-encoded pixels; each pixel takes its
  nearest palette colour. No 8-bit table can do better for this frame by
  much: this is the table's best case.
* **a palette organised as the paper's code groups**: the frame's own 8-bit
  codes (:func:`sunset.encode` of the same frame: hill, cliff, beach, sky,
  track and halo groups), each code given the mean colour (in linear light)
  of the RGB pixels that carry it, which is the best table the paper's tape
  could be exposed through at this hour.

The colour error is CIEDE2000 (ΔE₀₀, colour-science's ``delta_E``, sRGB →
XYZ → CIE L*a*b* under D65, all three colour-science's, imported when the
first difference is computed): ΔE₀₀ ≈ 1 is about a just-noticeable
difference, above 2–3 a difference anyone sees side by side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


__all__ = ["median_cut_kmeans", "kmeans", "code_group_palette", "delta_e_2000", "picture_agreement", "QuantisationResult",
           "quantisation_test", "FIGURE_DIFFER_SHARE", "FIGURE_MAX_DE00"]


def median_cut_kmeans(rgb8: np.ndarray, colours: int = 256, iterations: int = 10, fit_pixels: int = 65536):
    """The frame quantised to its own best ``colours``-colour palette: (palette (c, 3) uint8, image (H, W, 3) uint8).

    Median cut (Pillow, no dithering) seeds k-means on at most ``fit_pixels``
    evenly strided pixels; every pixel then takes its nearest colour.
    """
    from PIL import Image
    from scipy.cluster.vq import vq

    img = Image.fromarray(np.ascontiguousarray(rgb8, np.uint8))
    q = img.quantize(colors=colours, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    seed = np.asarray(q.getpalette()[: 3 * colours], dtype=float).reshape(-1, 3)
    pixels = np.asarray(rgb8, dtype=float).reshape(-1, 3)
    fit = pixels[:: max(1, len(pixels) // fit_pixels)]
    centres = kmeans(fit, seed, iterations) if len(seed) == colours else seed
    centres = np.clip(np.rint(centres), 0, 255)
    # a frame repeats its colours: find each distinct colour's nearest centre once
    keys, inverse = np.unique(_pack(np.asarray(rgb8, np.uint8).reshape(-1, 3)), return_inverse=True)
    labels, _ = vq(_unpack(keys).astype(float), centres)
    palette = centres.astype(np.uint8)
    return palette, palette[labels[inverse.reshape(-1)]].reshape(np.shape(rgb8))


def kmeans(points: np.ndarray, centres: np.ndarray, iterations: int) -> np.ndarray:
    """Lloyd's k-means from ``centres`` (k, 3) over ``points`` (n, 3) of whole numbers 0–255: the centres after
    ``iterations`` steps, the bits of ``scipy.cluster.vq.kmeans2(points, centres, iter=iterations,
    minit="matrix")`` (a centre left without points stays where it was, with kmeans2's warning).

    The pixels of a frame repeat their colours (a frame's 65 536 strided pixels hold some 9 000): each
    step finds each distinct colour's nearest centre once (``scipy.cluster.vq.vq``, the function kmeans2
    calls, so the same labels), and a centre's new place is the sum of its points over their count, where
    the sums of whole numbers (below 2⁵³) are exact in any order, so the same bits as kmeans2's sums point
    by point.
    """
    import warnings

    from scipy.cluster.vq import vq

    keys, counts = np.unique(_pack(np.asarray(points, np.int64)), return_counts=True)
    rows = _unpack(keys).astype(float)
    weighted = rows * counts[:, None]                     # whole numbers: exact
    centres = np.array(centres, dtype=float)
    k = len(centres)
    for _ in range(int(iterations)):
        label = vq(rows, centres)[0]
        members = np.bincount(label, weights=counts, minlength=k)
        sums = np.stack([np.bincount(label, weights=weighted[:, j], minlength=k) for j in range(3)], axis=1)
        has = members > 0
        if not has.all():
            warnings.warn("One of the clusters is empty. Re-run kmeans with a different initialization.",
                          stacklevel=2)
        centres = np.where(has[:, None], sums / np.where(has, members, 1.0)[:, None], centres)
    return centres


def _pack(rgb8) -> np.ndarray:
    rgb8 = np.asarray(rgb8, np.int64)
    return (rgb8[..., 0] << 16) | (rgb8[..., 1] << 8) | rgb8[..., 2]


def _unpack(keys) -> np.ndarray:
    return np.stack([(keys >> 16) & 255, (keys >> 8) & 255, keys & 255], axis=-1).astype(np.uint8)


def code_group_palette(display_linear: np.ndarray, codes: np.ndarray):
    """The best table for the paper's codes: each code's mean linear colour.

    Returns (palette (≥256, 3), image (H, W, 3)), both linear.
    """
    lin = np.asarray(display_linear, dtype=float).reshape(-1, 3)
    c = np.asarray(codes).reshape(-1).astype(np.intp)
    size = max(256, int(c.max()) + 1)
    counts = np.bincount(c, minlength=size).astype(float)
    sums = [np.bincount(c, weights=lin[:, j], minlength=size) for j in range(3)]
    palette = np.stack(sums, axis=1)
    palette = palette / np.maximum(counts, 1.0)[:, None]
    return palette, palette[c].reshape(np.shape(display_linear))


def delta_e_2000(rgb8_a: np.ndarray, rgb8_b: np.ndarray) -> np.ndarray:
    """CIEDE2000 between two sRGB images of bytes (uint8), per pixel.

    Computed once per distinct pair of colours (a frame repeats its colours
    many times) and spread back over the pixels.
    """
    import colour

    d65 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]

    a = np.asarray(rgb8_a, np.uint8)
    b = np.asarray(rgb8_b, np.uint8)
    shape = np.broadcast_shapes(a.shape, b.shape)[:-1]
    pairs = (_pack(np.broadcast_to(a, shape + (3,))).reshape(-1) << 24) | _pack(np.broadcast_to(b, shape + (3,))).reshape(-1)
    keys, inverse = np.unique(pairs, return_inverse=True)

    def lab(rgb8):
        return colour.XYZ_to_Lab(colour.sRGB_to_XYZ(rgb8 / 255.0), d65)     # decodes the sRGB curve, D65

    de = np.asarray(colour.delta_E(lab(_unpack(keys >> 24)), lab(_unpack(keys & 0xFFFFFF)), method="CIE 2000"),
                    dtype=float)
    return de[inverse.reshape(-1)].reshape(shape)


#: The figures of the two kernel paths (:mod:`sunset.kernels`) may differ in at most this share of their pixels ...
#: Measured: none of Figures 4–7 at 160 × 160 differ on any packaged scene; the RGB Figure 6 in 1 pixel of
#: 52,480 (carlas-island, with and without clouds: a grazing ray), 1.9e-5.
FIGURE_DIFFER_SHARE = 1e-4
#: ... and by at most this CIEDE2000 difference (1: about a just-noticeable difference). Measured: 0.50.
FIGURE_MAX_DE00 = 1.0


def picture_agreement(rgb8_a: np.ndarray, rgb8_b: np.ndarray) -> dict:
    """How far two 8-bit sRGB pictures (H, W, 3) of the same thing are apart, in terms a reader can weigh.

    Returns ``pixels`` (the count), ``differ`` (the share of pixels whose bytes differ at all), ``visible``
    (the share whose CIEDE2000 difference, :func:`delta_e_2000`, exceeds 1, about a just-noticeable
    difference) and ``max_de00`` (the largest ΔE₀₀). The figures' tests compare the two kernel paths so.
    """
    a = np.asarray(rgb8_a, np.uint8)
    b = np.asarray(rgb8_b, np.uint8)
    if a.shape != b.shape or a.ndim != 3 or a.shape[-1] != 3:
        raise ValueError(f"picture_agreement: two (H, W, 3) pictures of one shape, got {a.shape} and {b.shape}")
    de = delta_e_2000(a, b)
    return {"pixels": int(de.size), "differ": float(np.mean(np.any(a != b, axis=-1))),
            "visible": float(np.mean(de > 1.0)), "max_de00": float(de.max(initial=0.0))}


@dataclass
class QuantisationResult:
    """ΔE₀₀ maps (H, W) of the two palettes, and the images."""

    best: np.ndarray
    codes: np.ndarray
    best_image: np.ndarray
    codes_image: np.ndarray
    reference: np.ndarray

    @staticmethod
    def summary(de: np.ndarray) -> dict:
        """Median, 90th and 99th percentiles, maximum, and the shares above 1 and 3."""
        return {"median": float(np.median(de)), "p90": float(np.percentile(de, 90)),
                "p99": float(np.percentile(de, 99)), "max": float(de.max()),
                "over1": float(np.mean(de > 1.0)), "over3": float(np.mean(de > 3.0))}


def quantisation_test(display_linear: np.ndarray, codes: np.ndarray, sun_disk=None) -> QuantisationResult:
    """Quantise an RGB frame (linear display values) both ways; ΔE₀₀ of each against it.

    ``sun_disk`` (H, W) bool, optional: the pixels the film recorder paints in
    the sun's colour by their raster position (the paper's sun-disk rule,
    :func:`sunset.recorder.dicomed.sun_coverage`), given their own entry beside the
    256 codes, as the recorder gave them the sun's colour whatever their code.
    """
    from .output import to_uint8

    ref = to_uint8(display_linear)
    _, best = median_cut_kmeans(ref)
    codes = np.asarray(codes).astype(np.intp)
    if sun_disk is not None:
        codes = np.where(sun_disk, 256, codes)
    palette, _ = code_group_palette(display_linear, codes)
    by_code = to_uint8(palette)[codes]                   # the bytes of to_uint8 of the image, per code once
    return QuantisationResult(best=delta_e_2000(ref, best), codes=delta_e_2000(ref, by_code), best_image=best,
                              codes_image=by_code, reference=ref)
