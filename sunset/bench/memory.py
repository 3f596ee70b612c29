"""How much memory one frame takes per pixel, measured (the budget is FRAME_BYTES_PER_PIXEL in sunset/constants.py)."""

from __future__ import annotations

__all__ = ["measure_bytes_per_pixel"]


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
