"""The RGB back end's shading: a frame's geometry shaded, box-filtered and tone-mapped.

The rays are traced by the pipeline (:func:`sunset.pipeline.rgb.trace_geometry`,
:func:`sunset.pipeline.rgb.render_rgb`), at ``samples`` = k² per pixel.

Supersampling pattern
---------------------
``samples`` = k² rays per pixel on a regular k × k grid: the vector stage
renders the same window at k times the width and the height (each ray
through the centre of a k × k sub-pixel cell, σ kept in sub-pixels, so every
ray is traced as finely as at one sample per pixel), and the k × k block of
each pixel is averaged with equal weights (a box filter) in *linear light*:
after the eye's response, before the sRGB transfer curve, as the film
recorder mixes the sun's rim. Averaging before the response would let one
sample of the sun's disk (10⁴ times the sky) whiten its whole pixel.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import SunsetError, require_int_range
from .geometry import Geometry
from .lighting import Lighting
from .shade import shade
from .tone import display_filtered, scene_linear

__all__ = ["MAX_SAMPLES", "check_samples", "supersampled", "shade_display", "frame_light", "box_filter",
           "shade_scene_linear"]

#: Most samples per pixel (a 16 × 16 grid).
MAX_SAMPLES = 256


def check_samples(samples) -> int:
    """k for ``samples`` = k², or a :class:`SunsetError` (samples must be a square: 1, 4, 9, 16, …)."""
    require_int_range("samples", samples, 1, MAX_SAMPLES)
    k = math.isqrt(int(samples))
    if k * k != samples:
        raise SunsetError(f"samples must be a square number (1, 4, 9, 16, ... : a k x k grid), got {samples!r}")
    return k


def supersampled(scene, k: int):
    """The scene with its picture k times wider and taller (same window, σ in sub-pixels)."""
    cam = scene.camera
    return scene.with_size(cam.width * k, cam.height * k)


def box_filter(image: np.ndarray, k: int) -> np.ndarray:
    """Mean of each k × k block of an (kH, kW, c) image: (H, W, c)."""
    if k == 1:
        return image
    h, w = image.shape[0] // k, image.shape[1] // k
    return image.reshape(h, k, w, k, -1).mean(axis=(1, 3))


def shade_display(geometry: Geometry, light: Lighting, k: int = 1) -> np.ndarray:
    """Shade, apply the film's response and box-filter k × k: linear display RGB (H, W, 3) in [0, 1].

    The response and the filter are one pass (:func:`sunset.light.tone.display_filtered`): the same bytes as
    ``box_filter(display_linear(shade(geometry, light), light.scale), k)``.
    """
    return display_filtered(shade(geometry, light), light.scale, k)


def shade_scene_linear(geometry: Geometry, light: Lighting, k: int = 1) -> np.ndarray:
    """Exposed scene-referred linear sRGB (H, W, 3) float32: radiance box-filtered k × k, no response curve."""
    return scene_linear(box_filter(shade(geometry, light), k), light.scale).astype(np.float32)


def frame_light(scene, t: float, hours: float, shore: bool = True) -> Lighting:
    """The light of one frame: the hour's sky and sun, the scene's clouds, and the ripples of light the waves
    throw at time ``t`` on its posts (:func:`sunset.light.ripples.ripple_source`) and on its islands' shores
    near the water line (:func:`sunset.light.shore.shore_source`, unless ``shore`` is False), which depend on
    the waves' time as well as the hour; with the sun's centre below the horizon there is no sunlight for the
    waves to throw, and no ripples. A sea given by its wind (``scene.sea.wind``) throws none either: the light
    tracers read the sea as its trains' cosines (:func:`sunset.light.sunrays.sea_table`), and a wind sea has no
    trains (its still water would throw a mirror's flat band instead).
    """
    light = Lighting.for_scene(scene, hours)
    if light.sun_dir[2] <= 0.0 or scene.sea.wind is not None:    # no sunlight on the waves, or no trains
        return light
    if scene.posts:
        from .ripples import ripple_source

        light.extra_irradiance.append(ripple_source(scene, float(t), float(hours), light))
    if shore and scene.islands:
        from .shore import shore_source

        light.extra_irradiance.append(shore_source(scene, float(t), float(hours), light))
    return light
