"""The reflected rays, as a strip kernel: every sea pixel's ray of a strip of rows reflected, pierced and written back.

:func:`trace_sea_rays` reflects the direct ray of every sea pixel off the
wave normal (:func:`sunset.vector.pierce.reflect`), optionally a second time off
the crest ahead (:mod:`sunset.vector.crests`), folds the ray up (R_z → |R_z|, the
paper's rule for rays that would go under the sea) and pierces the islands'
cosine-free paraboloids (:mod:`sunset.vector.pierce`); what it meets fills the
frame's final fields. The per-ray work runs on compressed subsets
(:func:`~sunset.vector.pierce.gather`, :func:`~sunset.vector.pierce.scatter`), as the Cray's gather/scatter would.
The pipeline runs it over a frame's strips of rows (:func:`sunset.pipeline.frame.trace_reflections`).

Reflection modes
----------------
0
    Reflected rays go straight to the sky: no islands are pierced and no
    secondary reflection is looked for (a diagnostic; the cheapest mode).
1
    One reflection from the waves, each reflected R_z replaced by |R_z|, then
    the islands or the sky (Figure 5; Figure 4 is this mode on still water).
2
    Up to two reflections: secondary reflections off a parabolic cylinder
    fitted to the crest ahead, gathered and scattered (Figure 6); on a wind
    sea, off its tile's height field, the ray marched over it
    (:mod:`sunset.vector.windsea_crests`).
"""

from __future__ import annotations

import numpy as np

from ..constants import SEA, SKY
from ..errors import SunsetError
from ..kernels import twin
from .crests import secondary_reflections
from .frame import Frame
from .heightfield import WIND_REFUSED
from .pierce import gather, island_normal, pierce_islands, reflect, scatter

__all__ = ["trace_sea_rays", "sea_rays", "record_bounces"]


@twin("sunset.vector.reflect_numba")
def trace_sea_rays(scene, frame: Frame, reflections: int) -> Frame:
    """The reflected rays of a strip of rows (``frame``) with sea pixels, on a sea of trains: reflect, pierce, write back.

    :func:`sea_rays` with the crest cylinders' second reflections
    (:func:`sunset.vector.crests.secondary_reflections`). A wind sea is
    refused (:data:`~sunset.vector.heightfield.WIND_REFUSED`): its rays are
    :func:`sunset.vector.windsea_crests.wind_sea_rays`', chosen by the
    pipeline (:func:`sunset.pipeline.frame.sea_stage`).
    """
    if scene.sea.wind is not None:
        raise SunsetError(WIND_REFUSED)
    return sea_rays(scene, frame, reflections, lambda q, r: secondary_reflections(scene.sea, frame.t, q, r))


def sea_rays(scene, frame: Frame, reflections: int, second) -> Frame:
    """The reflected rays of a strip of rows, whatever the sea, with ``second`` its second reflections.

    Gather and reflect the sea pixels' rays; with two reflections,
    ``second(q, r)`` gives the rays that meet the sea again (their indices,
    the points where they meet it, their directions reflected there);
    |R_z|; pierce the islands and shade the island hits; scatter the final
    fields into the frame (in place) and return it.
    """
    sea_mask = frame.surface == SEA
    h = scene.camera.eye_height
    q = frame.point[sea_mask].astype(np.float64)
    d = frame.direction[sea_mask].astype(np.float64)
    n = frame.normal[sea_mask].astype(np.float64)
    r = reflect(d, n)
    r1 = r.copy()
    bounces = np.ones(len(q), np.uint8)
    idx = ray2 = None
    if reflections == 2:
        idx, point, ray2 = second(q, r)
        scatter(idx, point, q)
        scatter(idx, ray2, r)
        scatter(idx, 2, bounces)
    record_bounces(frame, np.flatnonzero(sea_mask), -np.sum(d * n, axis=-1), r1, idx, ray2)
    r[:, 2] = np.abs(r[:, 2])
    final = np.full(len(q), SKY, np.int8)
    part = np.zeros(len(q), np.int8)
    normal = np.full((len(q), 3), np.nan)
    if reflections >= 1 and scene.islands:
        dist, final, part = pierce_islands(scene.islands, h, q, r)
        for k, island in enumerate(scene.islands, start=1):
            idx, (qk, rk, tk, pk) = gather(final == k, q, r, dist, part)
            if len(idx):
                hit = qk + tk[:, None] * rk
                scatter(idx, island_normal(island, hit[:, 0], hit[:, 1], pk), normal)
    frame.bounces[sea_mask] = bounces
    frame.ray[sea_mask] = r
    frame.final_surface[sea_mask] = final
    frame.final_part[sea_mask] = part
    frame.final_normal[sea_mask] = normal
    return frame


def record_bounces(frame: Frame, flat, cos1, r1, idx=None, ray2=None) -> None:
    """Record each sea bounce in ``frame.incidence`` and ``frame.sea_rays``.

    For :mod:`sunset.light`.

    ``flat`` are the sea pixels' row-major indices, ``cos1`` = −D·N and ``r1``
    the first reflected rays there; ``idx`` (into ``flat``) and ``ray2`` the
    rays that reflect a second time. Since R₂ = R₁ − 2(R₁·N₂)N₂ with
    R₁·N₂ = −cos i₂, the second incidence cosine is |R₂ − R₁|/2. The 8-bit
    codes read none of this: a frame without these fields (None) records nothing.
    """
    if frame.incidence is None:
        return
    inc = frame.incidence.reshape(-1, 2)
    rays = frame.sea_rays.reshape(-1, 2, 3)
    inc[flat, 0] = cos1
    rays[flat, 0] = r1
    if idx is not None and len(idx):
        at = flat[idx]
        inc[at, 1] = 0.5 * np.linalg.norm(ray2 - r1[idx], axis=-1)
        rays[at, 1] = ray2
