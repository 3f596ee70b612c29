"""The memory and the work of the RGB back end, predicted before any ray is traced.

``--shading rgb`` with ``samples`` = k² traces the picture at k times its
width and height (:func:`sunset.light.render.supersampled`), so every
per-pixel cost of the vector stage is multiplied by k², and the shading
keeps more per ray than the 8-bit codes do: the :class:`~sunset.light.geometry.Geometry`
(about :data:`GEOMETRY_BYTES_PER_RAY`), the spectral
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
frame (sea, islands, clouds, posts). This module predicts;
:func:`sunset.pipeline.budget.check_rgb_work`, once where an RGB frame or
film begins, refuses a request over budget with one line naming
``samples``, the size and (for a film) ``frames``, before anything is
traced. :func:`sunset.bench.memory.measure_rgb_bytes` measures the two
constants.
"""

from __future__ import annotations

from ..constants import RGB_BYTES_PER_RAY, RGB_LIGHT_BYTES

__all__ = ["GEOMETRY_BYTES_PER_RAY", "rgb_bytes"]

#: A bound on one ray's stored geometry (final ray, normal, kind, throughput, sky lookup, up to three water bounces).
GEOMETRY_BYTES_PER_RAY = 112


def rgb_bytes(width: int, height: int, samples: int = 1, frames: int = 0) -> int:
    """Predicted peak bytes of one RGB frame (``frames`` = 0) or of an RGB film keeping ``frames`` geometries."""
    rays = int(width) * int(height) * int(samples)
    return RGB_LIGHT_BYTES + rays * RGB_BYTES_PER_RAY + int(frames) * rays * GEOMETRY_BYTES_PER_RAY
