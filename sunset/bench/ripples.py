"""The ripples of light (issue 30, :mod:`sunset.light.caustics`), timed and weighed for ``make bench``.

``measure_ripples``: one texture of the post in the swell by beams (the
figure's settings) and by as many photons as the figure's comparison; the
light of a frame of Carla's Island at the paper's size
(:func:`sunset.light.render.frame_light`: what every RGB frame and film frame
computes), with its three shore textures (reflected light alone, at their
finest) and without, and the light of a frame of the post in the swell (its
post's texture as the film traces it); the bytes of each texture.
``measure_convergence`` (``python -m sunset.bench --measure
ripples-convergence``, about five minutes): the beams against 10⁸ photons
counted in their texels, the photons in sixteen independent parts so that
their own noise is measured beside the difference; and each mesh against the
next finer one, reflected and refracted light, which has no noise to hide the
beams' order of convergence: on the whole texture, with beams halved at a
glance or everywhere, and away from what keeps that order under 2
(:class:`NearPost`).
"""

from __future__ import annotations

import statistics
import time

import numpy as np

__all__ = ["measure_ripples", "measure_convergence", "rows", "format_rows", "CONVERGENCE_PHOTONS",
           "CONVERGENCE_CELLS", "NearPost", "near_textures", "self_orders", "NEAR_REACH", "NEAR_LEAST_COSINE",
           "NEAR_CELLS", "silhouette_columns", "SILHOUETTE_REACH"]

#: Photons of the convergence check (in independent parts, each within RIPPLE_MAX_RAYS) and the beams' cells set
#: against them, metres.
CONVERGENCE_PHOTONS = 10 ** 8
CONVERGENCE_PARTS = 16
#: The beams are also traced with this many halvings of those that land at a glance.
CONVERGENCE_REFINE = 3
CONVERGENCE_CELLS = (0.08, 0.04, 0.02, 0.01)
#: Texels up the post in the convergence check.
CONVERGENCE_TEXELS = 32
#: The same check away from what keeps the order under 2 (:class:`NearPost`): water within NEAR_REACH metres of
#: the post's axis, light meeting the post at a cosine of incidence of at least NEAR_LEAST_COSINE, in cells of
#: NEAR_CELLS metres.
NEAR_REACH = 4.0
NEAR_LEAST_COSINE = 0.3
NEAR_CELLS = (0.04, 0.02, 0.01, 0.005)
#: The texture's columns by the post's silhouettes: lit columns within this many columns of an unlit one.
SILHOUETTE_REACH = 2


class NearPost:
    """A post's receiver (:class:`sunset.light.postrays.PostReceiver`) cut down to what a mesh of centimetres
    resolves: its patch shortened to ``reach`` metres towards the sun (and narrowed in proportion), and the light
    that would meet the post at a cosine of incidence under ``least`` booked as passing it.

    Two things keep the full texture's order under 2 (chapter 13). At the post's silhouette the landing
    azimuth moves as the square root of the distance to it, which a straight-edged beam cannot follow: the
    error of the beams near it falls as h^1.5. And from far water the post is a small target: a ray's
    sideways turn θ (twice the slope across, which changes within a quarter of a ripple) times the distance s
    sweeps it across the post's width 2ρ within bands 2ρ/(s·|∇θ|) across, a few cells of centimetres, over
    each of which the landing point sweeps the post's lit half: meshes of centimetres are not yet in the range
    where the order shows. The status boundary ``least`` makes is a smooth curve on the water, which the
    beams' cuts follow to O(h²).
    """

    def __init__(self, receiver, reach: float, least: float):
        import copy

        self.__dict__.update(copy.copy(receiver).__dict__)
        self._receiver, self.least = receiver, float(least)
        length = min(receiver.L, float(reach))
        post = receiver.post
        self.W = post.radius + (receiver.W - post.radius) * length / receiver.L
        self.L = length
        from ..light.postrays import GEOMETRY

        self.geo = receiver.geo.copy()
        for name in ("L", "W"):
            self.geo[GEOMETRY.index(name)] = getattr(self, name)
        for name in ("dark_names", "reflected_names", "refracted_names", "reflected_clipped", "refracted_clipped"):
            setattr(self, name, getattr(type(receiver), name))

    @property
    def area(self) -> float:
        return 2.0 * self.W * self.L

    def evaluate(self, a, b):
        from ..light.caustics import LIT
        from ..light.postrays import PostReceiver

        nodes = PostReceiver.evaluate(self, a, b)
        drop = (nodes.status >= LIT) & (nodes.glance < self.least)
        nodes.status = np.where(drop, LIT + 11, nodes.status)
        for name in ("ur", "vr", "ut", "vt"):
            getattr(nodes, name)[drop] = np.nan
        nodes.path[drop], nodes.glance[drop] = 0.0, 1.0
        return nodes


def near_textures(scene, hours: float, cells, texels: int = CONVERGENCE_TEXELS, reach: float = NEAR_REACH,
                  least: float = NEAR_LEAST_COSINE, t: float = 0.0) -> list:
    """The (reflected, refracted mean over λ) textures of :class:`NearPost` of ``scene``'s first post, by beams of
    each of ``cells`` metres (no refinement)."""
    import math

    from ..light.caustics import trace_beams
    from ..light.postrays import PostReceiver

    near = NearPost(PostReceiver(scene, 0, t, hours, texels), reach, least)
    out = []
    for cell in cells:
        books = trace_beams(near, max(1, math.ceil(near.L / cell)), max(1, math.ceil(2 * near.W / cell)))
        out.append((books.reflected, books.refracted.mean(axis=-1)))
    return out


def silhouette_columns(texture) -> np.ndarray:
    """Which columns (n_φ,) of a post's ``texture`` (n_z, n_φ) lie by its silhouettes: lit ones within
    :data:`SILHOUETTE_REACH` columns (around the post) of a column with no light at all."""
    dark = ~np.any(texture > 0, axis=0)
    near = np.zeros_like(dark)
    for k in range(1, SILHOUETTE_REACH + 1):
        near |= np.roll(dark, k) | np.roll(dark, -k)
    return near & ~dark


def self_orders(textures, which: int) -> dict:
    """Each texture against the next finer one (texture ``which`` of each pair): the rms (L2) and mean absolute
    (L1) differences, relative to the finer texture's rms and mean, and the order of each halving."""
    import math

    out = {}
    for norm, f in (("L2", lambda x: float(np.sqrt(np.mean(x ** 2)))), ("L1", lambda x: float(np.mean(np.abs(x))))):
        e = [f(a[which] - b[which]) / f(b[which]) for a, b in zip(textures[:-1], textures[1:])]
        out[norm] = e
        out[norm + "_order"] = [math.log2(x / y) for x, y in zip(e[:-1], e[1:])]
    return out


def _runs(fn, repeats: int) -> list[float]:
    fn()                                     # warm: the compiled kernels load once
    out = []
    for _ in range(repeats):
        start = time.process_time()
        fn()
        out.append(time.process_time() - start)
    return out


def measure_ripples(width: int, height: int, repeats: int) -> dict:
    """CPU seconds of the textures and of a frame's light, and the bytes of each texture (``bytes``)."""
    from ..figures.future import RIPPLE_CELL, RIPPLE_HOURS, RIPPLE_RAYS, RIPPLE_TEXELS
    from ..constants import RGB_LIGHT_BYTES
    from ..light.render import frame_light
    from ..light.ripples import trace_ripples
    from ..model.scene import load_named_scene
    from .memory import _traced_peak

    # Carla's Island at the paper's size: its shore textures at their finest (light/shore.py's frame_texels)
    swell, carla = load_named_scene("post-in-the-swell"), load_named_scene("carlas-island")
    size = f"{carla.camera.width}x{carla.camera.height}"
    made = {}

    def post(method):
        made[method] = trace_ripples(swell, 0, 0.0, RIPPLE_HOURS, method=method, cell=RIPPLE_CELL, rays=RIPPLE_RAYS,
                                     texels=RIPPLE_TEXELS)

    def light(shore):
        made[shore] = frame_light(carla, 0.0, 0.35, shore=shore)

    def post_light():
        made["film post"] = frame_light(swell, 0.0, RIPPLE_HOURS)

    times = {"post texture, beams": _runs(lambda: post("beams"), repeats),
             "post texture, photons": _runs(lambda: post("photons"), repeats),
             f"a film frame's light, Carla's Island {size} (3 shore textures)": _runs(lambda: light(True), repeats),
             "a film frame's light, Carla's Island, no shores": _runs(lambda: light(False), repeats),
             "a film frame's light, the post in the swell (its post's texture)": _runs(post_light, repeats)}
    beams, shores = made["beams"], made[True].extra_irradiance[-1].textures
    (film_post,) = made["film post"].extra_irradiance[-1].textures
    times["bytes"] = {"post texture (reflected)": int(beams.above.nbytes),
                      "post texture (refracted, per wavelength)": int(beams.below.nbytes),
                      "Carla's 3 shore textures (reflected)": int(sum(t.reflected.nbytes for t in shores)),
                      "a film frame's post texture (reflected and refracted)":
                          int(film_post.above.nbytes + film_post.below.nbytes),
                      "beams' corners, post": int(beams.rays),
                      "beams' corners, Carla's 3 shores": int(sum(t.rays for t in shores)),
                      f"a frame's light, Carla's Island {size}, traced peak (RGB_LIGHT_BYTES {RGB_LIGHT_BYTES:,})":
                          int(_traced_peak(lambda: light(True)))}
    return times


def measure_convergence(width: int = 0, height: int = 0, repeats: int = 1) -> dict:
    """The beams at :data:`CONVERGENCE_CELLS` against :data:`CONVERGENCE_PHOTONS` photons (a histogram), on the
    post in the swell at the figure's hour: rms differences of the reflected texture, relative to its rms; and
    each mesh against the next finer one (``self_*``, rms; ``*_l1``: mean absolute differences), plain, with
    the glancing beams halved (``_refined``), with every landing beam halved (``_everywhere``; its rms split
    between the columns by the silhouettes and the rest, ``_on_silhouettes``, ``_off_silhouettes``), and on
    :class:`NearPost` (``_near``, plain beams of :data:`NEAR_CELLS`)."""
    import math

    from ..figures.future import RIPPLE_HOURS
    from ..light.caustics import trace_beams
    from ..light.postrays import PostReceiver
    from ..light.ripples import trace_ripples
    from ..model.scene import load_named_scene

    swell = load_named_scene("post-in-the-swell")
    share = CONVERGENCE_PHOTONS // CONVERGENCE_PARTS
    start = time.process_time()
    parts = [trace_ripples(swell, 0, 0.0, RIPPLE_HOURS, method="photons", rays=share, texels=CONVERGENCE_TEXELS,
                           bandwidth=0.0, seed=100 + k).above for k in range(CONVERGENCE_PARTS)]
    photon_seconds = time.process_time() - start
    photons = np.mean(parts, axis=0)
    scale = float(np.sqrt(np.mean(photons ** 2)))
    # the noise of the mean of the parts, from their spread
    noise = float(np.sqrt(np.mean(np.var(parts, axis=0, ddof=1) / CONVERGENCE_PARTS)))
    out = {"photons": CONVERGENCE_PHOTONS, "photon_seconds": photon_seconds, "texels": CONVERGENCE_TEXELS,
           "hours": RIPPLE_HOURS, "rms": scale, "photon_noise": noise / scale, "cells": list(CONVERGENCE_CELLS)}
    for refine in (0, CONVERGENCE_REFINE):
        diff, seconds, textures = [], [], []
        for cell in CONVERGENCE_CELLS:
            start = time.process_time()
            tex = trace_ripples(swell, 0, 0.0, RIPPLE_HOURS, cell=cell, texels=CONVERGENCE_TEXELS, refine=refine)
            seconds.append(time.process_time() - start)
            diff.append(float(np.sqrt(np.mean((tex.above - photons) ** 2))) / scale)
            textures.append((tex.above, tex.below.mean(axis=-1)))
        key = "" if refine == 0 else "_refined"
        out["difference" + key], out["beam_seconds" + key] = diff, seconds
        # the beams against the next finer beams (no photon noise): reflected and refracted (mean over λ), each
        # relative to the finer texture's rms
        for j, name in enumerate(("reflected", "refracted")):
            orders = self_orders(textures, j)
            out[f"self_{name}{key}"], out[f"self_{name}{key}_l1"] = orders["L2"], orders["L1"]
    out["refine"] = CONVERGENCE_REFINE
    # the same halvings for every beam that lands, not only those at a glance: where the texture's error lives
    receiver = PostReceiver(swell, 0, 0.0, RIPPLE_HOURS, CONVERGENCE_TEXELS)
    textures, seconds = [], []
    for cell in CONVERGENCE_CELLS:
        start = time.process_time()
        books = trace_beams(receiver, math.ceil(receiver.L / cell), math.ceil(2 * receiver.W / cell),
                            levels=CONVERGENCE_REFINE, glance=2.0)
        seconds.append(time.process_time() - start)
        textures.append((books.reflected, books.refracted.mean(axis=-1)))
    out["beam_seconds_everywhere"] = seconds
    for j, name in enumerate(("reflected", "refracted")):
        orders = self_orders(textures, j)
        out[f"self_{name}_everywhere"], out[f"self_{name}_everywhere_l1"] = orders["L2"], orders["L1"]
        # the same rms differences split between the columns by the silhouettes and the rest (each relative to
        # the finer whole texture's rms, so that the two add in squares to the whole)
        by = silhouette_columns(textures[-1][j])
        out[f"silhouette_columns_{name}"] = np.flatnonzero(by).tolist()
        for key, cols in (("on", by), ("off", ~by)):
            out[f"self_{name}_everywhere_{key}_silhouettes"] = [
                float(np.sqrt(np.sum((a[j][:, cols] - b[j][:, cols]) ** 2) / b[j].size / np.mean(b[j] ** 2)))
                for a, b in zip(textures[:-1], textures[1:])]
    # away from the silhouettes and the far water (NearPost), plain beams
    near = near_textures(swell, RIPPLE_HOURS, NEAR_CELLS)
    out.update(near_cells=list(NEAR_CELLS), near_reach=NEAR_REACH, near_least_cosine=NEAR_LEAST_COSINE)
    for j, name in enumerate(("reflected", "refracted")):
        orders = self_orders(near, j)
        out[f"self_{name}_near"], out[f"self_{name}_near_l1"] = orders["L2"], orders["L1"]
    return out


def rows(result: dict) -> list[dict]:
    """The JSON rows of a :func:`measure_ripples` result run by :func:`sunset.bench.measure`."""
    times = dict(result["times"])
    weights = times.pop("bytes")
    out = [{"what": f"ripples: {what}", "median_cpu_s": statistics.median(t), "runs_cpu_s": list(t),
            "peak_rss_mib": result["peak_rss_mib"]} for what, t in times.items()]
    out += [{"what": f"ripples: {what}", "count": n} for what, n in weights.items()]
    return out


def format_rows(ripple_rows: list[dict]) -> str:
    """Plain-text lines for the table that ``make bench`` prints."""
    return "\n".join(f"{r['what']:48s} {'CPU s':>16s} {r['median_cpu_s']:9.3f}" if "median_cpu_s" in r
                     else f"{r['what']:48s} {'':16s} {r['count']:9,d}" for r in ripple_rows)
