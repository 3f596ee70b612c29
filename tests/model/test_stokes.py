"""Tests for sunset.model.stokes: the paper's expansion against exact Stokes waves.

Reference values come from independent computations: Bernoulli's law on the
exact surface (the solver never evaluates it), a Rienecker–Fenton style
stream function fitted to the Eulerian profile alone, finite differences,
Fourier analysis of the profile, and the classical analytic results of
Stokes' expansion (Stokes 1880; Lamb, Hydrodynamics §250), checked by the
order at which their error vanishes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sunset.constants import STOKES_MAX_STEEPNESS
from sunset.errors import SunsetError
from sunset.model.stokes import expansion_fit, series_crest_curvature, series_speed, stokes_coefficients
from sunset.model.stokes_exact import solve_stokes

SHAPES = [(), (6,), (2, 3), (2, 3, 1)]


def small_wave(kH: float):
    """An exact wave of small height on a plain grid (cached by the module)."""
    return solve_stokes(kH / (2 * math.pi), n_modes=48, map_parameter=1.0)


# --------------------------------------------------------------------------- the paper's series
@pytest.mark.parametrize("shape", SHAPES)
def test_coefficients_shapes(shape):
    alpha = np.full(shape, 0.2)
    out = stokes_coefficients(alpha, 4)
    assert out.shape == shape + (4,)
    assert series_speed(alpha).shape == shape
    assert series_crest_curvature(alpha).shape == shape
    np.testing.assert_allclose(out, np.broadcast_to(stokes_coefficients(0.2, 4), shape + (4,)))


def test_coefficients_truncation_orders():
    """Order p keeps the terms up to α^p: a₂'s α⁴ term appears only at order 4."""
    a = 0.3
    full = stokes_coefficients(a, 4)
    for order in (1, 2, 3):
        part = stokes_coefficients(a, order)
        assert part.shape == (order,)
        np.testing.assert_allclose(part[0], a)
    np.testing.assert_allclose(stokes_coefficients(a, 2)[1], a * a / 2)
    np.testing.assert_allclose(stokes_coefficients(a, 3)[:3], [a, a * a / 2, full[2]])
    assert full[1] > a * a / 2


def test_series_crest_curvature_is_minus_second_derivative():
    """κ/k of the series equals −z''(0), by a central difference of the series itself."""
    for alpha in (0.05, 0.2, 0.35):
        for order in (1, 2, 3, 4):
            amps = stokes_coefficients(alpha, order)
            z = lambda x: sum(a * math.cos(n * x) for n, a in enumerate(amps, start=1))  # noqa: E731
            h = 1e-4
            fd = -(z(h) - 2 * z(0.0) + z(-h)) / h**2
            assert float(series_crest_curvature(alpha, order)) == pytest.approx(fd, rel=1e-6)


@pytest.mark.parametrize("bad, message", [
    (dict(alpha=-0.1), "alpha must not be negative"),
    (dict(alpha=float("nan")), "alpha must be a finite number"),
    (dict(alpha=[0.1, float("inf")]), "alpha must be a finite number"),
    (dict(alpha=0.1, order=5), "order must be in 1..4"),
    (dict(alpha=0.1, order=0), "order must be in 1..4"),
    (dict(alpha=0.1, order=2.0), "order must be an integer"),
])
def test_series_bad_input(bad, message):
    for fn in (stokes_coefficients, series_speed, series_crest_curvature):
        with pytest.raises(SunsetError, match=message):
            fn(**bad)


# --------------------------------------------------------------------------- the exact solver
def bernoulli_spread(wave, n_points=3001):
    """Spread of ½q² + z along the exact surface, at points that are not collocation nodes."""
    surf = wave.surface(n_points)
    return float(np.ptp(0.5 * surf.speed**2 + surf.elevation))


def stream_function_check(wave, n_terms=30, n_points=600):
    """Independent check from the Eulerian profile and the speed only.

    A deep-water stream function ψ = −c z + Σ B_j e^{jz} cos jx (Rienecker &
    Fenton 1981) is fitted by least squares so that the profile z(x) is a
    streamline; then Bernoulli's ½|∇ψ|² + z must be the same all along it.
    Returns (spread of Bernoulli, largest kinematic residual).
    """
    x = np.linspace(0.0, math.pi, n_points)
    n = np.arange(1, len(wave.coefficients) + 1)
    z = np.cos(np.outer(x, n)) @ wave.coefficients
    j = np.arange(1, n_terms + 1)
    E = np.exp(np.outer(z - z.max(), j))
    EC, ES = E * np.cos(np.outer(x, j)), E * np.sin(np.outer(x, j))
    A = np.hstack([EC, -np.ones((n_points, 1))])
    sol, *_ = np.linalg.lstsq(A, wave.speed * z, rcond=None)
    u = -wave.speed + EC @ (j * sol[:-1])
    w = ES @ (j * sol[:-1])
    return float(np.ptp(0.5 * (u * u + w * w) + z)), float(np.max(np.abs(A @ sol - wave.speed * z)))


@pytest.mark.parametrize("steepness", [0.02, 0.06, 0.1, 0.12])
def test_exact_wave_satisfies_bernoulli_from_profile_alone(steepness):
    wave = solve_stokes(steepness)
    spread, kinematic = stream_function_check(wave)
    assert kinematic < 1e-12
    assert spread < 1e-10


def test_stream_function_check_detects_a_wrong_speed():
    """The independent check is sharp: a speed off by 1e-7 fails it by far."""
    import dataclasses

    wave = solve_stokes(0.06)
    wrong = dataclasses.replace(wave, speed=wave.speed * (1 + 1e-7))
    assert stream_function_check(wrong)[0] > 1e-8


@pytest.mark.parametrize("steepness, tol", [(0.05, 1e-12), (0.12, 1e-11), (0.135, 1e-10)])
def test_exact_wave_bernoulli_on_surface(steepness, tol):
    wave = solve_stokes(steepness)
    assert bernoulli_spread(wave) < tol
    surf = wave.surface(101)
    np.testing.assert_allclose(0.5 * surf.speed**2 + surf.elevation, wave.bernoulli, atol=tol)


@pytest.mark.parametrize("steepness", [0.05, 0.12, 0.135])
def test_exact_wave_geometry(steepness):
    """Height, zero mean level, crest at x = 0, and a_n = the Fourier series of the profile."""
    wave = solve_stokes(steepness)
    kH = 2 * math.pi * steepness
    assert wave.profile(0.0) - wave.profile(math.pi) == pytest.approx(kH, abs=1e-12)
    assert wave.crest_elevation == pytest.approx(float(wave.profile(0.0)), abs=1e-13)
    assert wave.trough_elevation == pytest.approx(float(wave.profile(math.pi)), abs=1e-13)
    # Fourier analysis of the profile on a uniform grid in x (DCT-I by a matrix).
    M = 2 * wave.n_modes
    x = math.pi * np.arange(M + 1) / M
    z = wave.profile(x)
    w = np.ones(M + 1)
    w[[0, M]] = 0.5
    n = np.arange(0, wave.n_modes + 1)
    a = (2.0 / M) * (np.cos(np.outer(n, x)) @ (w * z))
    assert abs(a[0] / 2) < 1e-12  # mean level
    np.testing.assert_allclose(a[1:], wave.coefficients, atol=1e-12)
    assert wave.alpha == wave.coefficients[0]
    # crest is the highest point, trough the lowest
    xs = np.linspace(-math.pi, math.pi, 2001)
    zs = wave.profile(xs)
    assert zs.max() == pytest.approx(wave.crest_elevation, abs=1e-13)
    assert zs.min() == pytest.approx(wave.trough_elevation, abs=1e-13)


@pytest.mark.parametrize("steepness", [0.05, 0.12])
def test_crest_curvature_by_finite_differences(steepness):
    wave = solve_stokes(steepness)
    estimates = []
    for h in (2e-3, 1e-3):
        z0, zh = wave.profile(0.0), wave.profile(h)
        estimates.append(-2 * (zh - z0) / h**2)
    richardson = (4 * estimates[1] - estimates[0]) / 3
    assert wave.crest_curvature == pytest.approx(float(richardson), rel=1e-6)
    # The Eulerian series says the same: κ = Σ n² k a_n at the crest (slope 0).
    n = np.arange(1, wave.n_modes + 1)
    assert wave.crest_curvature == pytest.approx(float(np.sum(n * n * wave.coefficients)), rel=1e-8)
    h = 1e-3
    trough = (wave.profile(math.pi + h) - wave.profile(math.pi)) * 2 / h**2
    assert wave.trough_curvature == pytest.approx(float(trough), rel=1e-4)
    assert 0 < wave.trough_curvature < wave.crest_curvature


def test_converged_to_1e_10_at_012():
    """Doubling the resolution changes nothing beyond 1e-10 (spec: converged up to H/λ = 0.12)."""
    auto = solve_stokes(0.12)
    fine = solve_stokes(0.12, n_modes=2 * auto.n_modes)
    assert auto.tail < 1e-13 and auto.residual < 1e-11
    assert abs(auto.speed - fine.speed) < 1e-12
    n = auto.n_modes
    assert np.max(np.abs(auto.coefficients - fine.coefficients[:n])) < 1e-12
    assert np.max(np.abs(fine.coefficients[n:])) < 1e-13
    assert auto.crest_curvature == pytest.approx(fine.crest_curvature, rel=1e-9)


def test_still_works_at_0135():
    wave = solve_stokes(0.135)
    assert wave.tail < 1e-13
    assert bernoulli_spread(wave) < 1e-10
    # steeper than Stokes' fourth-order wave at its crest: sharper crest, flatter trough
    assert wave.crest_curvature > 4 * float(series_crest_curvature(wave.alpha, 4))
    assert wave.crest_elevation > 0.55 * wave.height


def test_linear_limit_dispersion():
    """Small waves: c → √(g/k), a₁ → kH/2, the profile → a cosine."""
    wave = solve_stokes(1e-4)
    kH = 2 * math.pi * 1e-4
    assert wave.speed == pytest.approx(1.0, abs=1e-7)
    assert wave.alpha == pytest.approx(kH / 2, rel=1e-7)
    assert np.max(np.abs(wave.coefficients[1:])) < 1e-7


def test_still_water():
    wave = solve_stokes(0.0)
    assert wave.speed == 1.0 and wave.alpha == 0.0 and wave.crest_curvature == 0.0
    assert not np.any(wave.coefficients)


@pytest.mark.parametrize("shape", SHAPES)
def test_profile_shapes(shape):
    wave = solve_stokes(0.1)
    x = np.full(shape, 0.7)
    assert wave.profile(x).shape == shape
    np.testing.assert_allclose(wave.profile(x), float(wave.profile(0.7)), atol=1e-15)
    assert wave.series_profile(x).shape == shape
    # even and 2π-periodic
    assert float(wave.profile(-0.7)) == pytest.approx(float(wave.profile(0.7 + 2 * math.pi)), abs=1e-14)


def test_cached():
    assert solve_stokes(0.1) is solve_stokes(0.1)
    with pytest.raises(AttributeError):
        solve_stokes(0.1).speed = 2.0
    with pytest.raises(ValueError):
        solve_stokes(0.1).coefficients[0] = 1.0


@pytest.mark.parametrize("kwargs, message", [
    (dict(steepness=float("nan")), "steepness must be a finite number"),
    (dict(steepness=float("inf")), "steepness must be a finite number"),
    (dict(steepness=-0.01), "steepness must be in 0..0.141063"),
    (dict(steepness=STOKES_MAX_STEEPNESS + 1e-4), "steepness must be in 0..0.141063"),
    (dict(steepness=0.5), "highest"),
    (dict(steepness=0.1, n_modes=4), "n_modes must be in"),
    (dict(steepness=0.1, n_modes=32.0), "n_modes must be an integer"),
    (dict(steepness=0.1, map_parameter=0.0), r"map_parameter must be in \(0, 1\]"),
    (dict(steepness=0.1, map_parameter=float("nan")), "map_parameter must be a finite number"),
])
def test_solver_bad_input(kwargs, message):
    with pytest.raises(SunsetError, match=message):
        solve_stokes(**kwargs)


# --------------------------------------------------------------------------- the expansion vs the exact wave
def observed_order(exact, series, heights=(0.2, 0.1)):
    """log(err₁/err₂)/log(α₁/α₂) for the series' error against exact waves of two heights."""
    errs, alphas = [], []
    for kH in heights:
        wave = small_wave(kH)
        errs.append(abs(exact(wave) - series(wave.alpha)))
        alphas.append(wave.alpha)
    return math.log(errs[0] / errs[1]) / math.log(alphas[0] / alphas[1])


@pytest.mark.parametrize("n, order, expected", [
    (2, 2, 4),   # a₂ = α²/2 leaves O(α⁴)
    (2, 4, 6),   # a₂ = α²/2 + 17α⁴/24 leaves O(α⁶): the paper's 17/24 is right
    (3, 3, 5),   # a₃ = 3α³/8 leaves O(α⁵)
    (4, 4, 6),   # a₄ = α⁴/3 leaves O(α⁶)
])
def test_paper_coefficients_error_vanishes_at_the_next_order(n, order, expected):
    """With α = k a₁ of the exact wave, each truncation's error is O(α^(next power))."""
    p = observed_order(lambda w: w.coefficients[n - 1], lambda a: stokes_coefficients(a, order)[n - 1])
    assert p == pytest.approx(expected, abs=0.15)


def test_wrong_coefficient_would_be_caught():
    """Had the α⁴ term of a₂ been 1/3 (its value for ε = kH/2), the error would be O(α⁴)."""
    p = observed_order(lambda w: w.coefficients[1], lambda a: a * a / 2 + a**4 / 3)
    assert p == pytest.approx(4, abs=0.15)


@pytest.mark.parametrize("order, expected", [(1, 2), (2, 4), (4, 6)])
def test_series_speed_error_order(order, expected):
    p = observed_order(lambda w: w.speed, lambda a: series_speed(a, order))
    assert p == pytest.approx(expected, abs=0.15)


@pytest.mark.parametrize("order, expected", [(1, 2), (2, 3), (3, 4), (4, 5)])
def test_series_crest_curvature_error_order(order, expected):
    # The curvature's series has every power of α, so smaller waves keep the next
    # power's share of the error small (α <= 0.04).
    p = observed_order(lambda w: w.crest_curvature, lambda a: series_crest_curvature(a, order), (0.08, 0.04))
    assert p == pytest.approx(expected, abs=0.15)


def assert_close_each(actual, expected, atol):
    """|actual − expected| <= atol, element by element (atol may differ per element)."""
    err = np.abs(np.asarray(actual, float) - np.asarray(expected, float))
    assert np.all(err <= np.asarray(atol, float)), f"errors {err} exceed {atol}"


def test_expansion_fit_recovers_stokes_coefficients():
    """Fitted to exact waves, the expansion has Stokes' classical coefficients.

    k a₂ = α²/2 + 17α⁴/24, k a₃ = 3α³/8, k a₄ = α⁴/3, k a₅ = 125α⁵/384,
    c² = (g/k)(1 + α² + 5α⁴/4) (Stokes 1880; Lamb §250), and with ε = kH/2:
    k a₁ = ε − 3ε³/8, k a₂ = ε²/2 + ε⁴/3, c = 1 + ε²/2 + ε⁴/8. Tolerances: the
    fit's error grows by about 1e3 from one power to the next (α <= 0.1).
    """
    fit = expansion_fit()
    assert fit.alpha_max < 0.11
    assert_close_each(fit.a2[:2], [1 / 2, 17 / 24], [1e-10, 1e-7])
    assert_close_each(fit.a3[0], 3 / 8, 1e-9)
    assert_close_each(fit.a4[0], 1 / 3, 1e-8)
    assert_close_each(fit.a5[0], 125 / 384, 1e-6)
    assert_close_each(fit.speed[:3], [1, 1 / 2, 1 / 2], [1e-12, 1e-9, 1e-6])
    assert_close_each(fit.speed_squared[:3], [1, 1, 5 / 4], [1e-12, 1e-9, 1e-6])
    assert_close_each(fit.crest_curvature[:4], [1, 2, 27 / 8, 49 / 6], [1e-10, 1e-9, 1e-7, 1e-6])
    assert_close_each(fit.eps_a1[:2], [1, -3 / 8], [1e-12, 1e-9])
    assert_close_each(fit.eps_a2[:2], [1 / 2, 1 / 3], [1e-11, 1e-8])
    assert_close_each(fit.eps_speed[:3], [1, 1 / 2, 1 / 8], [1e-12, 1e-10, 1e-7])


@pytest.mark.parametrize("kwargs, message", [
    (dict(max_height=0.0), "max_height must be in"),
    (dict(max_height=float("nan")), "max_height must be a finite number"),
    (dict(terms=1), "terms must be in 2..8"),
    (dict(samples=3, terms=4), "samples must be in"),
])
def test_expansion_fit_bad_input(kwargs, message):
    with pytest.raises(SunsetError, match=message):
        expansion_fit(**kwargs)
