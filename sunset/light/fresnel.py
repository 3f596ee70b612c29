"""Fresnel's law at the sea surface: how much light the water reflects, how much it lets in.

The paper's *Directions for the Future* begins with it: a glancing ray is
almost wholly reflected, a steep one is largely refracted, so the fronts of
the waves, seen steeply, should take the colour of the water, not of the sky.

For a flat interface from air (index 1) into water (index n), with angle of
incidence i and angle of refraction t, sin t = sin i / n (Snell), the
amplitude ratios of the two polarisations give the reflectances (Born & Wolf,
*Principles of Optics*, §1.5)

    R_s = ((cos i − n cos t) / (cos i + n cos t))²,
    R_p = ((n cos i − cos t) / (n cos i + cos t))²,

and for unpolarised light (sunlight, and skylight to a good approximation)
R = (R_s + R_p)/2. Energy is conserved at the interface: the transmitted
fraction is T = 1 − R. The closed forms the tests check:

* normal incidence: R = ((n − 1)/(n + 1))², 2.1 % for n = 1.34;
* Brewster's angle tan i_B = n: R_p = 0 and R_s = ((n² − 1)/(n² + 1))²;
* grazing incidence i → 90°: R → 1.

Seen from below, a ray leaving the water at angle t to the normal has the same
R and T as the air ray at i (reciprocity), so the light scattered up out of
the sea is let through with the factor 1 − R(i) of the eye's ray.
"""

from __future__ import annotations

import numpy as np

from ..constants import WATER_REFRACTIVE_INDEX

__all__ = ["fresnel", "reflectance", "refract", "brewster_angle"]


def fresnel(cos_i, n: float = WATER_REFRACTIVE_INDEX):
    """R_s, R_p and R = (R_s + R_p)/2 (unpolarised), air into a medium of index n.

    Parameters
    ----------
    cos_i : array_like
        Cosine of the angle of incidence, clipped to [0, 1] (0: grazing, 1: normal).
    n : float
        Refractive index of the water relative to air (> 1).

    Returns
    -------
    (R_s, R_p, R) : ndarrays of the shape of ``cos_i``
    """
    c = np.clip(np.asarray(cos_i, dtype=float), 0.0, 1.0)
    ct = np.sqrt(1.0 - (1.0 - c * c) / (n * n))
    rs = ((c - n * ct) / (c + n * ct)) ** 2
    rp = ((n * c - ct) / (n * c + ct)) ** 2
    return rs, rp, 0.5 * (rs + rp)


def reflectance(cos_i, n: float = WATER_REFRACTIVE_INDEX) -> np.ndarray:
    """Unpolarised Fresnel reflectance R(cos i); the transmittance is 1 − R."""
    return fresnel(cos_i, n)[2]


def brewster_angle(n: float = WATER_REFRACTIVE_INDEX) -> float:
    """Brewster's angle arctan(n), radians: R_p = 0 there."""
    return float(np.arctan(n))


def refract(d, normal, cos_i, n: float = WATER_REFRACTIVE_INDEX) -> np.ndarray:
    """The refracted direction t of rays ``d`` entering water through a surface with unit ``normal``.

    t = d/n + (cos i / n − cos t) N with cos i = −d·N and cos t = √(1 − (1 − cos² i)/n²)
    (Snell's law in vector form, Glassner 1989): a unit vector pointing into
    the water, at angle t from −N.

    Parameters
    ----------
    d, normal : array_like (..., 3)
        Unit incident directions and unit normals (pointing out of the water).
    cos_i : array_like (...)
        −d·N, given because the caller usually has it already.
    """
    d = np.asarray(d)
    normal = np.asarray(normal)
    c = np.clip(np.asarray(cos_i), 0.0, 1.0)
    ct = np.sqrt(1.0 - (1.0 - c * c) / (n * n))
    return d / n + ((c / n - ct)[..., None]) * normal
