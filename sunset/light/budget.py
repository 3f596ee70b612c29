"""The memory and the work of the RGB back end, predicted before any ray is traced.

``--shading rgb`` with ``samples`` = k² traces the picture at k times its
width and height (:func:`sunset.light.render.supersampled`), so every
per-pixel cost of the vector stage is multiplied by k², and the shading
keeps more per ray than the 8-bit codes do: the :class:`~sunset.light.geometry.Geometry`
(about :data:`~sunset.light.film.GEOMETRY_BYTES_PER_RAY`), the spectral
radiance and its response, the box filter and the encoder. One frame's peak
is bounded by

    bytes = RGB_LIGHT_BYTES + rays × RGB_BYTES_PER_RAY,   rays = k² W H,

with :data:`~sunset.constants.RGB_LIGHT_BYTES` the hour's light (its sky
grid), which does not grow with the picture; the interpreter's own
:data:`~sunset.constants.INTERPRETER_BYTES` comes on top. A film (``film --shading rgb``)
keeps the geometry of every frame of its wave cycle and shades one film frame
at a time: frames × rays × GEOMETRY_BYTES_PER_RAY more. Both must stay within
:data:`~sunset.constants.MAX_FRAME_BYTES`; the work of the k-times finer
frame is then checked by :func:`sunset.vector.budget.check_work` as for any
frame (sea, islands, clouds, posts). :func:`check_rgb_work` refuses a request
over budget with one line naming ``samples``, the size and (for a film)
``frames``, before anything is traced; :func:`sunset.bench.memory.measure_rgb_bytes`
measures the two constants.
"""

from __future__ import annotations

import math

from ..constants import INTERPRETER_BYTES, MAX_FRAME_BYTES, MAX_PIXELS, RGB_BYTES_PER_RAY, RGB_LIGHT_BYTES
from ..errors import SunsetError

__all__ = ["rgb_bytes", "check_rgb_work"]


def rgb_bytes(width: int, height: int, samples: int = 1, frames: int = 0) -> int:
    """Predicted peak bytes of one RGB frame (``frames`` = 0) or of an RGB film keeping ``frames`` geometries."""
    from .film import GEOMETRY_BYTES_PER_RAY

    rays = int(width) * int(height) * int(samples)
    return RGB_LIGHT_BYTES + rays * RGB_BYTES_PER_RAY + int(frames) * rays * GEOMETRY_BYTES_PER_RAY


def check_rgb_work(scene, samples: int = 1, frames: int = 0) -> int:
    """Raise :class:`SunsetError` when the RGB back end would exceed its budget; else the predicted bytes.

    Checked before the picture is supersampled: the rays (k² per pixel) may be
    at most MAX_PIXELS, and the predicted peak (:func:`rgb_bytes`) with the
    interpreter's INTERPRETER_BYTES at most MAX_FRAME_BYTES. Then the supersampled frame's own work (samples of the
    sea, the islands, the clouds and the posts) is checked as any frame's.
    """
    from ..vector.budget import check_work
    from .render import check_samples, supersampled

    k = check_samples(samples)
    cam = scene.camera
    W, H = cam.width, cam.height
    size = f"{W}x{H}"
    per = "" if samples == 1 else f" at {samples} samples per pixel"
    one = rgb_bytes(W, H, samples)
    if W * H * samples > MAX_PIXELS or INTERPRETER_BYTES + one > MAX_FRAME_BYTES:
        raise SunsetError(f"samples: a {size} picture{per} needs about {math.ceil(one / 2**20):,} MiB and traces "
                          f"{W * H * samples:,} rays (at most {MAX_FRAME_BYTES // 2**20:,} MiB and "
                          f"{MAX_PIXELS:,} rays): use fewer samples or a smaller picture")
    need = rgb_bytes(W, H, samples, frames)
    if INTERPRETER_BYTES + need > MAX_FRAME_BYTES:
        raise SunsetError(f"frames: {frames} frames of a {size} picture{per} keep about {math.ceil(need / 2**20):,} "
                          f"MiB of geometry and light (at most {MAX_FRAME_BYTES // 2**20:,} MiB): use fewer frames, "
                          f"fewer samples or a smaller picture")
    try:
        check_work(supersampled(scene, k) if k > 1 else scene)
    except SunsetError as exc:
        if k == 1:
            raise
        raise SunsetError(f"samples: {samples} samples per pixel trace the picture at {W * k}x{H * k}: "
                          f"{exc}") from None
    return need
