"""The RGB back end's rows of ``make bench`` (:mod:`sunset.light`), measured in a child process like the others."""

from __future__ import annotations

import time

from .extra import timed

__all__ = ["measure_rgb"]


def measure_rgb(width: int, height: int, repeats: int) -> dict:
    """The RGB back end (:mod:`sunset.light`): re-shading a stored frame, one hour's light, a 4-sample frame.

    The 4-sample frame is also split into its vector stage (2 × 2 rays per pixel) and what the back end adds
    (the geometry, the shading, the response and the 2 × 2 box filter), from the same runs.

    As the ``sunset`` command does, the allocator keeps freed blocks (:func:`sunset.kernels.keep_freed_memory`).
    """
    from ..kernels import keep_freed_memory
    from ..light.geometry import Geometry
    from ..light.lighting import Lighting
    from ..light.render import shade_display, supersampled
    from ..pipeline.rgb import trace_geometry
    from ..pipeline.frame import render
    from ..model.scene import Scene

    keep_freed_memory()
    scene = Scene.default().with_size(width, height)
    geometry = trace_geometry(scene, 0.0, 2)
    light = Lighting.for_hour(scene.sun, 0.35)
    fine = supersampled(scene, 2)

    def four() -> tuple[float, float]:
        # trace_geometry(scene, 0.0, 2, 4), split: the vector stage at 2 x 2 rays per pixel, then the back end
        t0 = time.perf_counter()
        frame = render(fine, 0.0, 2, sea_bounces=True)
        t1 = time.perf_counter()
        shade_display(Geometry.from_frame(frame), light, 2)
        return t1 - t0, time.perf_counter() - t1

    four()                                                                    # warm-up
    split = [four() for _ in range(repeats)]
    return {"shade stored frame": timed(lambda: shade_display(geometry, light), repeats),
            "light of one hour": timed(lambda: Lighting.for_hour(scene.sun, 0.5), repeats),
            "4-sample frame": [a + b for a, b in split],
            "4-sample vector": [a for a, _ in split],
            "4-sample back end": [b for _, b in split]}
