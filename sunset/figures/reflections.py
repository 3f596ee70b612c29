"""Diagnostic maps of the three reflection modes (sunset/vector/pierce.py).

For each mode (0: straight to the sky, 1: one reflection with |R_z|, 2: two
reflections) three maps of the same frame: what each ray finally meets (sky or
an island part; rays that reflected on the sea drawn darker), how many times it
reflected on the water, and the z component of the final ray of the rays that
reach the sky (the quantity the sky's colour codes are made from).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..constants import PART_BEACH, PART_CLIFF, PART_HILL, SEA, SKY
from ..io import save_matplotlib
from .diagnostic import CLASS_COLOURS, prepare

#: Default size of each map, pixels (width, height): small, these are diagnostics.
DEFAULT_SIZE = (256, 256)

#: Colours of 0, 1 and 2 water reflections.
BOUNCE_COLOURS = ((0.80, 0.80, 0.80), (0.25, 0.45, 0.85), (0.90, 0.30, 0.20))

MODE_TITLES = {0: "mode 0: reflected rays to the sky", 1: "mode 1: one reflection, |R_z|",
               2: "mode 2: two reflections"}


def final_class_image(frame) -> np.ndarray:
    """(H, W, 3) float RGB of what every ray finally meets; reflected pixels are darkened."""
    rgb = np.empty(frame.shape + (3,))
    rgb[:] = CLASS_COLOURS["sky"]
    for part, name in ((PART_BEACH, "beach"), (PART_CLIFF, "cliff"), (PART_HILL, "hill")):
        rgb[(frame.final_surface != SKY) & (frame.final_part == part)] = CLASS_COLOURS[name]
    rgb[frame.surface == SEA] *= 0.7
    return rgb


def bounce_image(frame) -> np.ndarray:
    """(H, W, 3) float RGB of the number of water reflections (0, 1, 2)."""
    return np.asarray(BOUNCE_COLOURS)[frame.bounces]


def final_rz_image(frame) -> np.ma.MaskedArray:
    """The final ray's z component where the ray reaches the sky; masked where it meets an island."""
    return np.ma.masked_where(frame.final_surface != SKY, frame.ray[..., 2])


def reflection_modes(path, size: tuple[int, int] = DEFAULT_SIZE, scene=None, t: float = 0.0) -> Path:
    """Render ``scene`` (default: the default scene) in each reflection mode and write the maps.

    Parameters and return value as :func:`sunset.figures.diagnostic.diagnostic`.
    """
    from matplotlib.figure import Figure

    from ..pipeline.frame import render

    path, scene = prepare(path, size, scene)
    frames = {mode: render(scene, t, mode) for mode in (0, 1, 2)}

    fig = Figure(figsize=(10.5, 10.0), layout="constrained")
    axes = fig.subplots(3, 3)
    rz_max = max(float(np.max(f.ray[..., 2])) for f in frames.values())
    for row, (mode, frame) in enumerate(frames.items()):
        sea = frame.surface == SEA
        share = float(np.mean(frame.bounces[sea] == 2)) if sea.any() else 0.0
        ax = axes[row]
        ax[0].imshow(final_class_image(frame), interpolation="nearest")
        ax[0].set_title(f"{MODE_TITLES[mode]}\nfinal surface (reflected: darker)", fontsize=9)
        ax[1].imshow(bounce_image(frame), interpolation="nearest")
        ax[1].set_title(f"water reflections (grey 0, blue 1, red 2)\ntwice: {100 * share:.1f}% of sea pixels",
                        fontsize=9)
        im = ax[2].imshow(final_rz_image(frame), cmap="viridis", vmin=0.0, vmax=rz_max, interpolation="nearest")
        ax[2].set_title("final ray's R_z (sky rays only)", fontsize=9)
        fig.colorbar(im, ax=ax[2], shrink=0.8)
        for a in ax:
            a.set_xticks([])
            a.set_yticks([])
    fig.suptitle(f"{scene.title or 'scene'}: the three reflection modes, {scene.camera.width}×{scene.camera.height}, t = {t:g} s")
    return save_matplotlib(fig, path)
