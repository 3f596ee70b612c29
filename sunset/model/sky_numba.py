"""Numba twin of :func:`sunset.model.sky.sky_radiance`: the sky's single-scattering integral, compiled.

The NumPy reference builds, for K view rays × n_view points × n_sun points
towards the sun, arrays of heights, densities and their products, and then
the (K, n_view, n_λ) transmittances: hundreds of megabytes of memory
traffic for one film frame's colour tables. This twin walks the same points
one at a time, with the same formulas, and keeps nothing but a few sums:

* the view ray's cumulative columns, added from the ray's start;
* each point's column towards the sun (:func:`sunset.model.sky.slant_columns`)
  summed from the point outwards;
* each transmittance exp(−τ·c) with the C library's ``exp`` (``math.exp``).

It is not the reference's bits: NumPy's ``exp`` and matrix product choose
their own kernels by the processor, the twin does not follow them. The two
agree within :data:`RADIANCE_RTOL` (relative, measured; tested in
``tests/model/test_sky_numba.py``), and the colour tables made from either
within :data:`TABLE_STEPS` and :data:`TABLE_SHARE`; each gives the same bytes
on every run.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import (AEROSOL_ALBEDO, AEROSOL_SCALE_HEIGHT, ATMOSPHERE_TOP, EARTH_RADIUS, OZONE_HALF_WIDTH,
                         OZONE_PEAK_ALTITUDE, RAYLEIGH_SCALE_HEIGHT)
from ..kernels import jit as _jit
from . import sky

__all__ = ["sky_radiance", "RADIANCE_RTOL", "RADIANCE_FLOOR", "TABLE_STEPS", "TABLE_SHARE"]

#: The largest relative difference allowed between the two paths' radiances, |a − b| ≤ RTOL · max(a, FLOOR).
#: Measured: 1.4e-14 over 9.6 million values (414 suns from 17° below the horizon to the zenith, 459
#: directions each), the largest where the sun is 5° below the horizon: there a ray's optical depth
#: towards the sun is hundreds, and a last-bit difference in it is multiplied by as much in exp(−τ).
#: Chosen about twice that, for other processors' ``exp`` and matrix product.
RADIANCE_RTOL = 3e-14
#: Radiances below this (per unit E₀ per steradian, 28 orders of magnitude darker than the day's sky,
#: where both paths' sums are ill-conditioned) are compared as if they were this large.
RADIANCE_FLOOR = 1e-30
#: The colour tables' 8-bit entries of the two paths may differ by this many steps ...
TABLE_STEPS = 1
#: ... on at most this share of the entries (measured: none of 202,752 over the packaged scenes and 44 hours).
TABLE_SHARE = 1e-4

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
def _ozone(h):
    return max(1.0 - abs(h - _PEAK) / _HALF, 0.0) / _HALF


@_jit
def _scatter(mu_v, cos_g, sun_z, phase_r, phase_hg, tau, sun, n_view, n_sun, out):
    n_l = tau.shape[1]
    rr = _R * _R
    tt = _TOP * _TOP
    floor = -5.0 * _H_R
    jv2, dv = _positions(n_view)
    js2, ds_ = _positions(n_sun)
    acc = np.empty(n_l)
    for k in range(mu_v.size):
        mu = mu_v[k]
        cg = cos_g[k]
        length = -_R * mu + math.sqrt(rr * mu * mu + tt - rr)
        acc[:] = 0.0
        cum0 = 0.0
        cum1 = 0.0
        cum2 = 0.0
        for i in range(n_view):
            s = length * jv2[i]
            ds = length * dv[i]
            r = math.sqrt(rr + 2.0 * _R * mu * s + s * s)
            h = r - _R
            d0 = math.exp(-h / _H_R) / _H_R * ds
            d1 = math.exp(-h / _H_A) / _H_A * ds
            d2 = _ozone(h) * ds
            cum0 += d0
            cum1 += d1
            cum2 += d2
            # the column towards the sun from this point (slant_columns)
            mu_s = (_R * sun_z + s * cg) / r
            ls = -r * mu_s + math.sqrt(max(r * r * mu_s * mu_s + tt - r * r, 0.0))
            c0 = 0.0
            c1 = 0.0
            c2 = 0.0
            for q in range(n_sun):
                s2 = ls * js2[q]
                w = ls * ds_[q]
                hq = max(math.sqrt(max(r * r + 2.0 * r * mu_s * s2 + s2 * s2, 0.0)) - _R, floor)
                c0 += math.exp(-hq / _H_R) / _H_R * w
                c1 += math.exp(-hq / _H_A) / _H_A * w
                c2 += _ozone(hq) * w
            col0 = cum0 - 0.5 * d0 + c0
            col1 = cum1 - 0.5 * d1 + c1
            col2 = cum2 - 0.5 * d2 + c2
            ra = d0 * phase_r[k]
            ae = d1 * _ALBEDO * phase_hg[k]
            for lam in range(n_l):
                t = math.exp(-(col0 * tau[0, lam] + col1 * tau[1, lam] + col2 * tau[2, lam]))
                acc[lam] += (ra * tau[0, lam] + ae * tau[1, lam]) * t
        for lam in range(n_l):
            out[k, lam] = sun[lam] * acc[lam]


def sky_radiance(directions, sun_dir, n_view=sky._N_VIEW, n_sun=sky._N_SUN, columns=None):
    """:func:`sunset.model.sky.sky_radiance` compiled; the NumPy reference runs where a ``columns`` is given."""
    if columns is not None:
        return sky.sky_radiance.reference(directions, sun_dir, n_view, n_sun, columns)
    sp = sky.spectral_data()
    v = np.asarray(directions, dtype=float).reshape(-1, 3)
    p = np.asarray(sun_dir, dtype=float)
    mu_v = np.ascontiguousarray(np.clip(v[:, 2], 0.0, 1.0))
    cos_g = np.ascontiguousarray(np.clip(v @ p, -1.0, 1.0))       # the view rays' geometry as the reference's
    out = np.empty((len(v), sp.tau.shape[1]))
    _scatter(mu_v, cos_g, float(p[2]), sky._phase_rayleigh(cos_g), sky._phase_hg(cos_g),
             np.ascontiguousarray(sp.tau), np.ascontiguousarray(sp.sun), int(n_view), int(n_sun), out)
    return out
