"""The compiled kernels' own float32 sine and cosine (sunset/vector/sincos_numba.py) against the C library's, in ulp.

The reference is the float64 ``math.cos`` and ``math.sin`` of the C library
(correctly rounded to far below a float32's ulp), taken in a compiled loop;
the error of a float32 result is counted in units of the float32 spacing at
the true value. Within ``LIMIT`` the functions must stay within ``MAX_ULP``
over every binade, at the floats nearest the multiples of π/2 (where the
result is small and the reduction's accuracy shows) and on the quadrant
boundaries; beyond it, and for infinities and NaN, they are the C library's
``cosf`` and ``sinf``.
"""

import math
from fractions import Fraction

import numpy as np
import pytest

pytest.importorskip("numba")

from sunset.kernels import jit  # noqa: E402
from sunset.vector import sincos_numba as S  # noqa: E402


@jit
def _libm64(x, c, s):
    for i in range(x.shape[0]):
        c[i] = math.cos(np.float64(x[i]))
        s[i] = math.sin(np.float64(x[i]))


@jit
def _libm32(x, c, s):
    for i in range(x.shape[0]):
        c[i] = math.cos(x[i])
        s[i] = math.sin(x[i])


def ulp_error(got, want64):
    """|got − want| in float32 ulp at the true value ``want64`` (float64)."""
    spacing = np.spacing(np.abs(want64).astype(np.float32)).astype(np.float64)
    return np.abs(got.astype(np.float64) - want64) / spacing


def reference(x):
    c, s = np.empty(x.shape), np.empty(x.shape)
    _libm64(x, c, s)
    return c, s


def ours(x):
    s, c = np.empty_like(x), np.empty_like(x)
    S.sincos_into(x, s, c)
    return c, s


def near_multiples_of_half_pi(top, count):
    """The float32s nearest k·π/2 for k up to top·2/π (both neighbours), k exact in Fraction arithmetic."""
    k = np.unique(np.linspace(1, int(top / (math.pi / 2)), count).astype(np.int64))
    half_pi = Fraction(math.pi) / 2        # math.pi's own error (1e-16) is far below a float32's spacing
    x = np.array([float(kk * half_pi) for kk in k], np.float32)
    return np.concatenate([x, np.nextafter(x, np.float32(0)), np.nextafter(x, np.float32(np.inf))])


@pytest.mark.parametrize("top", [1.0, 10.0, 1e3, 3e4, float(S.LIMIT)])
def test_within_max_ulp_of_the_c_library(top):
    rng = np.random.default_rng(int(top))
    x = np.concatenate([rng.uniform(-top, top, 200_000), near_multiples_of_half_pi(top, 20_000)]).astype(np.float32)
    x = x[np.abs(x) <= S.LIMIT]
    want_c, want_s = reference(x)
    got_c, got_s = ours(x)
    err = max(ulp_error(got_c, want_c).max(), ulp_error(got_s, want_s).max())
    assert err <= S.MAX_ULP
    # the bound is not loose: it is within a quarter ulp of what is measured over the whole range
    if top == float(S.LIMIT):
        assert err > S.MAX_ULP - 0.25


def test_the_array_and_scalar_forms_agree():
    x = np.random.default_rng(3).uniform(-5e4, 5e4, 5000).astype(np.float32)
    c, s = ours(x)
    out = np.empty_like(x)
    np.testing.assert_array_equal(S.cos_into(x, out), c)
    assert all(S.cos32(v) == cv and S.sin32(v) == sv for v, cv, sv in zip(x[:300], c[:300], s[:300]))
    y = x.copy()
    S.cos_into(y, y)                             # in place
    np.testing.assert_array_equal(y, c)


@pytest.mark.parametrize("odd", [np.float32(2e5), np.float32(-3e9), np.float32(np.inf), np.float32(np.nan)])
def test_beyond_the_limit_it_is_the_c_librarys_float32_functions(odd):
    x = np.linspace(-500, 500, 1001, dtype=np.float32)
    x[17] = odd
    want_c, want_s = np.empty_like(x), np.empty_like(x)
    _libm32(x, want_c, want_s)
    got_c, got_s = ours(x)
    assert np.array_equal(got_c[17], want_c[17], equal_nan=True) and np.array_equal(got_s[17], want_s[17],
                                                                                  equal_nan=True)
    # the other elements are ours as before
    rest = np.delete(x, 17)
    c, s = ours(rest)
    np.testing.assert_array_equal(np.delete(got_c, 17), c)
    np.testing.assert_array_equal(np.delete(got_s, 17), s)
    y = x.copy()
    S.cos_into(y, y)
    assert np.array_equal(y, got_c, equal_nan=True)


def test_exact_values():
    x = np.array([0.0, -0.0, 1e-30, -1e-30], np.float32)
    c, s = ours(x)
    np.testing.assert_array_equal(c, 1.0)
    np.testing.assert_array_equal(s, x)          # −0 may come back as +0
    assert ours(np.zeros(0, np.float32))[0].shape == (0,)


def test_the_split_of_half_pi():
    a, b, c = S.split()
    # A has 20 significant bits, so that q·A is exact for the quotients the reduction meets
    assert Fraction(a) * 2**19 == int(Fraction(a) * 2**19)
    assert np.float32(b) == b and np.float32(c) == c
    # their sum is π/2 to 2⁻⁷⁰ (π from its 60 digits)
    err = abs(Fraction(a) + Fraction(b) + Fraction(c) - S._PI / 2)
    assert err < Fraction(1, 2**70)


def test_the_ulp_measure_sees_a_two_ulp_error():
    # the comparison can fail: a result nudged by two float32 steps is over MAX_ULP
    x = np.random.default_rng(5).uniform(-100, 100, 1000).astype(np.float32)
    c, _ = ours(x)
    want, _ = reference(x)
    bad = c.copy()
    bad[500] = np.nextafter(np.nextafter(bad[500], np.float32(2)), np.float32(2))
    assert ulp_error(bad, want).max() > S.MAX_ULP >= ulp_error(c, want).max()


# --------------------------------------------------------------------------- float64

def ulp64_error(got, want):
    """|got − want| in float64 ulp at the true value ``want`` (long double, 64-bit mantissa on x86)."""
    spacing = np.spacing(np.abs(want).astype(np.float64)).astype(np.longdouble)
    return (np.abs(got.astype(np.longdouble) - want) / spacing).astype(np.float64)


def ours64(x):
    s, c = np.empty_like(x), np.empty_like(x)
    S.sincos64_into(x, s, c)
    return c, s


@pytest.mark.skipif(np.finfo(np.longdouble).nmant < 63, reason="the reference needs an 80-bit long double")
@pytest.mark.parametrize("top", [1.0, 10.0, 1e3, 3e4, S.LIMIT64])
def test_float64_within_max_ulp_of_the_long_double_functions(top):
    rng = np.random.default_rng(int(top) + 1)
    k = np.unique(np.linspace(1, int(top / (math.pi / 2)) + 1, 5000).astype(np.int64))
    near = np.array([float(kk * S._PI / 2) for kk in k])
    x = np.concatenate([rng.uniform(-top, top, 200_000), near, np.nextafter(near, 0), np.nextafter(near, np.inf)])
    x = x[np.abs(x) <= S.LIMIT64]
    got_c, got_s = ours64(x)
    xl = x.astype(np.longdouble)
    err = max(ulp64_error(got_c, np.cos(xl)).max(), ulp64_error(got_s, np.sin(xl)).max())
    assert err <= S.MAX_ULP64
    # the measure sees a three-ulp error
    bad = got_c.copy()
    bad[7] = np.nextafter(np.nextafter(np.nextafter(bad[7], 2.0), 2.0), 2.0)
    assert ulp64_error(bad, np.cos(xl)).max() > S.MAX_ULP64


@pytest.mark.parametrize("odd", [2.0**21, -3e300, np.inf, np.nan])
def test_float64_beyond_the_limit_is_the_c_library_and_scalar_agrees(odd):
    x = np.linspace(-500, 500, 1001)
    x[17] = odd
    c, s = ours64(x)
    assert np.array_equal(c[17], math.cos(odd) if np.isfinite(odd) else np.nan, equal_nan=True)
    assert np.array_equal(s[17], math.sin(odd) if np.isfinite(odd) else np.nan, equal_nan=True)
    c2, s2 = ours64(np.delete(x, 17))
    np.testing.assert_array_equal(np.delete(c, 17), c2)
    assert all(S.sincos64(v) == (sv, cv) for v, cv, sv in zip(x[20:300], c[20:300], s[20:300]))


def test_the_float64_split_of_half_pi():
    a, b, c = S.split64()
    # A has 33 significant bits, so that q·A is exact for the quotients below LIMIT64 (q < 2²⁰)
    assert (Fraction(a) * 2**32).denominator == 1 and S.LIMIT64 * 2 / math.pi < 2**20
    err = abs(Fraction(a) + Fraction(b) + Fraction(c) - S._PI / 2)
    assert err < Fraction(1, 2**125)
