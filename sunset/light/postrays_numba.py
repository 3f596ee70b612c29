"""Numba twin of :func:`sunset.light.postrays.post_rays`: one sun ray at a time, in registers.

The same formulas in the same order (the table's cosines summed term after
term, Fresnel's two polarisations, the cylinder's quadratic in its
cancellation-free form), with the math library's sine, cosine and arctangent.
It agrees with the NumPy reference within round-off (tested: the codes the
same, the coordinates within :data:`COORD_ATOL`, but where a ray passes
within round-off of the post's silhouette). Each ray is computed alone, so the rays may be cut
into strips on threads and any split gives the same bytes.
"""

from __future__ import annotations

import math

import numpy as np

from ..kernels import jit as _jit
from ..kernels import run_strips, strips
from .caustics import LIT

__all__ = ["post_rays"]

#: Rays per strip on the threads.
STRIP = 16384
#: How far the compiled results may stray from the reference's where both give a ray the same code: texture
#: coordinates in texels, fluxes, reflectances and paths (round-off; measured: 0, the same operations).
COORD_ATOL = 1e-9


@_jit
def _side(cx, cy, rho, qx, qy, rx, ry):
    u, v = qx - cx, qy - cy
    a = rx * rx + ry * ry
    b = 2.0 * (u * rx + v * ry)
    c = u * u + v * v - rho * rho
    disc = b * b - 4.0 * a * c
    if not (disc > 0.0 and a > 0.0 and c > 0.0):
        return math.inf
    qq = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    t = min(qq / a, c / qq)
    return t if t > 0.0 else math.inf


@_jit
def _rays(a, b, amp, kx, ky, c, g, code, omega, R, ur, vr, ut, vt, path, glance, xs, ys, etas, start, stop):
    cx, cy, rho = g[0], g[1], g[2]
    px, py, pz = g[9], g[10], g[11]
    n = g[17]
    for i in range(start, stop):
        x = cx + g[3] * a[i] * g[7] + g[5] * (2.0 * b[i] - 1.0) * g[8]
        y = cy + g[4] * a[i] * g[7] + g[6] * (2.0 * b[i] - 1.0) * g[8]
        eta = 0.0
        fx = 0.0
        fy = 0.0
        for h in range(amp.size):
            theta = kx[h] * x + ky[h] * y + c[h]
            eta += amp[h] * math.cos(theta)
            s = amp[h] * math.sin(theta)
            fx -= kx[h] * s
            fy -= ky[h] * s
        inv = 1.0 / math.sqrt(fx * fx + fy * fy + 1.0)
        nx, ny, nz = -fx * inv, -fy * inv, inv
        omega[i] = max(pz - px * fx - py * fy, 0.0)
        pn = px * nx + py * ny + pz * nz
        ci = min(max(pn, 0.0), 1.0)
        ct = math.sqrt(1.0 - (1.0 - ci * ci) / (n * n))
        R[i] = 0.5 * (((ci - n * ct) / (ci + n * ct)) ** 2 + ((n * ci - ct) / (n * ci + ct)) ** 2)
        rx, ry, rz = -px + 2.0 * pn * nx, -py + 2.0 * pn * ny, -pz + 2.0 * pn * nz
        k = ci / n - ct
        tx, ty, tz = -px / n + k * nx, -py / n + k * ny, -pz / n + k * nz
        xs[i], ys[i], etas[i] = x, y, eta
        ur[i], vr[i], ut[i], vt[i] = math.nan, math.nan, math.nan, math.nan
        path[i], glance[i] = 0.0, 1.0
        if math.hypot(x - cx, y - cy) <= rho:
            code[i] = 2
            continue
        t_r = _side(cx, cy, rho, x, y, rx, ry)
        t_t = _side(cx, cy, rho, x, y, tx, ty)
        code_r = 2 if rz <= 0.0 else (0 if t_r < math.inf else 1)
        code_t = 0 if t_t < math.inf else 1
        code[i] = LIT + 10 * code_r + code_t
        if code_r == 0:
            hx, hy = x + t_r * rx - cx, y + t_r * ry - cy
            phi = math.atan2(hy, hx) % (2.0 * math.pi)
            ur[i] = phi / g[16]
            vr[i] = (eta + t_r * rz - g[12]) / g[13]
            glance[i] = min(glance[i], -(math.cos(phi) * rx + math.sin(phi) * ry))
        if code_t == 0:
            hx, hy = x + t_t * tx - cx, y + t_t * ty - cy
            phi = math.atan2(hy, hx) % (2.0 * math.pi)
            ut[i] = phi / g[16]
            vt[i] = (eta + t_t * tz - g[14]) / g[15]
            glance[i] = min(glance[i], -(math.cos(phi) * tx + math.sin(phi) * ty))
            path[i] = t_t


def post_rays(a, b, amp, kx, ky, c, geo):
    """:func:`sunset.light.postrays.post_rays` compiled."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    n = a.size
    code = np.empty(n, np.int64)
    out = [np.empty(n) for _ in range(11)]
    parts = strips(n, STRIP) if n > STRIP else [(0, n)]
    run_strips(lambda s, e: _rays(a, b, amp, kx, ky, c, np.asarray(geo, dtype=np.float64), code, *out, s, e), parts)
    return (code, *out)
