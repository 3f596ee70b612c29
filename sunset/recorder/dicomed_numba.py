"""Numba twin of :func:`sunset.recorder.dicomed.lookup`: the film recorder's table lookup, pixel by pixel.

``np.take`` copies each pixel's three bytes with a general-purpose loop;
this one reads the code and writes its three table entries. The same bytes
(tests). Chosen by :mod:`sunset.kernels`.
"""

from __future__ import annotations

import numpy as np

from ..kernels import jit as _jit


@_jit
def _lookup(lut, codes, out):
    h, w = codes.shape
    for i in range(h):
        for j in range(w):
            c = codes[i, j]
            out[i, j, 0] = lut[c, 0]
            out[i, j, 1] = lut[c, 1]
            out[i, j, 2] = lut[c, 2]


def lookup(lut, codes, out) -> None:
    """:func:`sunset.recorder.dicomed.lookup` compiled: ``out[i, j] = lut[codes[i, j]]`` (uint8, in place)."""
    if lut.shape != (256, 3) or lut.dtype != np.uint8 or codes.dtype != np.uint8 or out.dtype != np.uint8:
        raise ValueError("lookup: lut (256, 3), codes and out must be uint8")
    _lookup(np.ascontiguousarray(lut), codes, out)
