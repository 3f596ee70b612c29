"""Deferred shading over a wave cycle: its geometry traced once, re-shaded for every hour.

The paper's colour-table animation replayed one cycle of codes through the
tables of each hour (:mod:`sunset.recorder.film`). The same idea, generalised:
the :class:`~sunset.light.geometry.Geometry` of each frame of one wave cycle
is kept, and film frame j shows cycle frame j mod N shaded by the light of its
own hour (:class:`~sunset.light.lighting.Lighting`). No ray is traced twice;
per film frame only the hour's light (its sky grid) and the shading are
computed. The geometries are held in memory, so their size is bounded
(:data:`MAX_GEOMETRY_BYTES`). ``sunset film --shading rgb`` puts these
together with the cycle's times and the film's hours and encoder.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import SunsetError, require_finite, require_int_range
from .lighting import Lighting
from .output import check_rgb_output, save_rgb, to_uint8
from .render import check_samples, frame_light, shade_display, shade_scene_linear, trace_geometry

__all__ = ["MAX_GEOMETRY_BYTES", "GEOMETRY_BYTES_PER_RAY", "write_rgb_frame", "trace_cycle", "film_frames"]

#: Most bytes the stored geometries of one cycle may take.
MAX_GEOMETRY_BYTES = 3 * 2**30
#: A bound on one ray's stored geometry (final ray, normal, kind, throughput, sky lookup, up to three water bounces).
GEOMETRY_BYTES_PER_RAY = 112


def write_rgb_frame(scene, path, t: float = 0.0, hours: float = 0.35, samples: int = 1, reflections: int = 2,
                    depth: int = 8, metadata: dict | None = None) -> Path:
    """Render one RGB frame and write it (PNG 8/16 bit or float32 .npy, :mod:`sunset.light.output`)."""
    path = check_rgb_output(path, depth)
    k = check_samples(samples)
    require_finite("hours", hours)
    geometry = trace_geometry(scene, t, reflections, samples)
    light = frame_light(scene, t, hours)
    if path.suffix.lower() == ".npy":
        return save_rgb(path, None, shade_scene_linear(geometry, light, k), depth=depth)
    return save_rgb(path, shade_display(geometry, light, k), depth=depth, metadata=metadata)


def _bar(total: int, desc: str, progress: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="frame", file=sys.stderr, disable=not progress, leave=False)


def trace_cycle(scene, times, reflections: int = 2, samples: int = 1, progress: bool = True) -> list:
    """The geometries of the frames at ``times`` (one wave cycle), each traced once."""
    require_int_range("reflections", reflections, 0, 2)
    check_samples(samples)
    from .budget import check_rgb_work

    check_rgb_work(scene, samples, frames=len(times))
    cam = scene.camera
    need = len(times) * cam.width * cam.height * samples * GEOMETRY_BYTES_PER_RAY
    if need > MAX_GEOMETRY_BYTES:
        per = f"{samples} sample{'s' * (samples != 1)} per pixel"
        raise SunsetError(f"frames: {len(times)} frames at {cam.width}x{cam.height}, {per}, would keep up to "
                          f"{need / 2**30:.1f} GiB of geometry (at most "
                          f"{MAX_GEOMETRY_BYTES / 2**30:g} GiB): use fewer frames, fewer samples or a smaller picture")
    out = []
    with _bar(len(times), "tracing the wave cycle", progress) as bar:
        for t in times:
            out.append(trace_geometry(scene, float(t), reflections, samples))
            bar.update(1)
    return out


def film_frames(scene, geometries, hours, samples: int = 1):
    """Yield an sRGB frame (H, W, 3) uint8 per entry of ``hours``: geometry j mod N shaded for hour j."""
    k = check_samples(samples)
    n = len(geometries)
    for j, h in enumerate(hours):
        yield to_uint8(shade_display(geometries[j % n], Lighting.for_scene(scene, float(h)), k))
