"""Measuring anti-aliasing: supersampled frames against a 64-samples-per-pixel reference.

Paint by numbers could not anti-alias: a pixel's code names one surface, so a
pixel half island, half sky must be one or the other. The RGB back end mixes
its samples in linear light (:mod:`sunset.light.render`). How much that buys
is measured here, where aliasing shows:

* **island/sky edges**: pixels whose reference sub-samples' direct rays meet
  both an island and something else (sky or sea);
* **the sun's rim**: pixels whose reference sub-samples' final rays fall partly
  inside and partly outside the sun's disk (the disk itself and its
  reflections in the glitter).

The error of a frame at k² samples per pixel is the difference from the
reference (8 × 8 = 64 samples) in 8-bit sRGB units, root mean square over
the three channels and over the pixels of each class.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import SKY
from ..light.geometry import Geometry
from ..light.lighting import Lighting
from ..light.render import check_samples, shade_display, supersampled
from ..light.tone import encode_srgb
from .frame import render

__all__ = ["REFERENCE_SAMPLES", "AAResult", "edge_masks", "aa_errors"]

#: Samples per pixel of the reference (an 8 × 8 grid).
REFERENCE_SAMPLES = 64


@dataclass
class AAResult:
    """Errors (8-bit sRGB units, RMS) of each sample count, per pixel class."""

    samples: tuple
    edge: dict            # samples -> RMS error over island/sky edge pixels
    rim: dict             # samples -> RMS error over sun-rim pixels
    everywhere: dict      # samples -> RMS error over all pixels
    edge_pixels: int
    rim_pixels: int
    images: dict          # samples -> sRGB-encoded image (H, W, 3) float in [0, 1], and "reference"


def edge_masks(frame, geometry: Geometry, light: Lighting, k: int):
    """(edge, rim) boolean (H, W) masks from a k×-supersampled frame and its geometry."""
    h, w = frame.shape[0] // k, frame.shape[1] // k
    island = (frame.surface > 0).reshape(h, k, w, k)
    frac = island.mean(axis=(1, 3))
    edge = (frac > 0) & (frac < 1)
    d = geometry.final_dir.astype(np.float64)
    in_sun = ((d @ light.sun_dir > math.cos(light.delta)) & (geometry.final_kind == SKY)
              & (d[:, 2] >= 0)).reshape(h, k, w, k)
    f_sun = in_sun.mean(axis=(1, 3))
    rim = (f_sun > 0) & (f_sun < 1)
    return edge, rim


def _rms(a, b, mask) -> float:
    if not np.any(mask):
        return float("nan")
    diff = (a[mask] - b[mask]) * 255.0
    return float(np.sqrt(np.mean(diff * diff)))


def aa_errors(scene, t: float = 0.0, hours: float = 0.35, samples=(1, 4, 9, 16), reflections: int = 2,
              reference: int = REFERENCE_SAMPLES) -> AAResult:
    """Render ``scene`` at each sample count and at ``reference`` samples; the errors at edges and the sun's rim."""
    light = Lighting.for_scene(scene, hours)
    kr = check_samples(reference)
    ref_frame = render(supersampled(scene, kr), float(t), reflections, sea_bounces=True)
    ref_geom = Geometry.from_frame(ref_frame)
    ref = encode_srgb(shade_display(ref_geom, light, kr))
    edge, rim = edge_masks(ref_frame, ref_geom, light, kr)
    del ref_frame
    out = AAResult(samples=tuple(samples), edge={}, rim={}, everywhere={}, edge_pixels=int(edge.sum()),
                   rim_pixels=int(rim.sum()), images={"reference": ref})
    everything = np.ones(edge.shape, bool)
    for s in samples:
        k = check_samples(s)
        geom = Geometry.from_frame(render(supersampled(scene, k) if k > 1 else scene, float(t), reflections,
                                          sea_bounces=True))
        img = encode_srgb(shade_display(geom, light, k))
        out.images[s] = img
        out.edge[s] = _rms(img, ref, edge)
        out.rim[s] = _rms(img, ref, rim)
        out.everywhere[s] = _rms(img, ref, everything)
    return out
