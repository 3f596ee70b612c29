"""Figure 2: Stokes' approximations to the wave form, and the exact wave.

Left, the paper's Figure 2 (lost in the OCR): the first four terms
k a_n cos(n k x) of Stokes' series (eq. 2) with the paper's amplitudes
(:func:`sunset.model.stokes.stokes_coefficients`) and their sum, whose crests are
sharper and troughs wider and shallower than a cosine's. Right, beyond the
paper: at a large steepness H/λ the exact Stokes wave
(:func:`sunset.model.stokes.solve_stokes`) beside the series truncated at orders 1,
2 (what the paper put on its largest wave) and 4, all with the exact wave's
first-harmonic slope α = k a₁; and the crest magnified, with the curvatures
κ/k that the secondary reflections (sunset.vector.pierce) take from the series.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import SunsetError, require_finite, require_positive
from ..io import check_writable, save_matplotlib

#: α = k a₁ of the left panel (the paper's Figure 2 does not say which α it drew).
FIG2_ALPHA = 0.3

#: H/λ of the exact wave in the right panel: 92% of the highest wave's 0.1411.
FIG2_STEEPNESS = 0.13

#: Colours of the series' terms n = 1..4 and of the orders 1, 2, 4.
TERM_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red")
ORDER_COLOURS = {1: "tab:blue", 2: "tab:orange", 4: "tab:red"}


def figure2(path, alpha: float = FIG2_ALPHA, steepness: float = FIG2_STEEPNESS, dpi: int = 120) -> Path:
    """Write Figure 2 (Stokes' series, term by term) beside the series against the exact wave.

    Parameters
    ----------
    path : path-like
        The PNG to write (atomically, deterministically).
    alpha : float
        α = k a₁ of the left panel, in (0, 0.5].
    steepness : float
        H/λ of the exact wave of the right panel, in (0, 0.1411].
    dpi : int
        Resolution of the PNG, dots per inch.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    SunsetError
        For an ``alpha`` or ``steepness`` out of range or NaN, or a path that
        cannot be written.
    """
    require_finite("alpha", alpha)
    if not 0.0 < float(alpha) <= 0.5:
        raise SunsetError(f"alpha must be in (0, 0.5], got {alpha!r}")
    require_positive("steepness", steepness)
    path = check_writable(path)

    from matplotlib.figure import Figure

    from ..model.stokes import series_crest_curvature, stokes_coefficients
    from ..model.stokes_exact import solve_stokes

    wave = solve_stokes(float(steepness))  # raises SunsetError beyond the highest wave
    alpha = float(alpha)

    fig = Figure(figsize=(14.0, 4.6), layout="constrained")
    ax, bx, cx = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1.0, 1.0, 0.6]})

    # Left: the paper's Figure 2, two wavelengths, crests at k x = 0 and ±2π.
    kx = np.linspace(-2 * np.pi, 2 * np.pi, 1601)
    amps = stokes_coefficients(alpha, 4)
    total = np.zeros_like(kx)
    labels = ("α cos kx", "(α²/2 + 17α⁴/24) cos 2kx", "(3α³/8) cos 3kx", "(α⁴/3) cos 4kx")
    for n, (a, colour, label) in enumerate(zip(amps, TERM_COLOURS, labels), start=1):
        term = a * np.cos(n * kx)
        total += term
        ax.plot(kx / (2 * np.pi), term, color=colour, lw=1.2, label=f"n = {n}: {label}")
    ax.plot(kx / (2 * np.pi), total, color="k", lw=2.2, label="sum of the four terms")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlim(-1, 1)
    ax.set_xlabel("x / λ")
    ax.set_ylabel("k z (elevation × wave number)")
    ax.set_title(f"(a) Stokes' series (eq. 2): four terms, α = k a₁ = {alpha:g}", fontsize=10)
    ax.legend(loc="lower center", fontsize=8, ncol=2, framealpha=0.9)
    ax.set_ylim(min(total.min(), -amps[0]) * 1.9, total.max() * 1.2)

    # Middle: the exact wave against the truncated series, one wavelength, crest in the middle.
    kx = np.linspace(-np.pi, np.pi, 1201)
    bx.plot(kx / (2 * np.pi), wave.profile(kx), color="k", lw=2.4, label="exact (solve_stokes)")
    for order, colour in ORDER_COLOURS.items():
        bx.plot(kx / (2 * np.pi), wave.series_profile(kx, order), color=colour, lw=1.2,
                ls="-" if order == 4 else "--", label=f"series to order {order}")
    bx.axhline(0.0, color="0.6", lw=0.6)
    bx.set_xlim(-0.5, 0.5)
    bx.set_xlabel("x / λ")
    bx.set_ylabel("k z")
    bx.set_title(f"(b) exact wave, H/λ = {wave.steepness:g}, and the series with its α = {wave.alpha:.3f}",
                 fontsize=10)
    bx.legend(loc="lower center", fontsize=8, ncol=2, framealpha=0.9)
    top = wave.crest_elevation
    bx.set_ylim(wave.trough_elevation * 1.8, top * 1.15)

    # Right: the crest magnified, where the series is least right, with the curvatures κ/k.
    half = 0.08
    zoom = np.linspace(-half, half, 401) * 2 * np.pi
    kappa = wave.crest_curvature
    cx.plot(zoom / (2 * np.pi), wave.profile(zoom), color="k", lw=2.4, label=f"exact: κ/k = {kappa:.2f}")
    for order, colour in ORDER_COLOURS.items():
        k_n = float(series_crest_curvature(wave.alpha, order))
        cx.plot(zoom / (2 * np.pi), wave.series_profile(zoom, order), color=colour, lw=1.2,
                ls="-" if order == 4 else "--", label=f"order {order}: κ/k = {k_n:.2f}")
    # the osculating parabola of the exact crest, z = z_top − κ x²/2 (in units of k)
    cx.plot(zoom / (2 * np.pi), top - 0.5 * kappa * zoom**2, color="0.5", lw=1.0, ls=":",
            label="exact crest's parabola")
    cx.set_xlim(-half, half)
    cx.set_ylim(top - 0.22, top + 0.03)
    cx.set_xlabel("x / λ")
    cx.set_title("(c) the crest and its curvature", fontsize=10)
    cx.legend(loc="lower center", fontsize=7.5, framealpha=0.9)

    return save_matplotlib(fig, path, dpi=dpi)
