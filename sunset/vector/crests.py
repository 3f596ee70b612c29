"""Secondary reflections: the crest of the largest wave ahead of a ray as a parabolic cylinder.

A ray reflected off the sea that heads into the next crest meets the water a
second time (paper, "Secondary Reflections"). As for the islands, the wave is
replaced by a surface that a ray can pierce in closed form: the parabolic
cylinder z = top − κu²/2 fitted to the first crest of the largest train ahead
of the ray, with κ the crest curvature of the train's Stokes series (eq. 2).
The hit is then reflected again off the true wave normal
(:func:`secondary_reflections`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.stokes import series_crest_curvature
from ..model.waves import Sea, WaveTrain
from .pierce import first_entry, gather, quadratic_interval, reflect

__all__ = ["largest_train", "crest_curvature", "CrestCylinder", "harmonic_sum", "crest_rise", "crest_candidates",
           "crest_cylinder", "cylinder_coefficients", "secondary_reflections"]


def largest_train(sea: Sea) -> WaveTrain | None:
    """The train with the largest first-harmonic amplitude (the first on a tie); None for still water.

    A train so small that its crest curvature underflows to 0 (an amplitude of
    1e-300 m, say) has no crest to fit a cylinder to: it counts as still water.
    """
    moving = [t for t in sea.trains if t.amplitude > 0 and crest_curvature(t) > 0]
    if not moving:
        return None
    return max(moving, key=lambda t: t.amplitude)


def crest_curvature(train: WaveTrain) -> float:
    """κ = Σ_n a_n (n k)², the curvature of the train's Stokes series (eq. 2) at its crest, m⁻¹.

    The series z(u) = Σ a_n cos(n k u) has z'(0) = 0 and z''(0) = −Σ a_n (nk)²;
    :func:`sunset.model.stokes.series_crest_curvature` gives κ/k for the train's
    steepness α = k a₁ and Stokes order.
    """
    return float(series_crest_curvature(train.steepness, train.stokes_order)) * train.k


@dataclass(frozen=True)
class CrestCylinder:
    """Parabolic cylinders fitted to the first crest ahead of each ray, as degenerate paraboloids.

    z = top − e(x−x0)² − f(x−x0)(y−y0) − g(y−y0)² with f² = 4eg: the axis
    is the crest line through (x0, y0), the foot of the perpendicular from the
    ray's origin (eye coordinates, metres). ``u0`` is the signed distance from
    the crest line to the origin along the wave's direction of travel, ``w``
    the rate of change of that distance per unit t along the ray.
    """

    top: np.ndarray
    e: float
    f: float
    g: float
    x0: np.ndarray
    y0: np.ndarray
    curvature: float
    u0: np.ndarray
    w: np.ndarray


def harmonic_sum(amps, c):
    """Σ_n a_n cos nθ from c = cos θ, by the Chebyshev recurrence T_(n+1) = 2c T_n − T_(n−1).

    One cosine per ray instead of one per harmonic (the speed-up the paper
    suggests for the Stokes series); :mod:`sunset.vector.crests_numba` does the same
    operations in the same order.
    """
    c = np.asarray(c, dtype=float)
    out = amps[0] * c
    t_prev, t_cur = 1.0, c
    for a in amps[1:]:
        t_prev, t_cur = t_cur, 2.0 * c * t_cur - t_prev
        out = out + a * t_cur
    return out


def _ahead(psi, rate):
    """Phase from a ray's origin (ψ = θ mod 2π) to the next crest ahead of it, radians (see :func:`crest_cylinder`)."""
    return np.where(rate >= 0.0, 2.0 * math.pi - psi, np.where(psi > 0.0, -psi, -2.0 * math.pi))


def _crest_ahead(train: WaveTrain, t: float, q, r):
    """(ψ = θ mod 2π at the origin, the rate ℓR_x + mR_y of θ along the ray, u₀) for :func:`crest_cylinder`."""
    k = train.k
    l, m = train.wave_vector
    theta = l * q[..., 0] + m * q[..., 1] - train.omega * t + train.phase
    rate = l * r[..., 0] + m * r[..., 1]
    psi = np.mod(theta, 2.0 * math.pi)
    return psi, rate, -_ahead(psi, rate) / k


#: How far the crest's bounding test reaches beyond its bound, relative (far beyond rounding).
CREST_GRACE = 1e-7


def crest_rise(amps, psi):
    """A bound on top − Q_z = Σ a_n (1 − cos nψ) without a cosine, metres.

    ψ = θ mod 2π is the wave's phase at the ray's origin.

    With x = n·min(ψ, 2π − ψ), 1 − cos x <= x²/2 − x⁴/24 + x⁶/720 for every
    real x (the Taylor series of the cosine stopped after a negative term is
    a lower bound), and 1 − cos x <= 2.
    """
    psi = np.asarray(psi, dtype=float)
    near = np.minimum(psi, 2.0 * math.pi - psi)
    out = np.zeros_like(near)
    for n, a in enumerate(amps, start=1):
        x2 = (n * near) * (n * near)
        taylor = x2 * (0.5 - x2 * (1.0 / 24.0 - x2 * (1.0 / 720.0)))
        out = out + a * np.minimum(2.0, taylor)
    return out


def crest_candidates(train: WaveTrain, t: float, q, r) -> np.ndarray:
    """Rays that may meet their crest cylinder: a bounding test before the cosines and the quadratic.

    Along the ray, F(t) = top − κu(t)²/2 − Q_z − R_z t with u(t) = u₀ + w t
    (:func:`cylinder_coefficients`: F = a t² + b t + c), and top − Q_z is at
    most L = :func:`crest_rise` of the origin's phase, which needs no cosine.
    With c' = L − κu₀²/2 >= c in place of c, the ray reaches F >= 0 at some
    t > 0 only if c' >= 0, or b > 0 (F rises) and b² − 4ac' >= 0: rays
    that fail both clear the crest. The bound is widened by a grace far
    beyond rounding (:data:`CREST_GRACE`; u₀ and w are taken with 1/k, a
    rounding the grace covers), so, like :func:`sunset.vector.pierce.island_candidates`,
    the test only skips rays that miss: the quadratic decides.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    psi, rate, _ = _crest_ahead(train, t, q, r)
    inv_k = 1.0 / train.k
    u0 = -_ahead(psi, rate) * inv_k
    w = rate * inv_k
    kappa = crest_curvature(train)
    amps = train.harmonic_amplitudes()
    a = -0.5 * kappa * w * w
    b = -kappa * u0 * w - r[..., 2]
    bow = 0.5 * kappa * u0 * u0
    c = crest_rise(amps, psi) - bow + CREST_GRACE * (np.abs(q[..., 2]) + float(np.sum(amps)) + bow)
    return (c >= 0.0) | ((b > 0.0) & (b * b - 4.0 * a * c >= 0.0))


def crest_cylinder(train: WaveTrain, t: float, q, r) -> CrestCylinder:
    """The parabolic cylinder tangent to the first crest of ``train`` ahead of each ray.

    Crest lines are where the train's phase θ = ℓx + my − ωt + φ ≡ 0 (mod 2π).
    Along the ray, θ changes at the rate ℓR_x + mR_y per unit t; the first
    crest ahead is the next multiple of 2π that θ reaches in that direction
    (a crest through the origin itself is the one the ray leaves, not one
    ahead). A ray exactly parallel to the crests (rate 0, including vertical
    rays) takes the next crest in the direction of travel of the waves: the
    limit of rays turned ever so slightly forward; its cylinder's axis is
    parallel to the ray, and the quadratic becomes linear.

    Height. The cylinder is z = top − κu²/2 across the crest line (u the
    distance across), with κ = :func:`crest_curvature`. Its top is set so that
    the crest stands as far above the ray's origin Q as this train's crest
    stands above this train's own elevation at Q:

        top = Q_z + Σ_n a_n − Σ_n a_n cos(nθ(Q)),

    i.e. the other trains' elevation is taken as a constant offset, its value
    at Q. Because every a_n >= 0 and cos y >= 1 − y²/2, the train's profile
    lies on or above its osculating parabola, so the origin is never inside
    the cylinder (c <= 0): every ray heading down meets it, and the test
    "d >= 0 and t > 0" (the paper's) picks out exactly the rays that do not
    clear the crest.

    Parameters
    ----------
    train : WaveTrain
    t : float
        Time, seconds.
    q, r : array_like, shape (N, 3)
        Ray origins on the sea (eye coordinates, metres) and first reflected directions.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    k = train.k
    l, m = train.wave_vector
    psi, rate, u0 = _crest_ahead(train, t, q, r)
    amps = train.harmonic_amplitudes()
    elevation = harmonic_sum(amps, np.cos(psi))  # cos θ = cos ψ, cheaper on the reduced angle
    top = q[..., 2] + float(np.sum(amps)) - elevation
    kappa = crest_curvature(train)
    cl, cm = l / k, m / k
    x0 = q[..., 0] - u0 * cl
    y0 = q[..., 1] - u0 * cm
    return CrestCylinder(top=top, e=0.5 * kappa * cl * cl, f=kappa * cl * cm, g=0.5 * kappa * cm * cm,
                         x0=x0, y0=y0, curvature=kappa, u0=u0, w=rate / k)


def cylinder_coefficients(cyl: CrestCylinder, q, r):
    """a, b, c of eq. 6 for a crest cylinder, in its factored form.

    With u(t) = u₀ + w t the distance across the crest line,
    F(t) = top − κu(t)²/2 − Q_z − R_z t, so a = −κw²/2 (exactly <= 0, even
    where rounding would make e R_x² + f R_x R_y + g R_y² of the unfactored
    form slightly negative), b = −κu₀w − R_z, c = top − κu₀²/2 − Q_z.
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    kap = cyl.curvature
    a = -0.5 * kap * cyl.w * cyl.w
    b = -kap * cyl.u0 * cyl.w - r[..., 2]
    c = cyl.top - 0.5 * kap * cyl.u0 * cyl.u0 - q[..., 2]
    return a, b, c


def secondary_reflections(sea: Sea, t: float, q, r):
    """Second reflections off the crest ahead (Figure 6), for rays (N, 3).

    Pierce each ray's crest cylinder (the rays that :func:`crest_candidates`
    keeps, gathered); the rays that hit (d >= 0, t > 0) are
    gathered into contiguous arrays, reflected again off the true wave normal
    (:meth:`Sea.normal`) at the piercing point's (x, y), and returned with
    their indices for scattering back.

    Returns
    -------
    idx : ndarray of intp
        Indices of the rays that reflect twice.
    point : ndarray (len(idx), 3)
        The piercing points on the cylinders (the second rays' origins).
    ray : ndarray (len(idx), 3)
        The second reflected directions (R_z not yet made positive).
    """
    q = np.asarray(q, dtype=float)
    r = np.asarray(r, dtype=float)
    train = largest_train(sea)
    if train is None or q.shape[0] == 0:
        return np.zeros(0, np.intp), np.zeros((0, 3)), np.zeros((0, 3))
    cand, (qc, rc) = gather(crest_candidates(train, t, q, r), q, r)
    cyl = crest_cylinder(train, t, qc, rc)
    t_in, _, meets = quadratic_interval(*cylinder_coefficients(cyl, qc, rc))
    hit = first_entry(t_in, meets)
    sel, (q2, r2, t2) = gather(np.isfinite(hit), qc, rc, hit)
    idx = cand[sel]
    point = q2 + t2[:, None] * r2
    normal = sea.normal(point[:, 0], point[:, 1], t)
    return idx, point, reflect(r2, normal)
