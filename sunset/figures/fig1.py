"""Figure 1: the sun's great circle C on the unit sphere at the observer.

The paper's Figure 1 (lost in the OCR) shows a unit sphere centred on the
observer O, the circle C on which the sun moves, the unit vectors U (to the
setting sun, on the horizon), V (to the sun at its highest) and W = U × V
(normal to the plane of C), and the sun's position P(θ) = U cos θ + V sin θ,
θ = 15° per hour before sunset. This module redraws it from the same vectors
the renderer uses (:class:`sunset.model.sun.Sun`), so the picture is the code's
geometry, not a sketch of it.

:func:`circle_geometry` returns every point and vector the figure draws;
:func:`figure1` draws it: (a) the sphere in perspective, (b) the plane of C
seen face-on, where P(θ) is a point on a unit circle at angle θ from U.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SunsetError, require_finite
from ..io import check_writable, save_matplotlib

#: Hours before sunset at which Figure 1 marks P(θ) (θ = 15° per hour, so 2 h is θ = 30°).
FIG1_HOURS = 2.0

#: Points on each drawn circle.
_N_CIRCLE = 361


@dataclass(frozen=True)
class CircleGeometry:
    """What Figure 1 draws, all unit vectors at the observer (x right, y ahead, z up).

    Attributes
    ----------
    U, V, W : ndarray (3,)
        The setting sun, the highest sun, and W = U × V.
    theta : float
        θ of the marked sun, radians.
    P : ndarray (3,)
        P(θ) = U cos θ + V sin θ.
    circle : ndarray (n, 3)
        C: P over θ in [0, 2π], with ``circle_theta`` the θ of each point.
    circle_theta : ndarray (n,)
    horizon : ndarray (n, 3)
        The horizon, the sphere's great circle z = 0.
    elevation : float
        The marked sun's elevation above the horizon, radians.
    tilt : float
        The angle between C and the horizon, radians: V's elevation.
    """

    U: np.ndarray
    V: np.ndarray
    W: np.ndarray
    theta: float
    P: np.ndarray
    circle: np.ndarray
    circle_theta: np.ndarray
    horizon: np.ndarray
    elevation: float
    tilt: float


def circle_geometry(sun, hours: float = FIG1_HOURS, n: int = _N_CIRCLE) -> CircleGeometry:
    """U, V, W, P(θ), the circle C and the horizon, from a :class:`~sunset.model.sun.Sun`.

    Parameters
    ----------
    sun : Sun
        The sun's track (its ``U``, ``V``, ``W`` and ``position``).
    hours : float
        Hours before sunset of the marked sun P(θ).
    n : int
        Points on each circle (at least 8).

    Returns
    -------
    CircleGeometry
    """
    require_finite("hours", hours)
    if int(n) != n or n < 8:
        raise SunsetError(f"n must be an integer of at least 8, got {n!r}")
    theta = float(sun.theta(hours))
    th = np.linspace(0.0, 2.0 * math.pi, int(n))
    # the circle from the renderer's own P(θ): θ is hours × 2π/24
    circle = sun.position(th / float(sun.theta(1.0)))
    phi = np.linspace(0.0, 2.0 * math.pi, int(n))
    horizon = np.stack([np.cos(phi), np.sin(phi), np.zeros_like(phi)], axis=-1)
    P = sun.position(hours)
    return CircleGeometry(U=sun.U, V=sun.V, W=sun.W, theta=theta, P=P, circle=circle, circle_theta=th,
                          horizon=horizon, elevation=float(math.asin(max(-1.0, min(1.0, P[2])))),
                          tilt=float(math.asin(max(-1.0, min(1.0, sun.V[2])))))


def _arrow(ax, v, colour, label, offset=1.12, lw=2.0):
    ax.quiver(0, 0, 0, *v, color=colour, lw=lw, arrow_length_ratio=0.08)
    ax.text(*(np.asarray(v) * offset), label, color=colour, fontsize=12, fontweight="bold",
            ha="center", va="center")


def figure1(path, sun=None, hours: float = FIG1_HOURS, dpi: int = 120) -> Path:
    """Write Figure 1: the unit sphere at the observer, C, U, V, W = U × V and P(θ).

    Parameters
    ----------
    path : path-like
        The PNG to write (atomically, deterministically).
    sun : Sun, optional
        The sun's track; the default scene's when None.
    hours : float
        Hours before sunset of the marked P(θ), in (0, 6) so that it lies
        between U and V as in the paper's figure.
    dpi : int
        Resolution, dots per inch.

    Returns
    -------
    Path
        ``path``.
    """
    require_finite("hours", hours)
    if not 0.0 < float(hours) < 6.0:
        raise SunsetError(f"hours must be in (0, 6) for Figure 1 (P between U and V), got {hours!r}")
    path = check_writable(path)
    if sun is None:
        from ..model.scene import Scene

        sun = Scene.default().sun
    geo = circle_geometry(sun, hours)

    from matplotlib.figure import Figure

    fig = Figure(figsize=(12.0, 5.8), layout="constrained")
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    bx = fig.add_subplot(1, 2, 2)

    # (a) the sphere in perspective
    u = np.linspace(0, 2 * np.pi, 25)
    for lat in np.radians([-60, -30, 30, 60]):
        ax.plot(np.cos(lat) * np.cos(u), np.cos(lat) * np.sin(u), np.full_like(u, np.sin(lat)),
                color="0.85", lw=0.6)
    for lon in np.radians(np.arange(0, 180, 30)):
        v = np.linspace(0, 2 * np.pi, 49)
        ax.plot(np.cos(v) * np.cos(lon), np.cos(v) * np.sin(lon), np.sin(v), color="0.85", lw=0.6)
    hz = geo.horizon
    ax.plot(hz[:, 0], hz[:, 1], hz[:, 2], color="0.35", lw=1.2, ls="--")
    ax.text(-0.95, -0.55, 0.0, "horizon", color="0.35", fontsize=9)
    c = geo.circle
    up = c[:, 2] >= 0
    ax.plot(*np.where(up[:, None], c, np.nan).T, color="tab:orange", lw=2.4)
    ax.plot(*np.where(~up[:, None], c, np.nan).T, color="tab:orange", lw=1.0, ls=":")
    k = int(0.37 * len(c))
    ax.text(*(c[k] * 1.08), "C", color="tab:orange", fontsize=13, fontweight="bold")
    _arrow(ax, geo.U, "tab:red", "U")
    _arrow(ax, geo.V, "tab:blue", "V")
    _arrow(ax, geo.W, "tab:purple", "W = U × V")
    _arrow(ax, geo.P, "darkorange", "P(θ)", offset=1.2)
    # the arc θ from U to P along C
    arc = sun.position(np.linspace(0.0, hours, 30)) * 0.35
    ax.plot(*arc.T, color="k", lw=1.0)
    mid = sun.position(0.5 * hours) * 0.45
    ax.text(*mid, "θ", fontsize=12)
    ax.scatter([0], [0], [0], color="k", s=12)
    ax.text(0.04, -0.12, -0.12, "O", fontsize=12)
    for vec, lab in (((1.35, 0, 0), "x"), ((0, 1.35, 0), "y (view)"), ((0, 0, 1.35), "z")):
        ax.plot([0, vec[0]], [0, vec[1]], [0, vec[2]], color="0.55", lw=0.7)
        ax.text(*vec, lab, color="0.45", fontsize=9)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlim(-1, 1)
    ax.set_ylim(-1, 1)
    ax.set_zlim(-1, 1)
    ax.view_init(elev=18, azim=-62)
    ax.set_axis_off()
    ax.set_title("(a) the unit sphere at the observer O", fontsize=10)

    # (b) the plane of C face-on: coordinates (P·U, P·V)
    t = np.linspace(0, 2 * np.pi, 361)
    bx.plot(np.cos(t), np.sin(t), color="tab:orange", lw=2.0)
    # the horizon meets the plane of C in the line through ±U: the V-axis's zero
    bx.axhline(0.0, color="0.35", lw=1.0, ls="--")
    bx.text(-1.02, 0.03, "horizon (−U … U)", color="0.35", fontsize=9, ha="left", va="bottom")
    th = geo.theta
    for (x, y), colour, lab in (((1, 0), "tab:red", "U"), ((0, 1), "tab:blue", "V"),
                                ((math.cos(th), math.sin(th)), "darkorange", "P(θ)")):
        bx.annotate("", xy=(x, y), xytext=(0, 0),
                    arrowprops=dict(arrowstyle="-|>", color=colour, lw=2.0))
        bx.text(1.12 * x, 1.12 * y, lab, color=colour, fontsize=12, fontweight="bold", ha="center", va="center")
    bx.plot([math.cos(th), math.cos(th)], [0, math.sin(th)], color="0.5", lw=0.8, ls=":")
    bx.text(math.cos(th), -0.08, "cos θ", ha="center", va="top", fontsize=9, color="0.3")
    bx.plot([0, math.cos(th)], [math.sin(th), math.sin(th)], color="0.5", lw=0.8, ls=":")
    bx.text(-0.04, math.sin(th), "sin θ", ha="right", va="center", fontsize=9, color="0.3")
    a = np.linspace(0, th, 30)
    bx.plot(0.3 * np.cos(a), 0.3 * np.sin(a), color="k", lw=1.0)
    bx.text(0.36 * math.cos(th / 2), 0.36 * math.sin(th / 2), "θ", fontsize=12, va="center")
    bx.text(0.0, -0.06, "O", fontsize=11, ha="center", va="top")
    bx.text(0.02, -1.22, "W points out of the page", fontsize=9, ha="center", color="tab:purple")
    bx.set_aspect("equal")
    bx.set_xlim(-1.35, 1.35)
    bx.set_ylim(-1.3, 1.3)
    bx.set_axis_off()
    bx.set_title(f"(b) the plane of C face-on: P(θ) = U cos θ + V sin θ, θ = 15°/h × {hours:g} h", fontsize=10)
    fig.suptitle(f"Figure 1. The sun's great circle C (tilt {math.degrees(geo.tilt):.0f}° to the horizon, "
                 f"setting {sun.azimuth:g}° right of the view axis)", fontsize=11)
    return save_matplotlib(fig, path, dpi=dpi)
