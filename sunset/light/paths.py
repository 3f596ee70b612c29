"""The light paths of a strip of pixels: the kernel behind :meth:`sunset.light.geometry.Geometry.from_frame`.

For each pixel of a strip (flat arrays of a frame's rows) :func:`trace_paths`
works out what its path does, without the light (see
:mod:`sunset.light.geometry`):

* the final kind: −1 sky (a cloud counts as sky), an island part 1–3, or a
  post, shaded as the cliff (2);
* the final normal, NaN made 0;
* at each sea bounce k (the eye's ray D on the wave's normal N₁; R₁ on
  N₂ = (R₂ − R₁)/|R₂ − R₁|; and the fold of a ray still heading down,
  off the mean surface N = (0, 0, 1)) the direction u_k of the light that
  comes up out of the water towards the eye, the refracted ray reversed
  (Snell's law in vector form, :func:`sunset.light.fresnel.refract`), and
  the weight τ_(k−1) (1 − R_k)/n²;
* the throughput τ = Π R_k, R_k the unpolarised Fresnel reflectance.

Precision: the directions are float32, as the frame stores them; the
reflectance is :func:`sunset.light.fresnel.reflectance` in float64 of the
float32 cosine, rounded to float32 once. The twin in
:mod:`sunset.light.paths_numba` computes the same formulas one pixel at a
time; the two agree within :data:`~sunset.light.paths_numba.PATHS_RTOL`
(measured and tested), and each gives the same bytes on every run.
"""

from __future__ import annotations

import numpy as np

from ..constants import CLOUD, PART_CLIFF, POST, SEA, SKY
from ..kernels import twin
from .fresnel import reflectance

__all__ = ["trace_paths", "lookups"]

_f = np.float32


def _clip32(x):
    return np.minimum(np.maximum(x, _f(0)), _f(1))


def _layer(incident, normal, cos_i, before, n: float):
    """The water seen at one bounce: up (M, 3), weight (M,) and R (M,), float32.

    ``up`` is the refracted ray reversed, ``weight`` = before × (1 − R)/n².
    """
    n32 = _f(n)
    c = _clip32(cos_i)
    ct = np.sqrt(_f(1) - (_f(1) - c * c) / (n32 * n32))
    k = c / n32 - ct
    t0 = incident[:, 0] / n32 + k * normal[:, 0]
    t1 = incident[:, 1] / n32 + k * normal[:, 1]
    t2 = incident[:, 2] / n32 + k * normal[:, 2]
    length = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    up = np.stack([-t0 / length, -t1 / length, -t2 / length], axis=-1)
    r = reflectance(np.asarray(cos_i, np.float64), n)
    weight = before * ((1.0 - r) / (n * n)).astype(np.float32)
    return up, weight, r.astype(np.float32)


@twin("sunset.light.paths_numba")
def trace_paths(surface, final_surface, final_part, final_normal, direction, normal, incidence, sea_rays,
                n: float):
    """The paths of P pixels (flat arrays of a strip of a frame).

    Parameters
    ----------
    surface, final_surface, final_part : (P,) int8
    final_normal, direction, normal : (P, 3) float32
    incidence : (P, 2) float32
    sea_rays : (P, 2, 3) float32
        The frame's fields (:class:`~sunset.vector.frame.Frame`), flattened.
    n : float
        The water's refractive index.

    Returns
    -------
    kind : (P,) int8
    final_normal : (P, 3) float32, NaN made 0
    throughput : (P,) float32
    layers : tuple of three (index (M,) intp, up (M, 3) float32, weight (M,) float32)
        The water of the first bounce, the second and the fold; ``index``
        ascending within each.
    """
    kind = np.where((final_surface == SKY) | (final_surface == CLOUD), SKY,
                    np.where(final_surface == POST, PART_CLIFF, final_part)).astype(np.int8)
    nrm = np.where(np.isnan(final_normal), _f(0), final_normal).astype(np.float32)
    throughput = np.ones(len(surface), np.float32)
    sea = np.flatnonzero(surface == SEA)
    inc = incidence[sea]
    rays = sea_rays[sea]
    # bounce 1: the eye's ray D on the wave's normal N1
    up1, w1, r1 = _layer(direction[sea], normal[sea], inc[:, 0], np.ones(len(sea), np.float32), n)
    t_sea = r1
    # bounce 2: R1 on N2 = (R2 - R1)/|R2 - R1|
    two = np.isfinite(inc[:, 1])
    a, b = rays[two, 0], rays[two, 1]
    d0, d1, d2 = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1], b[:, 2] - a[:, 2]
    length = np.maximum(np.sqrt(d0 * d0 + d1 * d1 + d2 * d2), _f(1e-30))
    n2 = np.stack([d0 / length, d1 / length, d2 / length], axis=-1)
    up2, w2, r2 = _layer(a, n2, inc[two, 1], t_sea[two], n)
    t_sea[two] = t_sea[two] * r2
    # the fold: a ray still heading down reflects off the mean surface
    last = np.where(two[:, None], rays[:, 1], rays[:, 0])
    down = last[:, 2] < _f(0)
    ld = last[down]
    flat = np.zeros(ld.shape, np.float32)
    flat[:, 2] = 1
    up3, w3, r3 = _layer(ld, flat, -ld[:, 2], t_sea[down], n)
    t_sea[down] = t_sea[down] * r3
    throughput[sea] = t_sea
    return kind, nrm, throughput, ((sea, up1, w1), (sea[two], up2, w2), (sea[down], up3, w3))


@twin("sunset.light.paths_numba")
def lookups(ray, final_surface, bounces, point, kind, normal, offset: int, depth=None) -> dict:
    """A strip's sky and island lists: which pixels, and where their rays and normals fall in the hour's tables.

    ``kind`` and ``normal`` are :func:`trace_paths`' ; the other arrays the
    strip's frame fields, flattened; ``offset`` the strip's first pixel. The
    twin compacts the lists in one compiled pass and leaves the rows' arcsine
    and the arctangent to NumPy.
    """
    from .lighting import NORMAL_GRID, SKY_REFINE, SKY_ROWS, sky_row

    sky_local = np.flatnonzero(kind == SKY)
    fd = ray[sky_local]
    r_max = (SKY_ROWS - 1) * SKY_REFINE[0]
    rows = np.clip(sky_row(fd[:, 2]) * SKY_REFINE[0], 0, r_max)
    r0 = np.minimum(rows.astype(np.int32), r_max - 1)
    isl_local = np.flatnonzero(kind > 0)
    g = (np.clip(normal[isl_local, :2].astype(np.float64), -1, 1) + 1.0) * (0.5 * (NORMAL_GRID - 1))
    g0 = np.minimum(g.astype(np.int32), NORMAL_GRID - 2)
    direct_hit = bounces[isl_local] == 0
    out = {"sky_index": sky_local + offset, "sky_dir": fd, "sky_r0": r0,
           "sky_fr": (rows - r0).astype(np.float32),
           "sky_azimuth": np.arctan2(fd[:, 1], fd[:, 0]), "island_index": isl_local + offset,
           "island_normal": normal[isl_local], "island_g": g0,
           "island_f": (g - g0).astype(np.float32),
           "island_point": np.where(direct_hit[:, None], point[isl_local], np.nan).astype(np.float32)}
    if depth is not None:
        out["sky_cloud"] = np.where(final_surface[sky_local] == CLOUD, depth[sky_local],
                                    np.nan).astype(np.float32)
    return out
