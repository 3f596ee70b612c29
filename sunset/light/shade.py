"""Deferred shading: a stored :class:`~sunset.light.geometry.Geometry` and the light of an hour in, radiance out.

Per pixel, with the path's throughput τ = Π R_k (the Fresnel reflectances of
its sea bounces) and the water seen at each bounce,

    L = τ L_final + Σ_k τ_(k−1) (1 − R_k)/n² L_u(u_k),

L_final the sky (plus the sun's disk where the final ray falls in it) or the
island the path ends on, and L_u the light scattered up in the sea along the
reversed refracted ray u_k (:mod:`sunset.light.water`):

    L_u(u) = ω E'_sun p(ψ)/(μ'_sun + u_z) + ω E'_sky (1/4π)/(μ̄ + u_z),

both ω E' vectors in XYZ per hour (:class:`~sunset.light.lighting.Lighting`).
Everything is float32 XYZ radiance in the sky model's units.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import SKY
from . import water
from .geometry import Geometry
from .lighting import Lighting, sky_column

__all__ = ["shade"]


def shade(geometry: Geometry, light: Lighting) -> np.ndarray:
    """Radiance XYZ (H, W, 3) float32 of a stored frame under ``light``."""
    g = geometry
    out = np.zeros((g.final_dir.shape[0], 3), np.float32)
    # the sky and the sun along the final rays that reach the sky
    si = g.sky_index
    if len(si):
        sky = light.sky_at(g.sky_rows, sky_column(g.sky_azimuth, light.sun_azimuth))
        fd = g.final_dir[si]
        near = fd @ light.sun_dir.astype(np.float32) > np.float32(math.cos(light.delta))
        if np.any(near):
            sky[near] += light.sun(fd[near])
        for layer in light.extra_sky:
            sky = layer(fd, sky)
        out[si] = sky
    # the islands the final rays end on
    isl = np.flatnonzero(g.final_kind > 0)
    if len(isl):
        out[isl] = light.island(g.final_normal[isl], g.final_kind[isl])
    out *= g.throughput[:, None]
    # the water seen at each bounce
    mu_beam = np.float32(-light.beam[2])
    mu_bar = np.float32(water.diffuse_mean_cosine(light.n))
    beam = light.beam.astype(np.float32)
    ws = light.water_sun.astype(np.float32)
    wk = light.water_sky.astype(np.float32)
    for layer in g.water:
        up = layer.up
        mu = np.maximum(up[:, 2], np.float32(0))
        f_sun = water.upwelling(mu, mu_beam, up @ beam) * layer.weight
        f_sky = (np.float32(1 / (4 * math.pi)) / (mu_bar + mu)) * layer.weight
        out[layer.index] += f_sun[:, None] * ws + f_sky[:, None] * wk
    return out.reshape(g.shape + (3,))
