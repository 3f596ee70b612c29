"""Deferred shading: a stored :class:`~sunset.light.geometry.Geometry` and the light of an hour in, radiance out.

Per pixel, with the path's throughput τ = Π R_k (the Fresnel reflectances of
its sea bounces) and the water seen at each bounce,

    L = τ L_final + Σ_k τ_(k−1) (1 − R_k)/n² L_u(u_k),

L_final the sky (plus the sun's disk where the final ray falls in it), a
cloud (its light by depth, when the light has clouds) or the island the path
ends on, and L_u the light scattered up in the sea along the
reversed refracted ray u_k (:mod:`sunset.light.water`):

    L_u(u) = ω E'_sun p(ψ)/(μ'_sun + u_z) + ω E'_sky (1/4π)/(μ̄ + u_z),

both ω E' vectors in XYZ per hour (:class:`~sunset.light.lighting.Lighting`).
Everything is float32 XYZ radiance in the sky model's units. The per-pixel
loops are the kernels of :mod:`sunset.light.kernel`, the sky's and the islands'
run on strips of their lists on the threads (each entry computed alone, so
the same bytes for any number of threads); the extra sky layers and light
sources of a Lighting are applied between them. A wind sea's geometry carries
its :class:`~sunset.light.glitter.Glitter`: the sun's disk is left out of its
sea pixels' mirror reflections and the facets' glitter added instead
(:mod:`sunset.light.glitter`).
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import STRIP_PIXELS
from ..kernels import run_strips, strips
from .geometry import Geometry
from .glitter import glitter_radiance, sun_irradiance
from .kernel import combine, island_pixels, sky_pixels
from .lighting import SKY_REFINE, Lighting

__all__ = ["shade"]


def shade(geometry: Geometry, light: Lighting) -> np.ndarray:
    """Radiance XYZ (H, W, 3) float32 of a stored frame under ``light``."""
    g = geometry
    sky = np.empty((len(g.sky_index), 3), np.float32)
    col_scale = (light.sky_table.shape[1] - 1) * SKY_REFINE[1]

    def sky_part(a: int, b: int) -> None:
        sky[a:b] = sky_pixels(g.sky_r0[a:b], g.sky_fr[a:b], g.sky_azimuth[a:b], g.sky_dir[a:b], light.sky_linear,
                              light.sun_azimuth, col_scale, light.sun_dir, math.cos(light.delta), light.sun_xyz)

    run_strips(sky_part, strips(len(sky), STRIP_PIXELS))
    gl = g.glitter
    if gl is not None:      # a wind sea: the sun's light off its facets (below), not its disk in the sea's mirror
        sea_path = np.zeros(len(g.final_dir), bool)
        sea_path[gl.index] = True
        sel = np.flatnonzero(sea_path[g.sky_index])
        if len(sel):
            sky[sel] = sky_pixels(g.sky_r0[sel], g.sky_fr[sel], g.sky_azimuth[sel], g.sky_dir[sel], light.sky_linear,
                                  light.sun_azimuth, col_scale, light.sun_dir, math.cos(light.delta), np.zeros(3))
    for layer in light.extra_sky:
        sky = np.asarray(layer(g.sky_dir, sky), np.float32)
    if g.sky_cloud is not None and light.cloud_xyz is not None:
        on = np.isfinite(g.sky_cloud)          # a cloud in front of the sky (and of the sun: its glitter goes out)
        if np.any(on):
            sky = np.array(sky, np.float32)
            sky[on] = light.cloud(g.sky_cloud[on])
    direct, table = light.island_tables()
    isl_normal = g.island_normal
    isl_part = g.final_kind[g.island_index]
    island = np.empty((len(isl_part), 3), np.float32)

    def island_part(a: int, b: int) -> None:
        island[a:b] = island_pixels(isl_normal[a:b], isl_part[a:b], g.island_g[a:b, 0], g.island_g[a:b, 1],
                                    g.island_f[a:b, 0], g.island_f[a:b, 1], light.sun_dir, direct, table)

    run_strips(island_part, strips(len(island), STRIP_PIXELS))
    for source in light.extra_irradiance:
        island = np.asarray(island + source(g.island_point, isl_normal, isl_part), np.float32)
    out = combine(g.final_dir.shape[0], g.throughput, g.sky_index, sky, g.island_index, island, g.water_starts,
                  g.water_index, g.water_up, g.water_mu, g.water_weight, g.water_sky, light.beam, -light.beam[2],
                  light.water_sun, light.water_sky)
    if gl is not None and len(gl.index):
        out[gl.index] += glitter_radiance(gl.view, gl.normal, light.sun_dir, sun_irradiance(light.sun_xyz, light.delta),
                                          gl.var_upwind, gl.var_crosswind, gl.wind_direction, gl.n)
    return out.reshape(g.shape + (3,))
