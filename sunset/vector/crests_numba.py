"""Numba kernels of the secondary reflections, one ray at a time: pierce the crest, reflect again.

For :func:`sunset.vector.reflect_numba.trace_sea_rays`, the twin of
:func:`sunset.vector.reflect.trace_sea_rays`:

* :func:`crest_phase` is the bounding test of :func:`sunset.vector.crests.crest_candidates`
  (no cosine: :func:`~sunset.vector.crests.crest_rise` bounds the crest's height) and
  :func:`crest_entry` the distance along a candidate to its crest cylinder
  (:func:`~sunset.vector.crests.crest_cylinder`, :func:`~sunset.vector.crests.cylinder_coefficients`,
  :func:`sunset.vector.pierce.first_entry`), the cosine of the reduced phase taken in
  the loop (float64 ``math.cos``, the C library's); :func:`crest_distance` is the two together;
* :func:`sea_normal` is :meth:`sunset.model.waves.Sea.normal` at one point
  (float64 sine and cosine, :func:`sunset.vector.sincos_numba.sincos64`, the
  harmonics by the angle-sum recurrence), :func:`sea_normals_into` the same
  at a block of points, in loops the compiler vectorises.

:func:`sunset.vector.reflect_numba.trace_strip` calls them on the sea pixels' rays.
They agree with the NumPy reference within the tolerances of chapter 10 (tests).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..kernels import jit as _jit
from .sincos_numba import sincos64, sincos64_into
from .crests import CREST_GRACE, crest_curvature, largest_train


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
    """x mod 2π in [0, 2π), as ``np.mod`` gives it to a rounding: x − ⌊x/2π⌋·2π.

    Where that falls outside [0, 2π) (x/2π rounded across an integer), and
    for infinities and NaN, Python's ``%`` decides (the C library's fmod).
    """
    two_pi = 2.0 * math.pi
    r = x - math.floor(x * (1.0 / two_pi)) * two_pi
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
def _crest_bound(ps, qz, rx, ry, rz, crest, amps):
    """The bounding test of :func:`sunset.vector.crests.crest_candidates` for one ray, from its ψ."""
    l, m, omega_t, phase, k, amp_sum, kappa = crest
    two_pi = 2.0 * math.pi
    rate = l * rx + m * ry
    inv_k = 1.0 / k
    u0 = -_phase_ahead(rate, ps) * inv_k
    w = rate * inv_k
    near = min(ps, two_pi - ps)
    rise = 0.0
    for n in range(amps.shape[0]):
        x2 = ((n + 1) * near) * ((n + 1) * near)
        rise = rise + amps[n] * min(2.0, x2 * (0.5 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0))))
    a = -0.5 * kappa * w * w
    b = -kappa * u0 * w - rz
    bow = 0.5 * kappa * u0 * u0
    c = rise - bow + CREST_GRACE * (abs(qz) + amp_sum + bow)
    return (c >= 0.0) | ((b > 0.0) & (b * b - 4.0 * a * c >= 0.0))


@_jit
def crest_phase(qx, qy, qz, rx, ry, rz, crest, amps):
    """(may it meet its crest, ψ = θ mod 2π at its origin) for one ray: the bounding test of
    :func:`sunset.vector.crests.crest_candidates` (its bound :func:`~sunset.vector.crests.crest_rise`).

    ``crest`` = (ℓ, m, ωt, φ, k, Σ a_n, κ) of the largest train and ``amps``
    its a_n (:func:`crest_constants`).
    """
    l, m, omega_t, phase = crest[0], crest[1], crest[2], crest[3]
    ps = mod_two_pi(l * qx + m * qy - omega_t + phase)
    return _crest_bound(ps, qz, rx, ry, rz, crest, amps), ps


@_jit
def crest_block(n, qx, qy, qz, rx, ry, rz, crest, amps, psi, keep, scratch):
    """ψ and the crest's bounding test for the first ``n`` rays of a block, in loops over the block.

    What :func:`crest_phase` does ray by ray, with the same operations, as
    whole-block loops without branches that the compiler vectorises: ψ as
    :func:`mod_two_pi` (the rays whose ψ falls outside [0, 2π), with
    infinities and NaN, take Python's ``%`` in a second loop); then each
    harmonic's bound, then the test.
    ``scratch`` is (5, block) float64.
    """
    l, m, omega_t, phase, k, amp_sum, kappa = crest
    two_pi = 2.0 * math.pi
    inv_two_pi = 1.0 / two_pi
    inv_k = 1.0 / k
    theta, near, rise, a_, b_ = scratch[0], scratch[1], scratch[2], scratch[3], scratch[4]
    for j in range(n):
        x = l * qx[j] + m * qy[j] - omega_t + phase
        theta[j] = x
        psi[j] = x - math.floor(x * inv_two_pi) * two_pi
    for j in range(n):
        p = psi[j]
        if not (p >= 0.0 and p < two_pi):
            psi[j] = theta[j] % two_pi
    for j in range(n):
        p = psi[j]
        rate = l * rx[j] + m * ry[j]
        ahead = (two_pi - p) if rate >= 0.0 else ((-p) if p > 0.0 else -two_pi)
        u0 = -ahead * inv_k
        w = rate * inv_k
        near[j] = min(p, two_pi - p)
        rise[j] = 0.0
        a_[j] = -0.5 * kappa * w * w
        b_[j] = -kappa * u0 * w - rz[j]
        theta[j] = 0.5 * kappa * u0 * u0
    for h in range(amps.shape[0]):
        an = amps[h]
        for j in range(n):
            x2 = ((h + 1) * near[j]) * ((h + 1) * near[j])
            rise[j] = rise[j] + an * min(2.0, x2 * (0.5 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0))))
    for j in range(n):
        bow = theta[j]
        c = rise[j] - bow + CREST_GRACE * (abs(qz[j]) + amp_sum + bow)
        keep[j] = (c >= 0.0) | ((b_[j] > 0.0) & (b_[j] * b_[j] - 4.0 * a_[j] * c >= 0.0))


@_jit
def crest_entry(qx, qy, qz, rx, ry, rz, ps, crest, amps):
    """Distance along a candidate ray to its crest cylinder (ψ from :func:`crest_phase`), +inf where it misses."""
    l, m, omega_t, phase, k, amp_sum, kappa = crest
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
    keep, ps = crest_phase(qx, qy, qz, rx, ry, rz, crest, amps)
    if not keep:
        return np.inf
    return crest_entry(qx, qy, qz, rx, ry, rz, ps, crest, amps)


def crest_constants(train, t: float):
    """(ℓ, m, ωt, φ, k, Σ a_n, κ) and the a_n of a train, for :func:`crest_distance`."""
    l, m = train.wave_vector
    amps = np.ascontiguousarray(train.harmonic_amplitudes(), dtype=np.float64)
    kappa = float(crest_curvature(train))
    return ((float(l), float(m), float(train.omega * t), float(train.phase), float(train.k),
             float(np.sum(amps)), kappa), amps)


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
        s1, c1 = sincos64(theta)
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
def sea_normals_into(n, x, y, waves, coef, count, work, nx, ny, nz):
    """:func:`sea_normal` at the ``n`` points (x[i], y[i]) into (nx, ny, nz)[:n], in loops over the points.

    The same operations in the same order as :func:`sea_normal`, point by point
    (the same bits), train by train over all the points: the phases, their sines
    and cosines in one vectorised loop (:func:`sunset.vector.sincos_numba.sincos64_into`),
    the harmonics, the slopes. ``work`` is (6, ≥ n) float64 scratch.
    """
    theta, s1, c1, cn, sn, slope = work[0, :n], work[1, :n], work[2, :n], work[3, :n], work[4, :n], work[5, :n]
    for i in range(n):
        nx[i] = 0.0
        ny[i] = 0.0
    for j in range(waves.shape[0]):
        l, m, omega_t, phase = waves[j, 0], waves[j, 1], waves[j, 2], waves[j, 3]
        for i in range(n):
            theta[i] = l * x[i] + m * y[i] - omega_t + phase
        sincos64_into(theta, s1, c1)
        a0 = coef[j, 0]
        for i in range(n):
            cn[i] = c1[i]
            sn[i] = s1[i]
            slope[i] = 0.0 - a0 * s1[i]
        for h in range(1, count[j]):
            ah = coef[j, h]
            for i in range(n):
                cc, ss = cn[i] * c1[i] - sn[i] * s1[i], sn[i] * c1[i] + cn[i] * s1[i]
                cn[i] = cc
                sn[i] = ss
                slope[i] = slope[i] - ah * ss
        for i in range(n):
            nx[i] = nx[i] + l * slope[i]
            ny[i] = ny[i] + m * slope[i]
    for i in range(n):
        fx = nx[i]
        fy = ny[i]
        zb = 1.0 / math.sqrt(fx * fx + fy * fy + 1.0)
        nx[i] = -zb * fx
        ny[i] = -zb * fy
        nz[i] = zb


def second_bounce_constants(sea, t: float):
    """What :func:`sunset.vector.reflect_numba.trace_strip` needs for two reflections: (crest constants, a_n, waves, n·a_n, counts), or None.

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
