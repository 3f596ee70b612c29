"""The sun's glitter on a rendered RGB picture of a wind sea, measured against Cox and Munk's prediction (issue 31).

Cox and Munk (1954) predict the glitter of a sea whose slopes are Gaussian
with their measured variances: at every point of a flat mean sea,

    L = ρ(ω) E_sun p(ζ) / (4 μ_v μ_h⁴),

ζ the slope that turns the eye's ray into the sun, μ_v, μ_h the cosines of the
ray and of that facet with the vertical (:func:`sunset.light.glitter.glitter_radiance`
with the normal (0, 0, 1)). The renderer draws a particular sea: the tile's
resolved waves, traced, and about each pixel's resolved normal the facets it
cannot resolve. :func:`measure_glitter` measures the glitter *on the picture*,
the radiance the sun puts into each sea pixel (the picture shaded, less the
same picture shaded with the sun's radiance 0: what depends on the sun's disk
alone; the light the sun puts into the water's body is not counted, as it
does not depend on the disk), and compares it with the prediction for the
same pixels, rays, sun and wind:

* with Cox and Munk's clean-surface variances for the wind at 12.5 m
  (:func:`sunset.model.coxmunk.cox_munk_clean`), their law;
* and with the wind sea's own total variances (the spectrum and its
  spreading up to the capillary cutoff), which the renderer aims at, so that
  what the law and the model disagree on is told apart from what the
  rendering adds.

Measured: the total (the glitter summed over the picture, in the picture's
radiance units), the profile down the picture (summed along each row) and
across it (down each column), and the extent, the angles below the horizon
and about the sun's azimuth between which the middle 90 % of the glitter
lies (the 5 % and 95 % points of each profile's cumulative sum).

The rows within ``below`` degrees of the horizon (1° by default) are left
out of the total and the extents and measured alone: there the flat sea's
formula grows as 1/μ_v without bound (the row nearest the horizon alone can
outweigh the rest of the picture, by how near its centre falls to it), while
on the picture a ray that grazes the sea sees only the faces of the waves
turned to the eye and the crests, which hide the rest (Cox and Munk's
formula leaves hiding out).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..errors import SunsetError, require_finite, require_range
from ..light.glitter import glitter_radiance, sun_irradiance
from ..light.render import frame_light
from ..light.shade import shade
from ..model.coxmunk import cox_munk_clean
from ..pipeline.rgb import trace_geometry

__all__ = ["measure_glitter", "extent"]

#: The share of the glitter inside the measured extent.
EXTENT_SHARE = 0.9


def extent(profile, coords) -> tuple[float, float]:
    """(lo, hi): the coordinates between which the middle EXTENT_SHARE of ``profile`` (≥ 0) lies, interpolated."""
    p = np.clip(np.asarray(profile, dtype=float), 0.0, None)
    c = np.asarray(coords, dtype=float)
    order = np.argsort(c)
    p, c = p[order], c[order]
    cum = np.cumsum(p)
    if cum[-1] <= 0:
        return math.nan, math.nan
    tail = 0.5 * (1.0 - EXTENT_SHARE)
    cum = np.concatenate([[0.0], cum / cum[-1]])
    edges = np.concatenate([[c[0] - 0.5 * (c[1] - c[0])], 0.5 * (c[1:] + c[:-1]), [c[-1] + 0.5 * (c[-1] - c[-2])]])
    return float(np.interp(tail, cum, edges)), float(np.interp(1.0 - tail, cum, edges))


def measure_glitter(scene, t: float = 0.0, hours: float = 0.35, below: float = 1.0) -> dict:
    """The glitter on the RGB picture of a wind-sea ``scene`` against Cox and Munk's prediction.

    Returns
    -------
    dict
        ``image``, ``cox_munk``, ``model``: the glitter's luminance Y per pixel
        (H, W), on the picture and predicted (0 off the sea); ``rows``,
        ``columns``: each one's profile down and across (dicts of (H,) and (W,)
        arrays, same keys); ``elevation`` (H,) and ``azimuth`` (W,): each row's
        angle below the horizon and each column's azimuth from the sun's,
        degrees; ``total``: each one's sum over the rows ``below`` degrees
        or more below the horizon; ``horizon``: over the rows above them;
        ``vertical``, ``horizontal``: each one's extent (lo, hi), degrees, of
        the same rows as ``total``; ``variances``: the (upwind, crosswind)
        slope variances of the law, of the model and of the facets.
    """
    require_finite("t", t)
    require_finite("hours", hours)
    require_range("below", below, 0.0, 45.0, "degrees")
    wind = scene.sea.wind
    if wind is None:
        raise SunsetError("scene: the glitter is measured on a sea given by its wind ([sea.wind])")
    geometry = trace_geometry(scene, float(t), 1)
    light = frame_light(scene, float(t), float(hours))
    if light.sun_dir[2] <= 0:
        raise SunsetError(f"hours: the sun is below the horizon {hours!r} hours before sunset: no glitter to measure")
    full = shade(geometry, light)[..., 1].astype(float)
    dark = shade(geometry, replace(light, sun_xyz=np.zeros(3)))[..., 1].astype(float)
    gl = geometry.glitter
    shape = geometry.shape
    image = np.zeros(shape)
    image.reshape(-1)[gl.index] = (full - dark).reshape(-1)[gl.index]
    law = cox_munk_clean(min(wind.wind.u12_5, 14.0))
    variances = {"cox_munk": (float(law["upwind"][0]), float(law["crosswind"][0])), "model": wind.total_slopes(),
                 "facets": (gl.var_upwind, gl.var_crosswind)}
    e_sun = sun_irradiance(light.sun_xyz, light.delta)
    flat = np.broadcast_to(np.array([0.0, 0.0, 1.0], np.float32), gl.view.shape)
    out = {"image": image}
    for name in ("cox_munk", "model"):
        pred = np.zeros(shape)
        pred.reshape(-1)[gl.index] = glitter_radiance(gl.view, flat, light.sun_dir, e_sun, *variances[name],
                                                      wind.direction, gl.n)[:, 1]
        out[name] = pred
    cam = scene.camera
    elevation = -np.degrees(np.arctan(cam.zy_centres()))
    azimuth = np.degrees(np.arctan(cam.s_centres())) - math.degrees(math.atan2(light.sun_dir[0], light.sun_dir[1]))
    names = ("image", "cox_munk", "model")
    low = elevation >= below
    out.update({"rows": {k: out[k].sum(axis=1) for k in names}, "columns": {k: out[k][low].sum(axis=0) for k in names},
                "elevation": elevation, "azimuth": azimuth, "variances": variances,
                "total": {k: float(out[k][low].sum()) for k in names},
                "horizon": {k: float(out[k][~low].sum()) for k in names}})
    out["vertical"] = {k: extent(out["rows"][k][low], elevation[low]) for k in names}
    out["horizontal"] = {k: extent(out["columns"][k], azimuth) for k in names}
    return out
