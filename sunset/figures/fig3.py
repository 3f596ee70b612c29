"""Figure 3: perspective projection along one vertical scan line.

The paper's Figure 3 (lost in the OCR) shows the plane x = s·y of one
vertical scan line: a wavy sea profile, a point P on it and its projection Q
on the picture plane y = 1 at height g(y) = f(s·y, y)/y. This module redraws
it from the renderer's own pieces on the default scene's sea:

* (a) the side view: the eye, the profile z = f(s·y, y) (heights exaggerated),
  the rays through a few pixel centres, each ending where the scan line's
  loop puts it (:func:`sunset.vector.heightfield.scan_line_reference`), and the
  troughs that no ray reaches;
* (b) the same scan line in the picture plane: g(y) against 1/y (the paper's
  samples y_i = h/(iσΔζ) are evenly spaced in 1/y), its running maximum from
  near to far, which is the profile the eye sees, and the pixel centres.

A point of the profile is hidden exactly when g there lies below the running
maximum of g over all nearer points: some nearer crest projects higher.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SunsetError, require_finite
from ..io import check_writable, save_matplotlib

#: The figure's scan line: s = x/y (0: the one straight ahead), and the time.
FIG3_S = 0.0
FIG3_T = 0.0
#: The stretch of the scan line drawn, metres from the eye.
FIG3_Y_NEAR = 5.0
FIG3_Y_FAR = 90.0
#: Pixel centres of the figure's coarse scan line (few, so that each ray can be seen).
FIG3_PIXELS = 40
#: σ of the figure's samples, in the figure's pixels (the paper's 1/4).
FIG3_SIGMA = 0.25
#: Panel (b) shows the scan line beyond this distance, metres.
FIG3_ZOOM_NEAR = 25.0
#: Points of the dense profile.
_N_DENSE = 6000


@dataclass(frozen=True)
class ScanLine:
    """One vertical scan line of the sea, densely and as the renderer samples it.

    Attributes
    ----------
    h : float
        Eye height, metres.
    y, f, g, running_max : ndarray (n,)
        Dense distances (near to far), heights f (metres, eye at z = 0), their
        projections g = f/y and the running maximum of g from near to far.
    hidden : ndarray (n,) bool
        Points that no ray from the eye reaches: g < running maximum.
    y_samples, g_samples : ndarray (m,)
        The paper's samples y_i = h/(iσΔζ), near to far, and g there
        (:func:`sunset.vector.heightfield.sea_profile`).
    zeta : ndarray (k,)
        Pixel-centre heights on the picture plane, bottom to top.
    yp : ndarray (k,)
        Where the ray through each pixel centre meets the sea
        (:func:`sunset.vector.heightfield.scan_line_reference` on the samples); inf
        where it passes over every sample.
    """

    h: float
    y: np.ndarray
    f: np.ndarray
    g: np.ndarray
    running_max: np.ndarray
    hidden: np.ndarray
    y_samples: np.ndarray
    g_samples: np.ndarray
    zeta: np.ndarray
    yp: np.ndarray

    @property
    def hidden_fraction(self) -> float:
        """Share of the dense points (evenly spaced in y) that are hidden."""
        return float(np.mean(self.hidden))

    def hidden_runs(self) -> list[tuple[float, float]]:
        """The hidden stretches (y_start, y_end), metres, near to far."""
        h = self.hidden.astype(np.int8)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], h, [0]])))
        return [(float(self.y[a]), float(self.y[b - 1])) for a, b in zip(edges[::2], edges[1::2])]


def scan_line(scene, s: float = FIG3_S, t: float = FIG3_T, y_near: float = FIG3_Y_NEAR,
              y_far: float = FIG3_Y_FAR, pixels: int = FIG3_PIXELS, sigma: float = FIG3_SIGMA,
              n: int = _N_DENSE) -> ScanLine:
    """The scan line x = s·y of ``scene``'s sea at time ``t`` between ``y_near`` and ``y_far``.

    The pixels are ``pixels`` centres spread evenly in ζ from the projection
    of the highest crest at ``y_near`` to that of mean sea level at
    ``y_far``; the samples
    follow the paper's rule y_i = h/(iσΔζ) with that pixel pitch Δζ.
    """
    for name, v in (("s", s), ("t", t), ("y_near", y_near), ("y_far", y_far), ("sigma", sigma)):
        require_finite(name, v)
    if not 0.0 < y_near < y_far:
        raise SunsetError(f"need 0 < y_near < y_far, got {y_near!r} and {y_far!r}")
    if int(pixels) != pixels or pixels < 2:
        raise SunsetError(f"pixels must be an integer of at least 2, got {pixels!r}")
    if not 0.0 < sigma <= 4.0:
        raise SunsetError(f"sigma must be in (0, 4] pixels, got {sigma!r}")
    from ..vector.heightfield import scan_line_reference, sea_profile

    sea = scene.sea
    h = scene.camera.eye_height
    y = np.linspace(y_near, y_far, int(n))
    f = np.asarray(sea.elevation(s * y, y, t), dtype=float) - h
    g = f / y
    run = np.maximum.accumulate(g)
    hidden = g < run

    # the lowest pixel's ray is still above the highest crest at y_near (the paper's nearest-sample rule)
    zeta = np.linspace(-max(h - sea.max_elevation, 0.1 * h) / y_near, -h / y_far, int(pixels))
    dzeta = zeta[1] - zeta[0]
    du = sigma * dzeta / h
    i = np.arange(int(math.ceil(1.0 / (y_near * du))), int(math.floor(1.0 / (y_far * du))) - 1, -1)
    u = i * du                                            # near to far
    g_s = sea_profile(sea, np.array([s]), u, h, t)[0].astype(float)
    y_s = 1.0 / u
    yp = scan_line_reference(y_s, g_s, zeta)
    return ScanLine(h=h, y=y, f=f, g=g, running_max=run, hidden=hidden, y_samples=y_s, g_samples=g_s,
                    zeta=zeta, yp=yp)


def figure3(path, scene=None, dpi: int = 120) -> Path:
    """Write Figure 3: one vertical scan line in perspective over a wavy profile.

    Parameters
    ----------
    path : path-like
        The PNG to write (atomically, deterministically).
    scene : Scene, optional
        Whose sea and eye height; the default scene when None.
    dpi : int
        Resolution, dots per inch.

    Returns
    -------
    Path
        ``path``.
    """
    path = check_writable(path)
    if scene is None:
        from ..model.scene import Scene

        scene = Scene.default()
    sl = scan_line(scene)

    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 5.2), layout="constrained")
    ax, bx = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.35, 1.0]})

    # (a) side view, heights exaggerated
    ex = 5.0
    z = sl.f * ex
    ax.fill_between(sl.y, z, z.min() - 1.5, color="#cfe3f3", lw=0)
    ax.plot(sl.y, z, color="tab:blue", lw=1.6, label="the sea's profile z = f(s·y, y)")
    hid = np.where(sl.hidden, z, np.nan)
    ax.plot(sl.y, hid, color="tab:red", lw=3.0, label="hidden: no ray from the eye reaches it")
    for k, (zk, yk) in enumerate(zip(sl.zeta, sl.yp)):
        if not np.isfinite(yk):
            continue
        ax.plot([0, yk], [0, zk * yk * ex], color="0.45", lw=0.7)
        ax.plot([yk], [zk * yk * ex], "o", color="k", ms=3)
    ys = sl.y_samples
    fs = sl.g_samples * ys * ex
    ax.plot(ys, fs, "|", color="tab:green", ms=7, label="the paper's samples y_i = h/(iσΔζ)")
    ax.plot([0], [0], marker="o", color="k", ms=6)
    ax.annotate("eye", (0, 0), (3, 0.6 * ex * 0.25), fontsize=10)
    ax.plot([1, 1], [sl.zeta[0] * ex, 0.2 * ex], color="tab:purple", lw=2.0)
    ax.text(2.0, -0.35 * ex, "picture plane y = 1", color="tab:purple", fontsize=9)
    ax.axhline(-sl.h * ex, color="0.6", lw=0.6, ls="--")
    ax.text(0.5 * sl.y[-1], -sl.h * ex + 0.15, "mean sea level z = −h", ha="center", fontsize=8, color="0.4")
    ax.set_xlim(0, sl.y[-1])
    ax.set_ylim(z.min() - 1.5, 0.3 * ex)
    ax.set_xlabel("y, metres from the eye along the scan line")
    ax.set_ylabel(f"z, metres × {ex:g} (exaggerated)")
    ax.set_title("(a) the plane of one scan line: rays through the pixel centres", fontsize=10)
    ax.legend(loc="lower right", fontsize=8, framealpha=0.95)

    # (b) the picture plane: g against 1/y, its running maximum, the pixels
    u = 1.0 / sl.y
    bx.plot(u, sl.g, color="tab:blue", lw=1.2, label="g(y) = f(s·y, y)/y")
    bx.plot(u, sl.running_max, color="k", lw=2.0, label="running maximum from near to far: what is seen")
    bx.fill_between(u, sl.g, sl.running_max, where=sl.hidden, color="tab:red", alpha=0.35, lw=0,
                    label="hidden (g below the running maximum)")
    bx.plot(1.0 / sl.y_samples, sl.g_samples, ".", color="tab:green", ms=4, label="samples: evenly spaced in 1/y")
    for zk, yk in zip(sl.zeta, sl.yp):
        bx.axhline(zk, color="0.7", lw=0.5)
        if np.isfinite(yk):
            bx.plot([1.0 / yk], [zk], "o", color="k", ms=3)
    # the far part, where crests hide troughs (near on the left, far on the right, as in (a))
    far = sl.y >= FIG3_ZOOM_NEAR
    bx.set_xlim(1.0 / FIG3_ZOOM_NEAR, u[-1])
    lo, hi = sl.g[far].min(), sl.g[far].max()
    bx.set_ylim(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo))
    bx.set_xlabel(f"1/y (m⁻¹), from y = {FIG3_ZOOM_NEAR:g} m (left) to {sl.y[-1]:g} m")
    bx.set_ylabel("ζ = z/y on the picture plane")
    bx.set_title("(b) the scan line on the picture plane; grey lines: pixel centres ζ_k", fontsize=10)
    bx.legend(loc="lower right", fontsize=8, framealpha=0.95)
    fig.suptitle("Figure 3. Perspective projection along a vertical scan line", fontsize=11)
    return save_matplotlib(fig, path, dpi=dpi)
