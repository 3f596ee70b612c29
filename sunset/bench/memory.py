"""How much memory one frame takes per pixel, measured (the budget is FRAME_BYTES_PER_PIXEL in sunset/constants.py)."""

from __future__ import annotations

__all__ = ["measure_bytes_per_pixel", "measure_rgb_bytes"]


def measure_bytes_per_pixel(scene, sizes=((100, 80), (300, 240)), compiled: bool = False) -> float:
    """Measure how the peak memory of one frame grows per pixel: render, code and expose at two sizes.

    The peak is traced with :mod:`tracemalloc` (NumPy reports its arrays to
    it; arrays the compiled kernels make inside themselves are not seen, so
    the NumPy reference, ``compiled=False``, is the honest and the hungrier
    measurement). The difference of the peaks over the difference of the
    pixel counts leaves out what does not grow with the picture (tables,
    kernels, one strip of sea samples).
    """
    import tracemalloc

    from ..kernels import use_compiled
    from ..recorder.dicomed import expose
    from ..tape.codes import encode
    from ..vector.render import render

    def peak(w, h):
        s = scene.with_size(w, h)
        expose(s, encode(s, render(s, 0.0, 2)), 0.35)          # tables and kernels made once
        tracemalloc.start()
        try:
            expose(s, encode(s, render(s, 0.0, 2)), 0.35)
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    (w0, h0), (w1, h1) = sizes
    with use_compiled(compiled):
        p0, p1 = peak(w0, h0), peak(w1, h1)
    return (p1 - p0) / (w1 * h1 - w0 * h0)


def _traced_peak(fn) -> int:
    import tracemalloc

    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def measure_rgb_bytes(scene, samples: int = 4, sizes=((100, 80), (200, 160))) -> tuple[int, float]:
    """Measure the RGB back end's memory: (the hour's light, bytes; peak bytes per traced ray).

    The light (:func:`sunset.light.render.frame_light`, its sky grid) does
    not grow with the picture: its peak is measured alone. The rest of a
    frame is traced, shaded and encoded the three ways ``render --shading
    rgb`` writes (8-bit PNG, 16-bit PNG, float32 .npy) with the light made
    beforehand; the difference of the peaks over the difference of the rays
    (samples × pixels) is the growth per ray. NumPy reference kernels, as in
    :func:`measure_bytes_per_pixel`. The budget is RGB_LIGHT_BYTES +
    rays × RGB_BYTES_PER_RAY (:mod:`sunset.light.budget`).
    """
    from ..io import png_bytes
    from ..kernels import use_compiled
    from ..light.output import png16_bytes, to_uint16, to_uint8
    from ..light.render import check_samples, frame_light, shade_display, shade_scene_linear, trace_geometry

    k = check_samples(samples)

    def frame(s, light):
        g = trace_geometry(s, 0.0, 2, samples)
        display = shade_display(g, light, k)
        png_bytes(to_uint8(display))
        png16_bytes(to_uint16(display))
        shade_scene_linear(g, light, k)

    with use_compiled(False):
        small = scene.with_size(8, 8)
        frame_light(small, 0.0, 0.35)
        light_peak = _traced_peak(lambda: frame_light(small, 0.0, 0.35))
        peaks = []
        for w, h in sizes:
            s = scene.with_size(w, h)
            light = frame_light(s, 0.0, 0.35)
            frame(s, light)
            peaks.append(_traced_peak(lambda: frame(s, light)))
    (w0, h0), (w1, h1) = sizes
    return light_peak, (peaks[1] - peaks[0]) / ((w1 * h1 - w0 * h0) * samples)
