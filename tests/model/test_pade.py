"""Padé approximants (sunset.model.pade), checked against their definition and closed forms.

SciPy 1.18 deprecates ``scipy.interpolate.pade`` (removed in 1.20), and the
locks pin SciPy 1.18 on Python 3.12 and later, where its DeprecationWarning
failed the suite: the package builds the float64 approximant itself
(``pade_coefficients``), and the exact one (``pade_exact``) in rationals.
"""

import math
import warnings
from fractions import Fraction

import numpy as np
import pytest
import scipy.interpolate

from sunset.errors import SunsetError
from sunset.model.pade import pade_coefficients, pade_exact
from sunset.model.series import stokes_series


def test_exp_2_2_is_the_closed_form():
    """[2/2] of eˣ is (1 + x/2 + x²/12) / (1 − x/2 + x²/12)."""
    p, q = pade_coefficients([1 / math.factorial(k) for k in range(5)], 2, 2)
    np.testing.assert_allclose(p.coeffs[::-1], [1, 1 / 2, 1 / 12], rtol=0, atol=1e-15)
    np.testing.assert_allclose(q.coeffs[::-1], [1, -1 / 2, 1 / 12], rtol=0, atol=1e-15)


@pytest.mark.parametrize("m, n", [(0, 3), (1, 1), (2, 3), (3, 2), (4, 4), (5, 0)])
def test_q_times_f_minus_p_vanishes_through_order_m_plus_n(m, n):
    """The definition: the Taylor coefficients of q·f − p are 0 up to x^(m+n); deg p <= n, deg q <= m, q(0) = 1."""
    rng = np.random.default_rng(7 * m + n)
    an = rng.normal(size=m + n + 3)
    p, q = pade_coefficients(an, m, n)
    assert p.order <= n and q.order <= m
    assert q.coeffs[-1] == 1.0
    qc = np.zeros(m + 1)
    qc[: len(q.coeffs)] = q.coeffs[::-1]
    pc = np.zeros(m + n + 1)
    pc[: len(p.coeffs)] = p.coeffs[::-1]
    residual = np.convolve(qc, an[: m + n + 1])[: m + n + 1] - pc
    np.testing.assert_allclose(residual, 0.0, atol=1e-10 * np.abs(an).max() * max(1.0, np.abs(qc).max()))


def test_the_same_bits_as_scipy_while_scipy_has_it():
    scipy_pade = getattr(scipy.interpolate, "pade", None)
    if scipy_pade is None:
        pytest.skip("SciPy >= 1.20 has no scipy.interpolate.pade to compare with")
    an = stokes_series(12)._float("speed", "epsilon", 12)[0::2] * 3.0 ** np.arange(7)
    for m, n in [(3, 3), (2, 4), (0, 6)]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            sp, sq = scipy_pade(an, m, n)
        p, q = pade_coefficients(an, m, n)
        assert np.array_equal(p.coeffs, sp.coeffs) and np.array_equal(q.coeffs, sq.coeffs)


@pytest.mark.parametrize("m, n", [(3, 3), (-1, 2), (2, -1)])
def test_too_few_coefficients_or_negative_degrees(m, n):
    with pytest.raises(SunsetError, match="Padé"):
        pade_coefficients([1.0, 2.0, 3.0, 4.0], m, n)


# --------------------------------------------------------------------------- exact approximants
def qf_minus_p(an, p, q):
    """The Taylor coefficients of q·f − p through the order of ``an``, in Fractions."""
    return [sum(q[j] * an[k - j] for j in range(min(k, len(q) - 1) + 1)) - (p[k] if k < len(p) else 0)
            for k in range(len(an))]


def test_exact_exp_2_2_is_the_closed_form():
    p, q = pade_exact([Fraction(1, math.factorial(k)) for k in range(5)], 2, 2).fractions()
    assert p == (1, Fraction(1, 2), Fraction(1, 12)) and q == (1, Fraction(-1, 2), Fraction(1, 12))
    assert all(isinstance(c, Fraction) for c in p + q)


@pytest.mark.parametrize("m, n, digits", [(1, 1, 3), (3, 2, 5), (6, 6, 20), (12, 11, 40)])
def test_exact_q_times_f_minus_p_vanishes_through_order_m_plus_n(m, n, digits):
    """The definition, in Fractions: long random fractions need many primes (several rounds of them)."""
    rng = np.random.default_rng(100 * m + n)
    big = 10**digits

    def draw():
        return int(rng.integers(1, 10**9)) * big // int(rng.integers(1, 10**9)) - big // 2

    an = [Fraction(draw(), abs(draw()) + 1) for _ in range(m + n + 2)]
    p, q = pade_exact(an, m, n).fractions()
    assert len(p) == n + 1 and len(q) == m + 1 and q[0] == 1
    residual = qf_minus_p(an, p, q)
    assert all(r == 0 for r in residual[: m + n + 1])
    assert residual[m + n + 1] != 0  # one order more is not matched: the check above can fail


def test_exact_agrees_with_float64_where_float64_is_well_conditioned():
    """Low order (the speed's series in ε², order 12, rescaled): the float64 solve is good to 1e-13."""
    an = [float(c) * 0.44 ** (2 * k) for k, c in enumerate(stokes_series(12).speed("epsilon")[0::2])]
    for m, n in [(3, 3), (2, 4), (1, 2)]:
        fp, fq = pade_coefficients(an, m, n)
        p, q = pade_exact(an, m, n).fractions()
        np.testing.assert_allclose([float(c) for c in p], fp.coeffs[::-1], rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose([float(c) for c in q], fq.coeffs[::-1], rtol=1e-13, atol=1e-15)


def test_levinson_and_elimination_agree(monkeypatch):
    """The two solvers modulo primes, each on its own, give the same (verified) approximant."""
    import sunset.model.pade as pade

    an = [Fraction(int(k**3) - 40, int(k**2) + 3) for k in range(25)]
    fast = pade_exact(an, 12, 12)
    levinson = pade._levinson
    monkeypatch.setattr(pade, "_levinson", lambda g, m, n, p: (levinson(g, m, n, p)[0], np.zeros(len(p), bool)))
    assert pade_exact(an, 12, 12) == fast


def test_exact_with_a_vanishing_leading_minor():
    """a₁ = 0 stops Levinson's recursion at its first step; elimination with pivoting solves the system."""
    an = [Fraction(1), Fraction(0), Fraction(2), Fraction(3), Fraction(5, 7)]
    p, q = pade_exact(an, 2, 1).fractions()
    assert len(q) == 3 and all(r == 0 for r in qf_minus_p(an[:4], p, q))
    p, q = pade_exact(an, 2, 2).fractions()
    assert len(q) == 3 and all(r == 0 for r in qf_minus_p(an, p, q))


def test_exact_singular_systems_lower_the_denominator():
    assert pade_exact([1, 2, 0, 0, 0], 2, 2).fractions() == ((1, 2, 0), (1,))  # a polynomial is its own
    assert pade_exact([1, 0, 1], 1, 1).fractions() == ((1, 0), (1,))  # [1/1] of 1 + x² does not exist


def test_exact_takes_floats_as_the_binary_fractions_they_are():
    an = [0.1, -0.3, 0.7, 1e-3, 2.5]
    assert pade_exact(an, 2, 2) == pade_exact([Fraction(v) for v in an], 2, 2)


def test_exact_values():
    geometric = pade_exact([1, 1, 1, 1], 1, 1)  # 1/(1 − x), exactly
    assert geometric.fractions() == ((1, 0), (1, -1))
    assert geometric(Fraction(1, 3)) == Fraction(3, 2) and geometric(0.5) == 2
    with pytest.raises(SunsetError, match="pole"):
        geometric(1)


def test_lehmer_stops_where_euclid_stops():
    """Wang's reconstruction by Lehmer's method: the same remainder and cofactor as plain Euclid."""
    from sunset.model.pade import _half_euclid

    rng = np.random.default_rng(3)
    for bits in (40, 700, 5000):
        M = int.from_bytes(rng.bytes(bits // 8), "big") | 1
        y = int.from_bytes(rng.bytes(bits // 8), "big") % M
        bound = math.isqrt(M // 2)
        r0, r1, t0, t1 = M, y, 0, 1
        while r1 > bound:
            q = r0 // r1
            r0, r1, t0, t1 = r1, r0 - q * r1, t1, t0 - q * t1
        assert _half_euclid(M, y, bound) == (r1, t1)


def test_the_primes_are_primes():
    from sunset.model.pade import _primes

    p = _primes(40).tolist()
    assert len(set(p)) == 40 and all(2**30 < q < 2**31 for q in p)
    assert all(all(q % d for d in range(3, math.isqrt(q) + 1, 2)) for q in p[::8])  # trial division


@pytest.mark.parametrize("m, n", [(3, 3), (-1, 2), (2, -1)])
def test_exact_too_few_coefficients_or_negative_degrees(m, n):
    with pytest.raises(SunsetError, match="Padé"):
        pade_exact([1, 2, 3, 4], m, n)
