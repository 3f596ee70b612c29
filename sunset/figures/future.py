"""Figures of the paper's last two proposals: clouds by height functions, and ripples of light on a post.

``clouds.png``: Carla's Island under its cloud layer (the packaged scene
``carlas-island-clouds``) on the 8-bit tape, exposed while a cloud hides the
sun and shadows its glitter, and again once the sun has climbed back above it
(earlier in the film's hours), side by side; ``clouds-rgb.png``: the same
frame and hours from the RGB back end (:mod:`sunset.light`).

``ripples.png``: the light that the rippled water throws onto a post standing
in it (the packaged scene ``post-in-the-swell``), traced from the sun as a
mesh of beams (:func:`sunset.light.ripples.trace_ripples`): the post's side
unrolled (azimuth across, height up, the water line marked) at four times of
the wave cycle, the caustics' sharp lines moving over it, beside the photon
estimate of the first moment for about the same work.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..io import save_matplotlib, save_png
from ..model.scene import Scene, load_named_scene

#: Hours before sunset of the two exposures of clouds.png: the sun behind a cloud, and above it.
CLOUD_HOURS = (0.28, 0.45)
#: The scene of the ripples, the hour of its sun (20° high: sunlight refracted down the post under water and
#: reflected up it above), the beams' side on the water (m), the photons of the comparison (about the beams'
#: work) and the texels up the post.
RIPPLE_SCENE = "post-in-the-swell"
RIPPLE_HOURS = 2.0
RIPPLE_CELL = 0.05
RIPPLE_RAYS = 1 << 21
RIPPLE_TEXELS = 64


def cloudy(scene: Scene) -> Scene:
    """``scene`` (its camera, sea, islands, sun) under the cloud layer of ``carlas-island-clouds``."""
    return replace(scene, clouds=load_named_scene("carlas-island-clouds").clouds)


def clouds_figure(path, scene: Scene, seed: int = 0, t: float = 0.0) -> Path:
    """Write ``clouds.png``: the cloudy scene's tape exposed at both :data:`CLOUD_HOURS`, side by side."""
    from . import shared
    from .paper import png_metadata
    from ..pipeline.frame import expose

    scene = cloudy(scene)
    codes = shared.codes(scene, t, 2, seed)              # from clouds-rgb.png's frame when it was traced first
    rgb = _pair(expose(scene, codes, CLOUD_HOURS[0]), expose(scene, codes, CLOUD_HOURS[1]))
    settings = {"t": t, "reflections": 2, "seed": seed, "hours": list(CLOUD_HOURS), "figure": "clouds"}
    return save_png(path, rgb, png_metadata(scene, settings))


def clouds_rgb_figure(path, scene: Scene, t: float = 0.0) -> Path:
    """Write ``clouds-rgb.png``: the cloudy scene from the RGB back end at both :data:`CLOUD_HOURS`."""
    from . import shared
    from .paper import png_metadata
    from ..pipeline.budget import rgb_work
    from ..light.geometry import Geometry
    from ..light.lighting import Lighting
    from ..light.output import to_uint8
    from ..light.render import shade_display

    scene = cloudy(scene)
    work = rgb_work(scene, 1)                                   # the budget, once, passed to the frame
    geometry = Geometry.from_frame(shared.frame(scene, t, 2, work))    # traced once, shaded for each hour
    a, b = (to_uint8(shade_display(geometry, Lighting.for_scene(scene, h))) for h in CLOUD_HOURS)
    settings = {"t": t, "reflections": 2, "shading": "rgb", "hours": list(CLOUD_HOURS), "figure": "clouds-rgb"}
    return save_png(path, _pair(a, b), png_metadata(scene, settings))


def _pair(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Two images side by side with a white gap."""
    gap = np.full((a.shape[0], max(2, a.shape[1] // 100), 3), 255, np.uint8)
    return np.concatenate([a, gap, b], axis=1)


def ripple_textures(scene: Scene | None = None, times=None, texels: int | None = None, method: str = "beams",
                    cell: float | None = None, rays: int | None = None, seed: int = 0):
    """The post's textures of light at ``times`` (default: four quarters of the wave cycle), by ``method``
    (the beams' ``cell``, the photons' ``rays`` and the ``texels``: :data:`RIPPLE_CELL`, :data:`RIPPLE_RAYS`,
    :data:`RIPPLE_TEXELS` by default)."""
    from ..light.ripples import trace_ripples

    texels = RIPPLE_TEXELS if texels is None else texels
    cell = RIPPLE_CELL if cell is None else cell
    rays = RIPPLE_RAYS if rays is None else rays
    scene = load_named_scene(RIPPLE_SCENE) if scene is None else scene
    if times is None:
        times = [scene.sea.period * k / 4.0 for k in range(4)]
    textures = [trace_ripples(scene, 0, float(t), RIPPLE_HOURS, method=method, cell=cell, rays=rays, texels=texels,
                              seed=seed) for t in times]
    return list(times), textures


def unrolled(tex, post) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    """The texture above and below the water as one image (rows top down, each the reflected texel above the
    mean water line and the refracted one, mean over λ, below it), irradiance relative to the direct sun, and
    its extent (arc length across, height up) for ``imshow``."""
    dz = tex.z[1] - tex.z[0]
    top, foot = tex.z[-1] + 0.5 * dz, tex.z_below[0] - 0.5 * (tex.z_below[1] - tex.z_below[0])
    rows = int(round((top - foot) / dz))
    zc = top - (np.arange(rows) + 0.5) * (top - foot) / rows
    ia = np.clip(np.searchsorted(tex.z - 0.5 * dz, zc, side="right") - 1, 0, len(tex.z) - 1)
    zb_lo = tex.z_below - 0.5 * (tex.z_below[1] - tex.z_below[0])
    ib = np.clip(np.searchsorted(zb_lo, zc, side="right") - 1, 0, len(tex.z_below) - 1)
    img = np.where((zc >= 0)[:, None], tex.above[ia], tex.below.mean(axis=-1)[ib])
    return img, (0.0, post.radius * 2.0 * math.pi, float(foot), float(top))


def ripples_figure(path, seed: int = 0) -> Path:
    """Write ``ripples.png``: the post's unrolled textures by beams at four times of the cycle, and by photons."""
    from matplotlib.figure import Figure

    scene = load_named_scene(RIPPLE_SCENE)
    post = scene.posts[0]
    times, moving = ripple_textures(scene)
    _, (photons,) = ripple_textures(scene, times=times[:1], method="photons", seed=seed)
    fig = Figure(figsize=(11.0, 4.9), layout="constrained")       # the colour bar hugs the panels
    axes = fig.subplots(1, 5, sharey=True)
    images = [unrolled(t, post) for t in moving + [photons]]
    top = max(float(np.percentile(img, 99.0)) for img, _ in images[:-1])
    titles = [f"beams,\nt = {t:.2f} s" for t in times] + [f"{photons.rays:,} photons,\nt = {times[0]:.2f} s"]
    for ax, (img, extent), title in zip(axes, images, titles):
        im = ax.imshow(img, extent=extent, origin="upper", aspect="auto", cmap="magma", vmin=0.0, vmax=top,
                       interpolation="nearest")
        ax.axhline(0.0, color="0.7", lw=0.8, ls="--")
        ax.set_title(title, fontsize=8.5)
        ax.set_xlabel("around the post, m")
    axes[0].set_ylabel("height above mean sea level, m")
    fig.colorbar(im, ax=list(axes), shrink=0.85, label="irradiance from the water / direct sun")
    fig.suptitle(f"Ripples of light on a post {post.radius * 2:.1f} m thick, the sun {RIPPLE_HOURS:g} h before "
                 "sunset: reflected light above the water line, refracted light below it", fontsize=10)
    return save_matplotlib(fig, path)
