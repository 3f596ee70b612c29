"""The direct-ray diagnostic: surface classes, normals and distances of the default scene.

Three maps of one frame of :func:`sunset.pipeline.frame.trace_direct`: what the
ray through each pixel centre meets (sky, sea, or an island's beach, cliff or
hill), the unit normal there coloured as RGB = (N + 1)/2 (so an upward normal
is lavender, one facing the eye is green-tinted), and the distance to the hit
on a log scale.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from ..errors import require_int_range
from ..io import check_writable, save_matplotlib

#: Default (width, height) of each map, pixels: half the paper's 1020 × 1023.
DEFAULT_SIZE = (510, 512)

#: Colours (RGB in 0..1) of the surface classes.
CLASS_COLOURS = {
    "sky": (0.62, 0.78, 0.95),
    "sea": (0.10, 0.25, 0.50),
    "beach": (0.88, 0.76, 0.52),
    "cliff": (0.58, 0.36, 0.20),
    "hill": (0.30, 0.60, 0.25),
}

#: Brightness of island k's parts (k = 1, 2, 3, …, cycling), to tell islands apart.
ISLAND_SHADES = (1.0, 0.78, 0.6)


def prepare(path, size: tuple[int, int], scene=None):
    """Check a diagnostic's output path and size; the scene (default: the default scene) at that size.

    Returns
    -------
    (Path, Scene)
        The checked output path and the resized scene.
    """
    from ..model.scene import Scene

    width, height = size
    require_int_range("width", width, 1)
    require_int_range("height", height, 1)
    path = check_writable(path)
    return path, (Scene.default() if scene is None else scene).with_size(width, height)


def class_image(frame) -> np.ndarray:
    """(H, W, 3) float RGB of what each direct ray meets (islands shaded by number)."""
    rgb = np.empty(frame.shape + (3,))
    rgb[:] = CLASS_COLOURS["sky"]
    rgb[frame.surface == SEA] = CLASS_COLOURS["sea"]
    islands = frame.surface > 0
    for part, name in ((PART_BEACH, "beach"), (PART_CLIFF, "cliff"), (PART_HILL, "hill")):
        rgb[islands & (frame.part == part)] = CLASS_COLOURS[name]
    shade = np.asarray(ISLAND_SHADES)[(np.maximum(frame.surface, 1) - 1) % len(ISLAND_SHADES)]
    rgb[islands] *= shade[islands][:, None]
    return rgb


def normal_image(frame) -> np.ndarray:
    """(H, W, 3) float RGB = (N + 1)/2 of the unit normals; the sky is black."""
    rgb = 0.5 * (np.nan_to_num(frame.normal.astype(float), nan=-1.0) + 1.0)
    rgb[frame.surface == SKY] = 0.0
    return np.clip(rgb, 0.0, 1.0)


def diagnostic(path, size: tuple[int, int] = DEFAULT_SIZE, scene=None, t: float = 0.0) -> Path:
    """Trace the direct rays of ``scene`` (default: the default scene) and write the three maps.

    Parameters
    ----------
    path : path-like
        The PNG to write (atomically).
    size : (int, int)
        (width, height) of each map in pixels.
    scene : Scene, optional
    t : float
        Time, seconds.

    Returns
    -------
    Path
        ``path``.
    """
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    from ..pipeline.frame import trace_direct

    path, scene = prepare(path, size, scene)
    info: dict = {}
    frame = trace_direct(scene, t, info=info)

    fig = Figure(figsize=(15.0, 5.6), layout="constrained")
    axes = fig.subplots(1, 3)
    axes[0].imshow(class_image(frame), interpolation="nearest")
    names = [isl.name or f"island {k}" for k, isl in enumerate(scene.islands, start=1)]
    axes[0].set_title("what the direct ray meets\n(islands " + ", ".join(names) + ": lighter to darker)", fontsize=9)
    axes[0].legend(handles=[Patch(color=c, label=n) for n, c in CLASS_COLOURS.items()], loc="lower left",
                   fontsize=7, framealpha=0.8)
    axes[1].imshow(normal_image(frame), interpolation="nearest")
    axes[1].set_title("unit normal N as RGB = (N + 1)/2", fontsize=9)
    dist = np.ma.masked_invalid(np.where(np.isfinite(frame.distance), frame.distance, np.nan))
    im = axes[2].imshow(dist, cmap="magma_r", norm=LogNorm(vmin=max(float(dist.min()), 1e-3), vmax=float(dist.max())),
                        interpolation="nearest")
    axes[2].set_title("distance to the hit, metres (sky blank)", fontsize=9)
    fig.colorbar(im, ax=axes[2], shrink=0.8)
    for a in axes:
        a.set_xticks([])
        a.set_yticks([])
    fig.suptitle(f"{scene.title or 'scene'}: direct rays, {scene.camera.width}×{scene.camera.height}, t = {t:g} s, σ = {scene.camera.sigma:g} px "
                 f"({info['sea_samples']} sea samples per scan line)")
    return save_matplotlib(fig, path)
