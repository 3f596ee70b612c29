"""Deferred shading over a wave cycle: its geometry traced once, re-shaded for every hour.

The paper's colour-table animation replayed one cycle of codes through the
tables of each hour (:mod:`sunset.recorder.film`). The same idea, generalised:
the :class:`~sunset.light.geometry.Geometry` of each frame of one wave cycle
is kept, and film frame j shows cycle frame j mod N shaded by the light of its
own hour (:class:`~sunset.light.lighting.Lighting`). No ray is traced twice;
per film frame only the hour's light (its sky grid) and the shading are
computed: the light of its hour (:func:`sunset.light.render.frame_light`, with
the ripples on the posts at its cycle frame's time, so that a film frame is
the same bytes as the single frame ``sunset render --shading rgb`` makes for
that time and hour) and the shading (:func:`film_frame`).

The cycle's geometries are traced, and the film frames shared out to worker
processes, by the pipeline (:func:`sunset.pipeline.rgb.trace_cycle`,
:func:`sunset.pipeline.rgb.film_frames`); ``sunset film --shading rgb`` puts
these together with the cycle's times and the film's hours and encoder.
"""

from __future__ import annotations

from .lighting import Lighting
from .output import to_uint8
from .render import frame_light, shade_display

__all__ = ["film_frame", "LIGHT_CACHE"]


#: Most lights :func:`sunset.pipeline.rgb.film_frames` keeps for frames that come back to the same time and hour.
LIGHT_CACHE = 64


def film_frame(scene, geometries, times, hours, k: int, j: int, lights: dict | None = None):
    """Film frame j, sRGB (H, W, 3) uint8: geometry j mod N, traced at ``times[j mod N]``, shaded for ``hours[j]``.

    ``times`` None: the light of the hour alone (:meth:`Lighting.for_scene`, no ripples on the posts).
    ``lights``: a dict that keeps the light of each (time, hour) met, so that a film whose hours repeat (a
    film at one hour) computes each light once (at most :data:`LIGHT_CACHE` of them).
    """
    n = len(geometries)
    t = None if times is None else float(times[j % n])
    key = (t, float(hours[j]))
    light = None if lights is None else lights.get(key)
    if light is None:
        light = Lighting.for_scene(scene, key[1]) if t is None else frame_light(scene, t, key[1])
        if lights is not None:
            if len(lights) >= LIGHT_CACHE:
                lights.pop(next(iter(lights)))
            lights[key] = light
    return to_uint8(shade_display(geometries[j % n], light, k))
