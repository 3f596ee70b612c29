"""Figure 6 as the future work imagined, and the 8-bit test.

* ``fig6-rgb.png``: the paint-by-numbers Figure 6 (the 8-bit tape through the
  colour tables) beside the same frame from the RGB back end: Fresnel
  reflection, the colour of the water, the sun's disk in the sky and in the
  glitter, anti-aliased with 2 × 2 samples per pixel.
* ``quantisation.png``: the RGB frame quantised to 256 colours two ways (its
  own best palette; a table organised like the paper's code groups), the
  CIEDE2000 error maps and their distributions (:mod:`sunset.light.palette`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..figures.paper import SUNSET_HOURS, png_metadata
from ..io import check_writable, save_matplotlib, save_png

__all__ = ["RGB_SAMPLES", "GAP", "rgb_figure6", "quantisation_figure", "figure6_frames"]

#: Samples per pixel of the RGB Figure 6 (a 2 × 2 grid).
RGB_SAMPLES = 4
#: White gap between the two pictures, pixels.
GAP = 8


def figure6_frames(scene, hours: float = SUNSET_HOURS, seed: int = 0, t: float = 0.0):
    """Figure 6's frame: (8-bit exposure uint8, RGB at 1 sample linear, codes, the sun-disk rule's pixels).

    The codes and the 1-sample RGB frame come from the same traced frame (:mod:`sunset.figures.shared`:
    the exposure is Figure 6's when it was made in the same run).
    """
    from ..light.geometry import Geometry
    from ..light.render import shade_display
    from . import shared

    frame = shared.frame(scene, t, 2)
    codes = shared.codes(scene, t, 2, seed)
    rgb1 = shade_display(Geometry.from_frame(frame), _lighting(scene, hours))
    return shared.exposure(scene, t, 2, seed, hours), rgb1, codes, sun_disk_pixels(scene, codes, hours)


def _lighting(scene, hours: float):
    """The light of the hour (:meth:`~sunset.light.lighting.Lighting.for_scene`), shared by the figures of a run."""
    from ..light.lighting import Lighting
    from . import shared

    return shared.once("lighting", (scene, float(hours)), lambda: Lighting.for_scene(scene, float(hours)))


def sun_disk_pixels(scene, codes, hours: float) -> np.ndarray:
    """(H, W) bool: the pixels the film recorder paints in the sun's colour (mostly covered, sky codes)."""
    from ..tape.codes import CODE_MAP
    from ..recorder.dicomed import sun_coverage

    out = np.zeros(codes.shape, bool)
    rows, cols, cov = sun_coverage(scene.camera, scene.sun, hours)
    if cov.size:
        out[rows, cols] = (cov >= 0.5) & CODE_MAP.reaches_sky(codes[rows, cols])
    return out


def rgb_figure6(path, scene, hours: float = SUNSET_HOURS, seed: int = 0, t: float = 0.0,
                samples: int = RGB_SAMPLES) -> Path:
    """Write the paint-by-numbers Figure 6 and the RGB one side by side (a white gap between)."""
    from ..light.output import to_uint8
    from ..light.render import check_samples, shade_display
    from ..pipeline.rgb import trace_geometry
    from . import shared

    path = check_writable(path)
    k = check_samples(samples)
    pbn = shared.exposure(scene, t, 2, seed, hours)          # Figure 6's picture, when it was made in this run
    rgb = to_uint8(shade_display(trace_geometry(scene, t, 2, samples), _lighting(scene, hours), k))
    h, w = pbn.shape[:2]
    both = np.full((h, 2 * w + GAP, 3), 255, np.uint8)
    both[:, :w] = pbn
    both[:, w + GAP:] = rgb
    settings = {"figure": "6-rgb", "t": t, "hours": hours, "seed": seed, "samples": samples,
                "left": "8-bit codes through the colour tables", "right": "RGB back end"}
    return save_png(path, both, png_metadata(scene, settings))


def quantisation_figure(path, scene, hours: float = SUNSET_HOURS, seed: int = 0, t: float = 0.0) -> Path:
    """Write the 8-bit test: the two quantised frames, their ΔE₀₀ maps and distributions."""
    from matplotlib.figure import Figure

    from ..light.palette import QuantisationResult, quantisation_test

    path = check_writable(path)
    _, rgb1, codes, sun = figure6_frames(scene, hours, seed, t)
    q = quantisation_test(rgb1, codes, sun)
    fig = Figure(figsize=(12, 7.2), layout="constrained")
    axes = fig.subplots(2, 3)
    vmax = 10.0
    panels = [(q.reference, "RGB frame (1 sample per pixel)"),
              (q.best_image, "its own best 256 colours (median cut + k-means)"),
              (q.codes_image, "256 colours organised as the paper's codes")]
    for ax, (img, title) in zip(axes[0], panels):
        ax.imshow(img, interpolation="nearest")
        ax.set_title(title, fontsize=9)
        ax.set_axis_off()
    for ax, (de, title) in zip(axes[1, :2], [(q.best, "ΔE₀₀, best palette"), (q.codes, "ΔE₀₀, the paper's codes")]):
        im = ax.imshow(de, cmap="magma", vmin=0, vmax=vmax, interpolation="nearest")
        ax.set_title(title, fontsize=9)
        ax.set_axis_off()
    fig.colorbar(im, ax=axes[1, 1], shrink=0.8, label="CIEDE2000 (clipped at 10)")
    ax = axes[1, 2]
    bins = np.linspace(0, 20, 81)
    for de, label in ((q.best, "best palette"), (q.codes, "paper's codes")):
        s = QuantisationResult.summary(de)
        ax.hist(np.minimum(de.ravel(), 20), bins=bins, histtype="step", density=True,
                label=f"{label}: median {s['median']:.2f}, 99% {s['p99']:.1f}")
    ax.axvline(1.0, color="0.5", lw=0.8, ls="--")
    ax.set_xlabel("CIEDE2000")
    ax.set_ylabel("share of pixels (density)")
    ax.set_yscale("log")
    ax.legend(fontsize=8)
    ax.set_title("distributions", fontsize=9)
    return save_matplotlib(fig, path)
