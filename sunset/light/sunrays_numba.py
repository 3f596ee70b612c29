"""Numba twins of :func:`sunset.light.sunrays.surface` and :func:`sunset.light.sunrays.visible`.

One point at a time, the table's cosines summed in the table's order, the
math library's sine and cosine. They agree with the NumPy references within
the round-off of a sum of cosines (tested: heights and slopes to 1e-12 of the
sea's amplitude, :data:`SURFACE_ATOL`; the shadow test's answer the same on
every ray of the tests). Each point is computed alone, so the points may
be cut into strips on threads (:func:`sunset.kernels.run_strips`) and any
split gives the same bytes.
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels import jit as _jit
from ..kernels import run_strips, strips
from .sunrays import SHADOW_STEPS, SHADOW_TOLERANCE

__all__ = ["surface", "visible"]

#: Points per strip on the threads.
STRIP = 16384
#: How far the compiled heights and slopes may stray from the reference's, times the sea's Σ|a| (metres for
#: the heights; the slopes are held to the same number): the round-off of a sum of cosines of large phases.
SURFACE_ATOL = 1e-12


def _parts(n: int) -> list:
    """Strips of at least STRIP points (one strip for fewer: no threads for a small call)."""
    return strips(n, STRIP) if n > STRIP else [(0, n)]


@_jit
def _surface(a, kx, ky, c, x, y, eta, gx, gy, start, stop):
    for i in range(start, stop):
        e = 0.0
        sx = 0.0
        sy = 0.0
        for h in range(a.size):
            theta = kx[h] * x[i] + ky[h] * y[i] + c[h]
            e += a[h] * math.cos(theta)
            s = a[h] * math.sin(theta)
            sx -= kx[h] * s
            sy -= ky[h] * s
        eta[i] = e
        gx[i] = sx
        gy[i] = sy


def surface(a, kx, ky, c, x, y):
    """:func:`sunset.light.sunrays.surface` compiled."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    y = np.ascontiguousarray(y, dtype=np.float64)
    eta, gx, gy = np.empty(x.shape), np.empty(x.shape), np.empty(x.shape)
    run_strips(lambda s, e: _surface(a, kx, ky, c, x, y, eta, gx, gy, s, e), _parts(x.size))
    return eta, gx, gy


@_jit
def _visible(a, kx, ky, c, top, qx, qy, qz, omega, px, py, pz, steps, tol, lit, start, stop):
    n = a.size
    curv = 0.0
    for h in range(n):
        kp = kx[h] * px + ky[h] * py
        curv += abs(a[h]) * kp * kp
    curv = max(curv, 1e-300)
    for i in range(start, stop):
        lit[i] = False
        if not omega[i] > 0:
            continue
        tau = omega[i] / curv
        for _ in range(steps):
            height = qz[i] + tau * pz
            if height >= top:
                lit[i] = True
                break
            x = qx[i] + tau * px
            y = qy[i] + tau * py
            e = 0.0
            sx = 0.0
            sy = 0.0
            for h in range(n):
                theta = kx[h] * x + ky[h] * y + c[h]
                e += a[h] * math.cos(theta)
                s = a[h] * math.sin(theta)
                sx -= kx[h] * s
                sy -= ky[h] * s
            g = height - e
            if not g > tol:
                break
            climb = pz - px * sx - py * sy
            tau = tau + g / (math.sqrt(climb * climb + 2.0 * curv * g) - climb)


def visible(a, kx, ky, c, top: float, qx, qy, qz, omega, p) -> np.ndarray:
    """:func:`sunset.light.sunrays.visible` compiled."""
    lit = np.empty(qx.shape, dtype=np.bool_)
    args = (np.ascontiguousarray(qx, dtype=np.float64), np.ascontiguousarray(qy, dtype=np.float64),
            np.ascontiguousarray(qz, dtype=np.float64), np.ascontiguousarray(omega, dtype=np.float64))
    px, py, pz = (float(v) for v in p)
    run_strips(lambda s, e: _visible(a, kx, ky, c, float(top), *args, px, py, pz, SHADOW_STEPS, SHADOW_TOLERANCE,
                                     lit, s, e), _parts(qx.size))
    return lit
