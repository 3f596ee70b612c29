"""Tests for sunset.model.series: Stokes' expansion by computer.

The reference is always an independent computation: exact Stokes waves from
:func:`sunset.stokes.solve_stokes` (Newton's method on collocated Babenko
equations, nothing in common with the recurrence but the physics), Babenko's
equation evaluated by FFT on the series' own surface, and the classical
coefficients of Stokes (1880) and the paper. Coefficients are checked by the
order at which the series' error against exact waves vanishes: a wrong
coefficient at power p leaves an error of order x^p.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

import sunset
from sunset.errors import SunsetError
from sunset.model.pade import pade_exact
from sunset.model.series import StokesSeries, domb_sykes, stokes_series
from sunset.model.stokes_exact import solve_stokes

#: H/λ of the highest wave (Williams 1981) and where the speed peaks (the exact solver, below).
HIGHEST_WAVE = 0.14106


def small_wave(kH: float):
    """An exact wave of small height on a plain grid: its conformal y_n are in u itself (L = 1)."""
    return solve_stokes(kH / (2 * math.pi), n_modes=48, map_parameter=1.0)


@pytest.fixture(scope="module")
def deep():
    """The exact series to order 70, for the continuation tests."""
    return stokes_series(70)


# --------------------------------------------------------------------------- the classical coefficients
def test_the_issue_example():
    assert stokes_series(8).amplitude(2)[4] == Fraction(17, 24)


def test_paper_coefficients_in_alpha():
    s = stokes_series(8)
    assert s.amplitude(1) == (0, 1) + (0,) * 7  # α = k a₁ by definition
    assert s.amplitude(2)[2] == Fraction(1, 2)
    assert s.amplitude(3)[3] == Fraction(3, 8)
    assert s.amplitude(4)[4] == Fraction(1, 3)
    assert s.amplitude(5)[5] == Fraction(125, 384)  # the trochoid's n^(n−2)/(2^(n−1)(n−1)!)
    assert s.speed()[:5] == (1, 0, Fraction(1, 2), 0, Fraction(1, 2))
    assert s.speed_squared()[:5] == (1, 0, 1, 0, Fraction(5, 4))
    assert s.crest_curvature()[:5] == (0, 1, 2, Fraction(27, 8), Fraction(49, 6))
    for n in range(1, 9):
        coeffs = s.amplitude(n)
        assert all(isinstance(c, Fraction) for c in coeffs)
        assert len(coeffs) == 9
        # a_n starts at α^n and has only powers of n's parity
        assert all(c == 0 for p, c in enumerate(coeffs) if p < n or (p - n) % 2)


def test_paper_coefficients_in_epsilon():
    """In ε = kH/2 the same wave reads k a₁ = ε − 3ε³/8, k a₂ = ε²/2 + ε⁴/3, c = 1 + ε²/2 + ε⁴/8."""
    s = stokes_series(8)
    assert s.amplitude(1, "epsilon")[:4] == (0, 1, 0, Fraction(-3, 8))
    assert s.amplitude(2, "epsilon")[:5] == (0, 0, Fraction(1, 2), 0, Fraction(1, 3))
    assert s.speed("epsilon")[:5] == (1, 0, Fraction(1, 2), 0, Fraction(1, 8))
    assert s.speed_squared("epsilon")[:5] == (1, 0, 1, 0, Fraction(1, 2))
    assert s.height("epsilon") == (0, 1) + (0,) * 7


def test_alpha_epsilon_round_trip():
    """ε(α) composed with α(ε) is the identity, exactly, to the order kept."""
    s = stokes_series(16)
    alpha_of_eps = s.amplitude(1, "epsilon")
    eps_of_alpha = s.height("alpha")
    P = 16
    out = [Fraction(0)] * (P + 1)
    power = [Fraction(1)] + [Fraction(0)] * P
    for j in range(1, P + 1):  # Σ_j α_j ε(α)^j, by plain polynomial products
        power = [sum(power[i] * eps_of_alpha[p - i] for i in range(p + 1)) for p in range(P + 1)]
        out = [o + alpha_of_eps[j] * q for o, q in zip(out, power)]
    assert out == [0, 1] + [0] * (P - 1)
    # and a quantity converted both ways agrees: c(α) = c(ε(α))
    c_eps = s.speed("epsilon")
    c_alpha = [Fraction(0)] * (P + 1)
    power = [Fraction(1)] + [Fraction(0)] * P
    for j in range(P + 1):
        if j:
            power = [sum(power[i] * eps_of_alpha[p - i] for i in range(p + 1)) for p in range(P + 1)]
        c_alpha = [o + c_eps[j] * q for o, q in zip(c_alpha, power)]
    assert tuple(c_alpha) == s.speed("alpha")


# --------------------------------------------------------------------------- against exact waves
@pytest.mark.parametrize("quantity", ["speed", "a1", "a2", "a3", "a4", "crest_curvature"])
def test_partial_sums_match_exact_small_waves(quantity):
    """All coefficients to order 24 at once: the partial sum at kH = 0.1 is the exact wave to 2e-14.

    (1e-13 for the crest curvature, whose sum Σ n² y_n the solver itself knows to a few 1e-14.)
    """
    s = stokes_series(24)
    tol = 1e-13 if quantity == "crest_curvature" else 2e-14
    for kH in (0.05, 0.1):
        w = small_wave(kH)
        exact = {"speed": w.speed, "crest_curvature": w.crest_curvature}.get(quantity)
        if exact is None:
            exact = w.coefficients[int(quantity[1:]) - 1]
        got = s.partial_sum(quantity, kH / 2, "epsilon")
        assert abs(got - exact) < tol * max(1.0, abs(exact)), (quantity, kH, got, exact)
        got_alpha = s.partial_sum(quantity, w.alpha, "alpha")
        assert abs(got_alpha - exact) < tol * max(1.0, abs(exact)), (quantity, kH, got_alpha, exact)


@pytest.mark.parametrize("quantity, parameter", [
    ("a2", "alpha"), ("a3", "alpha"), ("speed", "alpha"), ("crest_curvature", "alpha"),
    ("a1", "epsilon"), ("a2", "epsilon"), ("speed", "epsilon"),
])
def test_error_vanishes_at_the_next_order(quantity, parameter):
    """Truncated after power p, the error against exact waves falls like the first power dropped.

    Each coefficient is checked on its own: a wrong coefficient at power q <= p
    would leave an error of order x^q, whose slope the fit would see.
    """
    s = stokes_series(14)
    b = s.coefficients(quantity, parameter)
    p = 6
    dropped, following = [q for q in range(p + 1, 15) if b[q] != 0][:2]
    kHs = np.array([0.08, 0.1, 0.12, 0.14])
    xs, errs = [], []
    for kH in kHs:
        w = small_wave(kH)
        x = w.alpha if parameter == "alpha" else kH / 2
        exact = {"speed": w.speed, "crest_curvature": w.crest_curvature}.get(quantity)
        if exact is None:
            exact = w.coefficients[int(quantity[1:]) - 1]
        xs.append(x)
        errs.append(exact - s.partial_sum(quantity, x, parameter, terms=p))
    xs, errs = np.array(xs), np.array(errs)
    slope = np.polyfit(np.log(xs), np.log(np.abs(errs)), 1)[0]
    assert abs(slope - dropped) < 0.3, (quantity, parameter, slope, dropped)
    # and the error is the first two dropped terms, to the order after them
    lead = float(b[dropped]) * xs**dropped + float(b[following]) * xs**following
    np.testing.assert_allclose(errs, lead, rtol=0.05)


def test_conformal_coefficients_match_the_solver():
    """y_n of the conformal surface, summed from the series, against the solver's own y_n (L = 1)."""
    s = stokes_series(24)
    for kH in (0.1, 0.2):
        w = small_wave(kH)
        for n in range(0, 8):
            got = np.polynomial.polynomial.polyval(kH / 2, [float(c) for c in s.conformal(n)])
            assert abs(got - w.conformal[n]) < 1e-14, (kH, n, got, w.conformal[n])


def test_series_surface_satisfies_babenko():
    """Babenko's equation, evaluated by FFT on the surface the series gives, vanishes to the order kept."""
    s = stokes_series(16)
    M = 256
    u = 2 * np.pi * np.arange(M) / M
    k = np.abs(np.fft.fftfreq(M, 1.0 / M))
    residuals = []
    for eps in (0.05, 0.1):
        y = sum(np.polynomial.polynomial.polyval(eps, [float(c) for c in s.conformal(n)]) * np.cos(n * u)
                for n in range(17))
        c2 = np.polynomial.polynomial.polyval(eps, [float(c) for c in s.speed_squared("epsilon")])

        def K(f):
            return np.real(np.fft.ifft(k * np.fft.fft(f)))

        Ky = K(y)
        residuals.append(np.max(np.abs(c2 * Ky - y - y * Ky - 0.5 * K(y * y))))
        wrong_speed = np.max(np.abs(c2 * (1 + 1e-9) * Ky - y - y * Ky - 0.5 * K(y * y)))
        assert wrong_speed > 1e-12  # the check can see a speed off by 1e-9
        assert abs(y[0] - y[M // 2] - 2 * eps) < 1e-15  # the height is exactly 2ε
    # what is left is the truncation: it falls like a high power of ε (the 17th, less round-off)
    assert residuals[0] < 1e-14 and residuals[1] / residuals[0] > 2**14


def test_float_matches_exact_to_order_30():
    exact, floats = stokes_series(30), stokes_series(30, exact=False)
    for quantity in ("speed", "crest_curvature", "a1", "a2", "a3"):
        for parameter in ("alpha", "epsilon", "omega"):
            e = np.array([float(v) for v in exact.coefficients(quantity, parameter)])
            f = np.array(floats.coefficients(quantity, parameter))
            assert all(isinstance(v, float) for v in floats.coefficients(quantity, parameter))
            scale = np.maximum(np.abs(e), 1e-300)
            assert np.all(np.abs(f - e) <= 1e-9 * scale + 1e-6 * (e == 0)), (quantity, parameter)


def test_float_reaches_order_100():
    s = stokes_series(100, exact=False)
    c = np.array(s.speed("epsilon"))
    assert len(c) == 101 and np.all(np.isfinite(c))
    assert np.all(c[1::2] == 0) and np.all(c[0::2] != 0)


# --------------------------------------------------------------------------- continuation
@pytest.mark.parametrize("steepness, tol", [(0.12, 1e-9), (0.135, 2e-6)])
def test_pade_matches_the_exact_solver(deep, steepness, tol):
    w = solve_stokes(steepness)
    sw = deep.at_steepness(steepness, n_amplitudes=4)
    assert abs(sw.speed - w.speed) < tol
    np.testing.assert_allclose(sw.amplitudes, w.coefficients[:4], rtol=0, atol=tol)
    assert abs(sw.crest_curvature - w.crest_curvature) < tol * max(1.0, w.crest_curvature)
    assert sw.alpha == sw.amplitudes[0]


def test_partial_sums_in_alpha_fail_where_pade_holds(deep):
    """At H/λ = 0.135 α is at its maximum, the branch point of every series in α."""
    w = solve_stokes(0.135)
    in_alpha = abs(deep.partial_sum("speed", w.alpha, "alpha") - w.speed)
    pade = abs(deep.at_steepness(0.135).speed - w.speed)
    assert in_alpha > 1e-4 and pade < 1e-7


def test_highest_wave_and_speed_maximum_from_the_series(deep):
    """From the exact approximants of order 70: the highest wave to 3e-5 (Williams 1981), the fastest to 1e-6.

    (The float64 solution of the same Padé system gave 0.14042 on an AVX-512
    machine and passed a 3e-4 tolerance on others: round-off, which kernels decide.)
    """
    assert abs(deep.highest_wave() - HIGHEST_WAVE) < 3e-5
    # the exact solver's fastest wave
    s_grid = np.linspace(0.1380, 0.1395, 16)
    speeds = [solve_stokes(s).speed for s in s_grid]
    i = int(np.argmax(speeds))
    steepness, speed = deep.speed_maximum()
    assert abs(steepness - s_grid[i]) < 1e-4  # one step of the grid
    assert abs(speed - speeds[i]) < 1e-6
    assert speed > solve_stokes(0.14).speed + 1e-4  # the highest wave is not the fastest


def test_the_exact_approximant_satisfies_its_definition(deep):
    """The [35/35] approximant behind highest_wave: q·ε(ω) − p vanishes through ω⁷⁰, in Fractions."""
    f = deep.height("omega")
    p, q = pade_exact(f, 35, 35).fractions()
    assert len(p) == len(q) == 36 and q[0] == 1
    qf = [sum(q[j] * f[k - j] for j in range(min(k, 35) + 1)) for k in range(71)]
    assert qf[:36] == list(p) and all(c == 0 for c in qf[36:])
    assert deep.highest_wave() == float(sum(p) / sum(q)) / math.pi  # p(1)/q(1), rounded once
    assert deep.highest_wave(70) == deep.highest_wave()
    # rounding the 71 coefficients to float64 (relative changes <= 1.1e-16) moves the answer by 1e-4
    rounded = pade_exact([float(c) for c in f], 35, 35)
    assert abs(float(rounded(1)) / math.pi - deep.highest_wave()) > 5e-5


@pytest.mark.parametrize("quantity, parameter", [
    ("speed", "epsilon"), ("a2", "epsilon"), ("crest_curvature", "epsilon"), ("height", "omega"),
    ("speed", "omega"), ("speed", "alpha"), ("a3", "alpha"),
])
def test_exact_and_float_continuations_agree_at_low_order(quantity, parameter):
    """Order 16, where float64 solves the Padé system well: exact and float series' approximants agree."""
    exact, floats = stokes_series(16), stokes_series(16, exact=False)
    x = {"epsilon": np.array([0.1, 0.3, 0.42]), "omega": np.array([0.2, 0.6, 1.0]),
         "alpha": np.array([0.1, 0.2, 0.28])}[parameter]
    e, f = exact.pade(quantity, x, parameter), floats.pade(quantity, x, parameter)
    np.testing.assert_allclose(e, f, rtol=1e-11, atol=1e-14)
    assert np.all(np.abs(e - exact.partial_sum(quantity, x, parameter)) > 0)  # not the partial sum


def test_domb_sykes_finds_alpha_max(deep):
    """The series in α stop at the largest α of the exact waves: a square-root branch point."""
    alpha_max = max(solve_stokes(s).alpha for s in np.linspace(0.134, 0.136, 9))
    d = domb_sykes(deep.height("alpha"), stride=2, shift=1, fit_last=10)
    assert abs(d.radius - alpha_max) < 2e-3
    assert abs(d.exponent - 0.5) < 0.15
    assert abs(domb_sykes(deep.speed("alpha"), stride=2).radius - alpha_max) < 2e-3


def test_domb_sykes_on_a_known_function():
    """(1 − x/2)^(1/2): radius 2, exponent 1/2; and (1 + x²/4)^(−1): radius −2 in x², i.e. on the imaginary axis."""
    b = [Fraction(1)]
    for k in range(1, 60):  # binomial series of (1 − t)^(1/2), t = x/2
        b.append(b[-1] * (k - 1 - Fraction(1, 2)) / k)
    coeffs = [float(c) / 2**k for k, c in enumerate(b)]
    d = domb_sykes(coeffs, fit_last=20)
    assert abs(d.radius - 2) < 1e-3 and abs(d.exponent - 0.5) < 1e-2
    alt = [(-0.25) ** (k // 2) if k % 2 == 0 else 0.0 for k in range(60)]
    d = domb_sykes(alt, stride=2)
    assert abs(d.radius + 2) < 1e-9
    with pytest.raises(SunsetError, match="zero"):
        domb_sykes(alt, stride=1)


@pytest.mark.parametrize("coefficients, kwargs, words", [
    ([1.0], {}, "needs at least 3 coefficients, got 1"),
    ([1.0, 0.5], {"fit_last": 2}, "needs at least 3 coefficients, got 2"),
    ([1.0, 0.5, 0.25, 0.125], {}, r"^domb_sykes: 4 coefficients, 4 after stride 1 and shift 0, give 3 "
                                     r"ratios, fewer than the fit_last = 10 fitted: pass more coefficients"),
    ([1.0] * 20, {"stride": 3, "fit_last": 10}, r"20 coefficients, 7 after stride 3 and shift 0, give 6 ratios"),
    ([1.0] * 20, {"fit_last": 10**5000}, r"fit_last = an integer of"),
    ([1.0] * 20, {"fit_last": "3"}, r"fit_last must be an integer, got 3 \(str\)"),
])
def test_domb_sykes_says_what_is_short(coefficients, kwargs, words):
    """Too few coefficients are named as such, not as a fit_last the caller never passed (issue 33)."""
    with pytest.raises(SunsetError, match=words):
        domb_sykes(coefficients, **kwargs)


# --------------------------------------------------------------------------- API and bad input
def test_public_api_and_cache():
    assert sunset.stokes_series is stokes_series
    assert stokes_series(6) is stokes_series(6)
    assert isinstance(stokes_series(6), StokesSeries)
    assert "order=6" in repr(stokes_series(6))


@pytest.mark.parametrize("order", [0, -3, float("nan"), 2.5, True, "8", None, 10**6, 81])
def test_bad_order(order):
    with pytest.raises(SunsetError, match="order") as info:
        stokes_series(order)
    assert "\n" not in str(info.value)


def test_float_order_limit():
    with pytest.raises(SunsetError, match="order"):
        stokes_series(401, exact=False)


@pytest.mark.parametrize("call, message", [
    (lambda s: s.amplitude(0), "n must be"),
    (lambda s: s.amplitude(9), "n must be"),
    (lambda s: s.amplitude(2, "beta"), "parameter"),
    (lambda s: s.coefficients("height of the crest"), "unknown quantity"),
    (lambda s: s.pade("speed", float("nan")), "x must be"),
    (lambda s: s.partial_sum("speed", 0.1, terms=9), "terms"),
    (lambda s: s.at_steepness(0.2), "steepness"),
    (lambda s: s.at_steepness(-0.01), "steepness"),
])
def test_bad_arguments(call, message):
    with pytest.raises(SunsetError, match=message) as info:
        call(stokes_series(8))
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("shape", [(), (6,), (2, 3), (2, 3, 1)])
def test_pade_and_partial_sum_shapes(shape):
    s = stokes_series(12)
    x = np.full(shape, 0.2)
    assert np.shape(s.pade("speed", x)) == shape
    assert np.shape(s.partial_sum("a2", x)) == shape
    np.testing.assert_allclose(s.pade("speed", x), float(s.pade("speed", 0.2)))


def test_bench_times_the_series():
    """The bench's series measurement (timing is never asserted, only what is measured)."""
    from sunset.bench import series as stokes_bench

    out = stokes_bench.measure_series(0, 0, 1, orders=((6, True), (8, False)))
    assert set(out) == {"order 6, exact", "order 8, float64"}
    assert all(len(v) == 1 and v[0] >= 0 for v in out.values())
    assert (30, True) in stokes_bench.SERIES_ORDERS
    assert any(o >= 100 and not e for o, e in stokes_bench.SERIES_ORDERS)
    rows = stokes_bench.rows({"times": out, "peak_rss_mib": 1.0})
    assert [r["median_s"] for r in rows] == [v[0] for v in out.values()]
    assert "order 6, exact" in stokes_bench.format_rows(rows)


@pytest.mark.parametrize("exact", [True, False])
def test_pade_of_a_series_that_ends_is_the_series(exact):
    """The height in ε is ε itself: Padé's system is singular, and the approximant is the polynomial."""
    s = stokes_series(12, exact=exact)
    x = np.array([0.0, 0.1, 0.3, 0.44])
    np.testing.assert_allclose(s.pade("height", x, "epsilon"), x, rtol=1e-15, atol=0)


_S6 = None


def _s6():
    global _S6
    _S6 = _S6 or stokes_series(6)
    return _S6


@pytest.mark.parametrize("call, words", [
    (lambda: solve_stokes(0.05).surface(10**9), r"^n_points must be in 3\.\.65536, got 1000000000"),
    (lambda: _s6().at_steepness(0.1411), r"^steepness must be in 0\.\.0\.141063 \(H/λ of the highest wave"),
    (lambda: solve_stokes(0.1411), r"^steepness must be in 0\.\.0\.141063"),
    (lambda: _s6().at_steepness(0.1, n_amplitudes=17), r"^n_amplitudes must be in 1\.\.6"),
    (lambda: _s6().pade("speed", 1e300), r"^x must lie in \[-1, 1\]"),
    (lambda: _s6().partial_sum("speed", -1e300), r"^x must lie in \[-1, 1\]"),
    (lambda: pade_exact([1, 2], 1, 1), r"needs the 3 coefficients of x\^0 \.\. x\^2, got 2"),
    (lambda: pade_exact(["a", 1, 1], 1, 1), r"^coefficient 0 must be a number"),
    (lambda: domb_sykes([1.0, 2.0]), r"needs at least 3 coefficients, got 2"),
    (lambda: solve_stokes("0.1"), r"^steepness must be a number .* \(str\)"),
    (lambda: stokes_series("6"), r"^order must be an integer, got 6 \(str\)"),
    (lambda: stokes_series(6, exact="no"), r"^exact must be True or False, got no \(str\)"),
    (lambda: solve_stokes(0.1, n_modes=4096), r"^n_modes must be in 16\.\.1024"),
    (lambda: stokes_series(81), r"^order must be in 1\.\.80"),
    (lambda: stokes_series(401, exact=False), r"^order must be in 1\.\.400"),
    (lambda: stokes_series(10**9), r"^order must be in 1\.\.80"),
])
def test_the_stokes_api_refuses_what_would_run_for_minutes_or_leak(call, words):
    """Issue 33's Stokes cases, each a one-line SunsetError within a second (surface(10**9) ran until killed,
    at_steepness took 0.1411 past the highest wave, pade(…, 1e300) leaked OverflowError, exact='no' meant exact)."""
    import time

    _s6()
    start = time.perf_counter()
    with pytest.raises(SunsetError, match=words) as info:
        call()
    assert "\n" not in str(info.value) and time.perf_counter() - start < 1.0
