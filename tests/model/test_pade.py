"""Padé approximants (sunset.model.series.pade_coefficients), checked against their definition and a closed form.

SciPy 1.18 deprecates ``scipy.interpolate.pade`` (removed in 1.20), and the
locks pin SciPy 1.18 on Python 3.12 and later, where its DeprecationWarning
failed the suite: the package builds the approximant itself.
"""

import math
import warnings

import numpy as np
import pytest
import scipy.interpolate

from sunset.errors import SunsetError
from sunset.model.series import pade_coefficients, stokes_series


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
