"""Numba kernels of the sea pixels' rays, one ray at a time: reflect, pierce the crest, reflect again.

For :func:`sunset.vector.reflect_numba.trace_sea_rays`, the twin of
:func:`sunset.vector.reflect.trace_sea_rays`:

* :func:`crest_distance` is the distance along a ray to its crest cylinder
  (:func:`sunset.vector.crests.crest_candidates`, :func:`~sunset.vector.crests.crest_cylinder`,
  :func:`~sunset.vector.crests.cylinder_coefficients`, :func:`sunset.vector.pierce.first_entry`),
  the cosine of the reduced phase taken in the loop (float64 ``math.cos``,
  which is the C library's ``cos`` that NumPy's float64 ``np.cos`` calls);
* :func:`sea_normal` is :meth:`sunset.model.waves.Sea.normal` at one point
  (float64 sine and cosine, the harmonics by the angle-sum recurrence);
* :func:`sea_rays` gathers the sea pixels of a strip of rows, reflects each
  ray (:func:`sunset.vector.pierce.reflect`), with two reflections pierces
  its crest and reflects the hits off the true wave normal, records the
  bounces for the RGB back end (:func:`sunset.vector.reflect.record_bounces`)
  and folds R_z up: one pass, nothing written twice.

The same operations in the same order as the NumPy reference: the frames
are identical (tests).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..kernels import jit as _jit
from ..trig_numba import fma64
from .crests import crest_curvature, crest_lift, largest_train


@_jit
def _quadratic(a, b, c):
    """(t_in, t_out, meets) as sunset.vector.pierce.quadratic_interval, for one ray."""
    d = b * b - 4.0 * a * c
    root = math.sqrt(abs(d))
    qq = -0.5 * (b + math.copysign(root, b))
    if a < 0.0:
        r1 = qq / a
        r2 = c / qq
        # np.fmin / np.fmax: a NaN gives way to the other value
        if r1 != r1:
            t_in = r2
            t_out = r2
        elif r2 != r2:
            t_in = r1
            t_out = r1
        else:
            t_in = min(r1, r2)
            t_out = max(r1, r2)
        return t_in, t_out, d >= 0.0
    lin = -c / b
    t_in = lin if b > 0.0 else -np.inf
    t_out = lin if b < 0.0 else np.inf
    return t_in, t_out, (b != 0.0) or (c >= 0.0)


@_jit
def mod_two_pi(x):
    """x mod 2π as ``np.mod`` (and Python's ``%``) gives it, mostly without fmod.

    With n = ⌊x/2π⌋, the remainder x − n·2π is a real number that
    ``np.mod`` rounds once (fmod's exact remainder, plus 2π where x < 0);
    one fused multiply-add rounds it once too. Where x/2π rounded across an
    integer (the result falls outside [0, 2π)), and for infinities and NaN,
    the C library's fmod decides, as ``np.mod`` does.
    """
    two_pi = 2.0 * math.pi
    r = fma64(-math.floor(x / two_pi), two_pi, x)
    if r >= 0.0 and r < two_pi:
        return r
    return x % two_pi


@_jit
def _phase_ahead(rate, ps):
    """Phase from a ray's start to the next crest ahead of it (as sunset.vector.crests._crest_ahead), radians."""
    two_pi = 2.0 * math.pi
    if rate >= 0.0:
        return two_pi - ps
    if ps > 0.0:
        return -ps
    return -two_pi


@_jit
def crest_phase(qx, qy, rx, ry, rz, crest):
    """(may it meet its crest, ψ = θ mod 2π at its origin) for one ray: the bounding test of
    :func:`sunset.vector.crests.crest_candidates`.

    ``crest`` = (ℓ, m, ωt, φ, k, lift, half-width, Σ a_n, κ) of the largest
    train (:func:`crest_constants`).
    """
    l, m, omega_t, phase, k, lift, half, amp_sum, kappa = crest
    theta = l * qx + m * qy - omega_t + phase
    ps = mod_two_pi(theta)
    if rz > 0.0:
        rate = l * rx + m * ry
        u0 = -_phase_ahead(rate, ps) / k
        u_end = u0 + (rate / k) * (lift / rz)
        if (u0 > half and u_end > half) or (u0 < -half and u_end < -half):
            return False, ps
    return True, ps


@_jit
def crest_entry(qx, qy, qz, rx, ry, rz, ps, crest, amps):
    """Distance along a candidate ray to its crest cylinder (ψ from :func:`crest_phase`), +inf where it misses."""
    l, m, omega_t, phase, k, lift, half, amp_sum, kappa = crest
    rate = l * rx + m * ry
    u0 = -_phase_ahead(rate, ps) / k
    # Σ a_n cos nθ by the Chebyshev recurrence (sunset.vector.crests.harmonic_sum), cos θ = cos ψ
    c1 = math.cos(ps)
    elev = amps[0] * c1
    t_prev = 1.0
    t_cur = c1
    for n in range(1, amps.shape[0]):
        t_next = 2.0 * c1 * t_cur - t_prev
        t_prev = t_cur
        t_cur = t_next
        elev = elev + amps[n] * t_cur
    top = qz + amp_sum - elev
    w = rate / k
    a = -0.5 * kappa * w * w
    b = -kappa * u0 * w - rz
    c = top - 0.5 * kappa * u0 * u0 - qz
    t_in, _, meets = _quadratic(a, b, c)
    if meets and t_in > 0.0 and t_in < np.inf:
        return t_in
    return np.inf


@_jit
def crest_distance(qx, qy, qz, rx, ry, rz, crest, amps):
    """Distance along one ray to its crest cylinder, +inf where it clears the crest or misses."""
    keep, ps = crest_phase(qx, qy, rx, ry, rz, crest)
    if not keep:
        return np.inf
    return crest_entry(qx, qy, qz, rx, ry, rz, ps, crest, amps)


def crest_constants(train, t: float):
    """(ℓ, m, ωt, φ, k, lift, half-width √(2 lift/κ), Σ a_n, κ) and the a_n of a train, for :func:`crest_distance`."""
    l, m = train.wave_vector
    amps = np.ascontiguousarray(train.harmonic_amplitudes(), dtype=np.float64)
    kappa = float(crest_curvature(train))
    lift = crest_lift(train)
    return ((float(l), float(m), float(train.omega * t), float(train.phase), float(train.k), lift,
             math.sqrt(2.0 * lift / kappa), float(np.sum(amps)), kappa), amps)


def sea_constants(sea, t: float):
    """Every train's (ℓ, m, ωt, φ) (T, 4) and n·a_n (T, N) for :func:`sea_normal` (zeros pad short trains)."""
    trains = sea.trains
    width = max([len(tr.harmonic_amplitudes()) for tr in trains] + [1])
    waves = np.zeros((len(trains), 4))
    coef = np.zeros((len(trains), width))
    count = np.zeros(len(trains), np.int64)
    for j, tr in enumerate(trains):
        l, m = tr.wave_vector
        waves[j] = (l, m, tr.omega * t, tr.phase)
        amps = tr.harmonic_amplitudes()
        for n in range(1, len(amps) + 1):
            coef[j, n - 1] = amps[n - 1] * n
        count[j] = len(amps)
    return waves, coef, count


@_jit
def sea_normal(x, y, waves, coef, count):
    """The unit upward normal of the sea at (x, y), float64, as :meth:`sunset.model.waves.Sea.normal`."""
    fx = 0.0
    fy = 0.0
    for j in range(waves.shape[0]):
        l, m, omega_t, phase = waves[j, 0], waves[j, 1], waves[j, 2], waves[j, 3]
        theta = l * x + m * y - omega_t + phase
        c1 = math.cos(theta)
        s1 = math.sin(theta)
        cn = c1
        sn = s1
        slope = 0.0 - coef[j, 0] * sn
        for n in range(1, count[j]):
            cn, sn = cn * c1 - sn * s1, sn * c1 + cn * s1
            slope = slope - coef[j, n] * sn
        fx = fx + l * slope
        fy = fy + m * slope
    zb = 1.0 / math.sqrt(fx * fx + fy * fy + 1.0)
    return -zb * fx, -zb * fy, zb


@_jit
def sea_rays(surface, point, direction, normal, sea_code, second, crest, amps, waves, coef, count,
             record, incidence, sea_rays_out, flat, q, r, bounces):
    """Every sea pixel's ray of a strip, row-major: reflected, maybe reflected again, R_z folded up.

    Fills ``flat`` (row-major pixel index), ``q``, ``r`` (float64, after
    |R_z|) and ``bounces``; with ``record``, ``incidence`` and
    ``sea_rays_out`` at those pixels. Returns the lowest origin of a ray
    heading up (+inf: none), as the island table needs. Two passes, as
    the reference's compress: reflect every ray and test it against its
    crest; pierce the candidates' crests and reflect the hits again. R_z is
    folded up where a ray is final (a candidate's after its crest).
    """
    H, W = surface.shape
    n = q.shape[0]
    cand = np.empty(n if second else 0, np.intp)
    psi = np.empty(n if second else 0)
    n_cand = 0
    z0 = np.inf
    j = 0
    for yy in range(H):
        for xx in range(W):
            if surface[yy, xx] != sea_code:
                continue
            flat[j] = yy * W + xx
            dx = np.float64(direction[yy, xx, 0])
            dy = np.float64(direction[yy, xx, 1])
            dz = np.float64(direction[yy, xx, 2])
            nx = np.float64(normal[yy, xx, 0])
            ny = np.float64(normal[yy, xx, 1])
            nz = np.float64(normal[yy, xx, 2])
            dot = dx * nx + dy * ny + dz * nz
            two = 2.0 * dot
            qx = np.float64(point[yy, xx, 0])
            qy = np.float64(point[yy, xx, 1])
            q[j, 0] = qx
            q[j, 1] = qy
            q[j, 2] = np.float64(point[yy, xx, 2])
            rx = dx - two * nx
            ry = dy - two * ny
            rz = dz - two * nz
            r[j, 0] = rx
            r[j, 1] = ry
            r[j, 2] = rz
            bounces[j] = 1
            if record:
                incidence[yy, xx, 0] = -dot
                sea_rays_out[yy, xx, 0, 0] = rx
                sea_rays_out[yy, xx, 0, 1] = ry
                sea_rays_out[yy, xx, 0, 2] = rz
            keep = False
            if second:
                keep, ps = crest_phase(qx, qy, rx, ry, rz, crest)
                if keep:
                    cand[n_cand] = j
                    psi[n_cand] = ps
                    n_cand += 1
            if not keep:                      # final: fold R_z up (a candidate's, after its crest)
                rz = abs(rz)
                r[j, 2] = rz
                if rz >= 0.0 and q[j, 2] < z0:
                    z0 = q[j, 2]
            j += 1
    for c in range(n_cand):
        j = cand[c]
        qx, qy, qz = q[j, 0], q[j, 1], q[j, 2]
        rx, ry, rz = r[j, 0], r[j, 1], r[j, 2]
        t = crest_entry(qx, qy, qz, rx, ry, rz, psi[c], crest, amps)
        if t < np.inf:
            px = qx + t * rx
            py = qy + t * ry
            pz = qz + t * rz
            mx, my, mz = sea_normal(px, py, waves, coef, count)
            two = 2.0 * (rx * mx + ry * my + rz * mz)
            sx = rx - two * mx
            sy = ry - two * my
            sz = rz - two * mz
            if record:
                yy = flat[j] // W
                xx = flat[j] - yy * W
                ex = sx - rx
                ey = sy - ry
                ez = sz - rz
                incidence[yy, xx, 1] = 0.5 * math.sqrt(ex * ex + ey * ey + ez * ez)
                sea_rays_out[yy, xx, 1, 0] = sx
                sea_rays_out[yy, xx, 1, 1] = sy
                sea_rays_out[yy, xx, 1, 2] = sz
            q[j, 0] = px
            q[j, 1] = py
            q[j, 2] = pz
            r[j, 0] = sx
            r[j, 1] = sy
            r[j, 2] = sz
            bounces[j] = 2
        rz = abs(r[j, 2])
        r[j, 2] = rz
        if rz >= 0.0 and q[j, 2] < z0:
            z0 = q[j, 2]
    return z0


def second_bounce_constants(sea, t: float):
    """What :func:`sea_rays` needs for two reflections: (crest constants, a_n, waves, n·a_n, counts), or None.

    Kept for the last few (sea, t): every strip of a frame asks for the same (the arrays are only read).
    """
    return _second_bounce_constants(sea, float(t), math.copysign(1.0, t))


@functools.lru_cache(maxsize=16)
def _second_bounce_constants(sea, t: float, sign: float):
    """:func:`second_bounce_constants`, cached; ``sign`` tells −0.0 from 0.0 (equal as keys)."""
    train = largest_train(sea)
    if train is None:
        return None
    crest, amps = crest_constants(train, t)
    return (crest, amps, *sea_constants(sea, t))
