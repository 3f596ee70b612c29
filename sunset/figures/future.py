"""Figures of the paper's last two proposals: clouds by height functions, and ripples of light on a post.

``clouds.png``: Carla's Island under its cloud layer (the packaged scene
``carlas-island-clouds``) on the 8-bit tape, exposed while a cloud hides the
sun and shadows its glitter, and again once the sun has climbed back above it
(earlier in the film's hours), side by side; ``clouds-rgb.png``: the same
frame and hours from the RGB back end (:mod:`sunset.light`).

``ripples.png``: the light that the rippled water throws onto a post standing
in it (the packaged scene ``post-in-the-swell``), traced from the sun
(:func:`sunset.light.ripples.trace_ripples`): the post's side unrolled
(azimuth across, height up, the water line marked), at four times of the wave
cycle, beside still water's flat band.
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
#: The scene of the ripples, the hour of its sun, the rays per texture and the texels up the post.
RIPPLE_SCENE = "post-in-the-swell"
RIPPLE_HOURS = 1.0
RIPPLE_RAYS = 1 << 18
RIPPLE_TEXELS = 32


def cloudy(scene: Scene) -> Scene:
    """``scene`` (its camera, sea, islands, sun) under the cloud layer of ``carlas-island-clouds``."""
    return replace(scene, clouds=load_named_scene("carlas-island-clouds").clouds)


def clouds_figure(path, scene: Scene, seed: int = 0, t: float = 0.0) -> Path:
    """Write ``clouds.png``: the cloudy scene's tape exposed at both :data:`CLOUD_HOURS`, side by side."""
    from . import shared
    from .paper import png_metadata
    from ..recorder.dicomed import expose

    scene = cloudy(scene)
    codes = shared.codes(scene, t, 2, seed)              # from clouds-rgb.png's frame when it was traced first
    rgb = _pair(expose(scene, codes, CLOUD_HOURS[0]), expose(scene, codes, CLOUD_HOURS[1]))
    settings = {"t": t, "reflections": 2, "seed": seed, "hours": list(CLOUD_HOURS), "figure": "clouds"}
    return save_png(path, rgb, png_metadata(scene, settings))


def clouds_rgb_figure(path, scene: Scene, t: float = 0.0) -> Path:
    """Write ``clouds-rgb.png``: the cloudy scene from the RGB back end at both :data:`CLOUD_HOURS`."""
    from . import shared
    from .paper import png_metadata
    from ..light.budget import check_rgb_work
    from ..light.geometry import Geometry
    from ..light.lighting import Lighting
    from ..light.output import to_uint8
    from ..light.render import shade_display

    scene = cloudy(scene)
    check_rgb_work(scene, 1)
    geometry = Geometry.from_frame(shared.frame(scene, t, 2))    # traced once, shaded for each hour
    a, b = (to_uint8(shade_display(geometry, Lighting.for_scene(scene, h))) for h in CLOUD_HOURS)
    settings = {"t": t, "reflections": 2, "shading": "rgb", "hours": list(CLOUD_HOURS), "figure": "clouds-rgb"}
    return save_png(path, _pair(a, b), png_metadata(scene, settings))


def _pair(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Two images side by side with a white gap."""
    gap = np.full((a.shape[0], max(2, a.shape[1] // 100), 3), 255, np.uint8)
    return np.concatenate([a, gap, b], axis=1)


def ripple_textures(scene: Scene | None = None, times=None, rays: int = RIPPLE_RAYS, texels: int = RIPPLE_TEXELS,
                    seed: int = 0):
    """The post's textures of light at ``times`` (default: four quarters of the wave cycle) and on still water."""
    from ..light.ripples import trace_ripples

    scene = load_named_scene(RIPPLE_SCENE) if scene is None else scene
    if times is None:
        times = [scene.sea.period * k / 4.0 for k in range(4)]
    moving = [trace_ripples(scene, 0, float(t), RIPPLE_HOURS, rays, texels, seed=seed) for t in times]
    still = trace_ripples(scene.still(), 0, 0.0, RIPPLE_HOURS, rays, texels, seed=seed)
    return list(times), moving, still


def unrolled(tex, post) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    """The texture above and below the water as one image (rows top down), luminance of the light
    relative to the direct sun, and its extent (arc length across, height up) for ``imshow``."""
    below = tex.below.mean(axis=-1)
    img = np.concatenate([tex.above[::-1], below[::-1]], axis=0)
    arc = post.radius * 2.0 * math.pi
    return img, (0.0, arc, float(tex.z_below[0] - 0.5 * (tex.z_below[1] - tex.z_below[0])),
                 float(tex.z[-1] + 0.5 * (tex.z[1] - tex.z[0])))


def ripples_figure(path, seed: int = 0) -> Path:
    """Write ``ripples.png``: the post's unrolled textures at four times of the cycle and on still water."""
    from matplotlib.figure import Figure

    scene = load_named_scene(RIPPLE_SCENE)
    post = scene.posts[0]
    times, moving, still = ripple_textures(scene, seed=seed)
    fig = Figure(figsize=(11.0, 4.2))
    axes = fig.subplots(1, 5, sharey=True)
    top = max(float(np.percentile(t.above, 99.5)) for t in moving)
    for ax, tex, title in zip(axes, moving + [still],
                              [f"t = {t:.2f} s" for t in times] + ["still water"]):
        img, extent = unrolled(tex, post)
        im = ax.imshow(img, extent=extent, origin="upper", aspect="auto", cmap="magma", vmin=0.0, vmax=top,
                       interpolation="nearest")
        ax.axhline(0.0, color="0.7", lw=0.8, ls="--")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("around the post, m")
    axes[0].set_ylabel("height above mean sea level, m")
    fig.colorbar(im, ax=list(axes), shrink=0.85, label="irradiance from the water / direct sun")
    fig.suptitle(f"Ripples of light on a post {post.radius * 2:.1f} m thick, the sun {RIPPLE_HOURS:g} h "
                 "before sunset: reflected light above the water line, refracted light below it", fontsize=10)
    return save_matplotlib(fig, path)
