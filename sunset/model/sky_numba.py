"""Numba twin of :func:`sunset.model.sky.sky_radiance`: the sky's single-scattering integral, compiled.

The NumPy reference builds, for K view rays × n_view points × n_sun points
towards the sun, arrays of heights, densities and their products, and then
the (K, n_view, n_λ) transmittances: hundreds of megabytes of memory
traffic for one film frame's colour tables. This twin walks the same points
one at a time, with the same operations in the same order, so that it gives
the reference's bits:

* the view ray's cumulative columns in NumPy's ``cumsum`` order, element by
  element from the ray's start;
* each point's column towards the sun (:func:`sunset.model.sky.slant_columns`)
  summed from the point outwards, as ``einsum`` sums it;
* the optical depth ``col @ tau`` as the BLAS kernel computes a product with
  an inner dimension of 3: a product, then two fused multiply-adds,
  τ₂c₂ + (τ₁c₁ + τ₀c₀);
* each ``exp`` as NumPy takes it for float64 in this process
  (:func:`sunset.exp_numba.choice`): the C library's (x86 without AVX-512),
  or SVML's algorithm written out (x86 with AVX-512), an argument of the
  kernel;
* the sum over the view ray in order, as NumPy's ``sum(axis=1)`` adds rows.

The BLAS kernel and NumPy's ``exp`` are chosen at run time by the CPU, so
whether this holds is checked once per process by :func:`matches_numpy`, on a
probe of directions and sun positions; where it does not, the twin hands the
call to the NumPy reference (the same bytes, more slowly).
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import (AEROSOL_ALBEDO, AEROSOL_SCALE_HEIGHT, ATMOSPHERE_TOP, EARTH_RADIUS, OZONE_HALF_WIDTH,
                         OZONE_PEAK_ALTITUDE, RAYLEIGH_SCALE_HEIGHT)
from ..kernels import jit as _jit
from ..exp_numba import LIBM, choice, exp64, exp_in_place
from ..trig_numba import fma64
from . import sky

__all__ = ["sky_radiance", "matches_numpy"]

_R = EARTH_RADIUS
_TOP = EARTH_RADIUS + ATMOSPHERE_TOP
_H_R = RAYLEIGH_SCALE_HEIGHT
_H_A = AEROSOL_SCALE_HEIGHT
_PEAK = OZONE_PEAK_ALTITUDE
_HALF = OZONE_HALF_WIDTH
_ALBEDO = AEROSOL_ALBEDO


@_jit
def _positions(n):
    """The sample positions along a ray of n samples, as the reference's j = (i + ½)/n: j² and 2j/n."""
    j2 = np.empty(n)
    dj = np.empty(n)
    for i in range(n):
        j = (i + 0.5) / n
        j2[i] = j * j
        dj[i] = 2.0 * j / n
    return j2, dj


@_jit
def _scatter(mu_v, cos_g, sun_z, phase_r, phase_hg, tau, sun, n_view, n_sun, which, out):
    k_count = mu_v.size
    n_l = tau.shape[1]
    rr = _R * _R
    two_r = 2.0 * _R
    tt = _TOP * _TOP
    floor = -5.0 * _H_R
    r_pz = _R * sun_z
    jv2, dv = _positions(n_view)
    js2, ds_ = _positions(n_sun)
    h2 = np.empty(n_sun)
    w2 = np.empty(n_sun)
    e0 = np.empty(n_sun)
    e1 = np.empty(n_sun)
    oz = np.empty(n_sun)
    x = np.empty(n_l)
    acc = np.empty(n_l)
    for k in range(k_count):
        mu = mu_v[k]
        length = -_R * mu + math.sqrt(rr * mu * mu + tt - rr)
        cg = cos_g[k]
        ra_k = phase_r[k]
        ae_k = phase_hg[k]
        for lam in range(n_l):
            acc[lam] = 0.0
        cum0 = 0.0
        cum1 = 0.0
        cum2 = 0.0
        for i in range(n_view):
            s = length * jv2[i]
            ds = length * dv[i]
            r = math.sqrt(rr + two_r * mu * s + s * s)
            h = r - _R
            d0 = exp64(-h / _H_R, which) / _H_R * ds
            d1 = exp64(-h / _H_A, which) / _H_A * ds
            d2 = max(1.0 - abs(h - _PEAK) / _HALF, 0.0) / _HALF * ds
            cum0 += d0
            cum1 += d1
            cum2 += d2
            # the column towards the sun from this point (slant_columns)
            mu_s = (r_pz + s * cg) / r
            rs = _R + h
            ls = -rs * mu_s + math.sqrt(max(rs * rs * mu_s * mu_s + tt - rs * rs, 0.0))
            a = 2.0 * rs * mu_s
            rsq = rs * rs
            for q in range(n_sun):
                s2 = ls * js2[q]
                w2[q] = ls * ds_[q]
                hq = math.sqrt(max(rsq + a * s2 + s2 * s2, 0.0)) - _R
                hq = max(hq, floor)
                h2[q] = hq
                oz[q] = max(1.0 - abs(hq - _PEAK) / _HALF, 0.0) / _HALF * w2[q]
            for q in range(n_sun):
                e0[q] = -h2[q] / _H_R
                e1[q] = -h2[q] / _H_A
            exp_in_place(e0, n_sun, which)
            exp_in_place(e1, n_sun, which)
            for q in range(n_sun):
                e0[q] = e0[q] / _H_R * w2[q]
                e1[q] = e1[q] / _H_A * w2[q]
            c0 = 0.0
            c1 = 0.0
            c2 = 0.0
            for q in range(n_sun):
                c0 += e0[q]
                c1 += e1[q]
                c2 += oz[q]
            col0 = (cum0 - 0.5 * d0) + c0
            col1 = (cum1 - 0.5 * d1) + c1
            col2 = (cum2 - 0.5 * d2) + c2
            ra = d0 * ra_k
            ae = d1 * _ALBEDO * ae_k
            for lam in range(n_l):
                x[lam] = -fma64(col2, tau[2, lam], fma64(col1, tau[1, lam], col0 * tau[0, lam]))
            exp_in_place(x, n_l, which)
            for lam in range(n_l):
                acc[lam] += (ra * tau[0, lam] + ae * tau[1, lam]) * x[lam]
        for lam in range(n_l):
            out[k, lam] = sun[lam] * acc[lam]


def _which() -> int:
    """The ``exp`` the kernel takes: the one :func:`sunset.exp_numba.choice` found NumPy using, else the C library's."""
    w = choice()
    return LIBM if w is None else w


def _compiled(directions, sun_dir, n_view, n_sun):
    """The compiled integral, whatever the probe says (the tests call it directly)."""
    sp = sky.spectral_data()
    v = np.asarray(directions, dtype=float).reshape(-1, 3)
    p = np.asarray(sun_dir, dtype=float)
    mu_v = np.ascontiguousarray(np.clip(v[:, 2], 0.0, 1.0))
    cos_g = np.ascontiguousarray(np.clip(v @ p, -1.0, 1.0))
    out = np.empty((len(v), sp.tau.shape[1]))
    _scatter(mu_v, cos_g, float(p[2]), sky._phase_rayleigh(cos_g), sky._phase_hg(cos_g),
             np.ascontiguousarray(sp.tau), np.ascontiguousarray(sp.sun), int(n_view), int(n_sun), _which(), out)
    return out


_verdict: dict[str, bool] = {}


def matches_numpy() -> bool:
    """Whether the compiled integral gives the NumPy reference's bits in this process (checked once).

    The probe: the directions of the hemisphere :func:`sunset.model.sky.sky_dome` integrates over,
    with a sun high, low, at the horizon and below it.
    """
    if "ok" not in _verdict:
        dirs = sky._sphere()[0]
        ok = True
        for e in (0.9, 0.2, 0.01, -0.05):
            p = np.array([0.0, math.cos(e), math.sin(e)])
            want = sky.sky_radiance.reference(dirs, p, 16, 8)
            ok = ok and np.array_equal(want.view(np.uint8), _compiled(dirs, p, 16, 8).view(np.uint8))
        _verdict["ok"] = ok
    return _verdict["ok"]


def sky_radiance(directions, sun_dir, n_view=sky._N_VIEW, n_sun=sky._N_SUN, columns=None):
    """:func:`sunset.model.sky.sky_radiance` compiled.

    The NumPy reference runs instead where a ``columns`` is given, where
    :func:`matches_numpy` fails, and for a view ray of one point (``n_view``
    < 2: NumPy's matrix product takes another BLAS path for a single row).
    """
    if columns is not None or n_view < 2 or not matches_numpy():
        return sky.sky_radiance.reference(directions, sun_dir, n_view, n_sun, columns)
    return _compiled(directions, sun_dir, n_view, n_sun)
