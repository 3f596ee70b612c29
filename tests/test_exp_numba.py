"""The compiled float64 exp (sunset/exp_numba.py) against NumPy's ``np.exp`` and the C library's, bit for bit.

Which ``exp`` NumPy takes depends on the CPU: SVML's on x86 with AVX-512, the
C library's elsewhere. Where the probe picks SVML's, the replica must give
``np.exp``'s exact bits on arguments it never saw (random, random bit
patterns, the paths' edges, denormal and zero results); where it picks the
C library's, that is checked against ``np.exp`` directly and the replica must
still be a correct exp (within 1 ulp of ``math.exp``). The tables are checked
against decimal arithmetic, and a replica one ulp off is caught by the probe.
"""

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest

numba = pytest.importorskip("numba")

from sunset import exp_numba as E  # noqa: E402


def u64(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def ulps(a, b):
    """Distance in units in the last place between same-signed finite doubles."""
    return np.abs(u64(a).astype(np.int64) - u64(b).astype(np.int64))


def arguments(seed):
    """Arguments the probe never saw: every range the sky's exps take and the whole domain."""
    rng = np.random.default_rng(seed)
    pieces = [rng.uniform(-800.0, 800.0, 400_000), rng.uniform(-2.0, 2.0, 200_000),
              rng.uniform(-745.3, -707.0, 200_000), rng.uniform(707.0, 710.0, 50_000),
              -np.exp(rng.uniform(-35.0, 8.0, 200_000)), rng.uniform(-1e-15, 1e-15, 20_000),
              rng.integers(0, 2 ** 64, 300_000, dtype=np.uint64).view(np.float64)]
    x = np.concatenate(pieces)
    return x[~np.isnan(x)]


def test_the_probe_finds_the_exp_numpy_uses():
    """The choice is one of the two, and it is the one that gives np.exp's bits on fresh arguments."""
    which = E.choice()
    assert which in (E.LIBM, E.SVML)
    x = arguments(1)
    with np.errstate(all="ignore"):
        want = np.exp(x)
    got = E.exp_into(x, which)
    assert np.array_equal(u64(got), u64(want))
    if which == E.SVML:
        # SVML's exp is not the C library's: here the choice mattered
        assert not np.array_equal(u64(E.exp_into(x, E.LIBM)), u64(want))
    else:
        # where NumPy calls the C library, math.exp is it, argument by argument
        small = x[np.abs(x) < 700.0][:20_000]
        assert np.array_equal(u64([math.exp(v) for v in small]), u64(np.exp(small)))


def test_the_replica_is_numpys_exp_where_numpy_uses_svml():
    """The direct check on this machine; where NumPy uses the C library, that it does, and the replica is an exp."""
    x = arguments(2)
    with np.errstate(all="ignore"):
        want = np.exp(x)
    got = E.exp_into(x, E.SVML)
    if E.choice() == E.SVML:
        bad = u64(got) != u64(want)
        assert not bad.any(), (x[bad][:5], want[bad][:5], got[bad][:5])
    else:
        assert E.choice() == E.LIBM
    finite = (x > -745.2) & (x < 709.7)
    ref = np.array([math.exp(v) for v in x[finite][::10]])
    assert ulps(got[finite][::10], ref).max() <= 1


def test_the_replica_is_within_an_ulp_of_the_c_library():
    """On every machine: a correct exp over the whole range, denormal results included."""
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.uniform(-745.13, 709.78, 100_000), rng.uniform(-745.13, -708.0, 50_000),
                        rng.uniform(-1.0, 1.0, 20_000)])
    got = E.exp_into(x, E.SVML)
    ref = np.array([math.exp(v) for v in x])
    assert ulps(got, ref).max() <= 1
    assert np.any(got < 2.2250738585072014e-308) and np.all(got > 0.0)     # denormal results were there


def test_specials_overflow_and_underflow():
    nan = np.array([0x7FF8000000000000, 0xFFF8000000000000, 0x7FF8000000000123, 0x7FF0000000000001],
                   dtype=np.uint64).view(np.float64)
    got = E.exp_into(nan, E.SVML)
    assert np.array_equal(u64(got), u64(nan) | np.uint64(0x0008000000000000))   # the same NaN, quietened
    x = np.array([np.inf, -np.inf, 0.0, -0.0, 709.79, 1e308, -745.14, -1e308, 5e-324, -5e-324, 2.0 ** -60])
    want = [np.inf, 0.0, 1.0, 1.0, np.inf, np.inf, 0.0, 0.0, 1.0, 1.0, 1.0]
    assert E.exp_into(x, E.SVML).tolist() == want
    assert not np.signbit(E.exp_into(x, E.SVML)).any()
    # the largest finite and smallest non-zero results, on both sides of each path's edge
    assert E.exp_svml(709.78) == pytest.approx(math.exp(709.78), rel=3e-16)
    assert E.exp_svml(-745.13) == 5e-324 and E.exp_svml(-745.1332191019412) == 0.0
    for edge in (E._RARE, -E._RARE, E._SUB):
        for v in (np.nextafter(edge, -np.inf), edge, np.nextafter(edge, np.inf)):
            assert ulps([E.exp_svml(v)], [math.exp(v)])[0] <= 1


def test_the_tables_are_powers_of_two_in_two_parts():
    """Th the nearest double to 2^(j/n), Th(1 + Tl) within an ulp of Tl's of it (decimal arithmetic, 60 digits)."""
    with localcontext() as ctx:
        ctx.prec = 60
        for n, th, tl in ((16, E._TH16, E._TL16), (64, E._TH64, E._TL64)):
            assert len(th) == len(tl) == n
            for j in range(n):
                exact = Decimal(2) ** (Decimal(j) / Decimal(n))
                assert th[j] == float(exact)
                assert abs(Decimal(th[j]) * (1 + Decimal(tl[j])) - exact) <= Decimal(th[j]) * Decimal(2) ** -106


def test_exp64_takes_the_exp_it_is_told():
    x = np.linspace(-50.0, 5.0, 10_001)
    assert np.array_equal(u64(E.exp_into(x, E.LIBM)), u64([math.exp(v) for v in x]))
    assert np.array_equal(u64(E.exp_into(x, E.SVML)), u64([E.exp_svml(v) for v in x]))
    assert not np.array_equal(u64(E.exp_into(x, E.LIBM)), u64(E.exp_into(x, E.SVML)))


def test_the_probe_covers_every_path():
    x = E.probe()
    assert np.isnan(x).any() and np.isinf(x).sum() == 2 and (x == 0.0).any()
    with np.errstate(all="ignore"):
        y = np.exp(x)
    assert ((y > 0.0) & (y < 2.2250738585072014e-308)).sum() > 1000      # denormal results
    assert (y[np.isfinite(x)] == 0.0).sum() > 100 and np.isinf(y[np.isfinite(x)]).sum() > 100
    assert ((np.abs(x) >= E._RARE) & (np.abs(x) < 709.0)).sum() > 100      # SVML's scalar routine, finite results
    assert ((x > -30.0) & (x < 5.0)).sum() > 10_000                        # the sky's arguments


@pytest.mark.parametrize("where", ["everywhere", "scalar path", "denormal results"])
def test_the_probe_catches_an_exp_one_ulp_off(monkeypatch, where):
    """The exp the probe chose, made one ulp off (everywhere, or only where few arguments go), is chosen no more."""
    chosen = E.choice()
    original = E.exp_into
    start = {"everywhere": 0.0, "scalar path": E._RARE, "denormal results": -E._SUB}[where]

    def off(x, which):
        out = original(x, which)
        hit = np.isfinite(out) & (out > 0.0) & (np.abs(x) >= start)
        if which == chosen:
            out[hit] = np.nextafter(out[hit], np.inf)
        return out

    monkeypatch.setattr(E, "exp_into", off)
    monkeypatch.delitem(E._verdict, "which", raising=False)
    try:
        assert E.choice() is None
    finally:
        E._verdict.pop("which", None)


@pytest.mark.parametrize("which", [E.LIBM, E.SVML])
@pytest.mark.parametrize("odd", [None, 800.0, -800.0, -740.0, np.inf, np.nan])
def test_exp_in_place_is_exp64_element_by_element(which, odd):
    """The block form the sky's kernel uses: the vectorised loop, or element by element where an
    argument needs SVML's scalar path (or is NaN); only the first n elements change."""
    rng = np.random.default_rng(9)
    a = rng.uniform(-60.0, 5.0, 41)
    if odd is not None:
        a[17] = odd
    want = a.copy()
    with np.errstate(all="ignore"):
        for i in range(37):
            want[i] = E.exp64(a[i], which)
    got = a.copy()
    E.exp_in_place(got, 37, which)
    assert np.array_equal(u64(got), u64(want))
    if which == E.choice():
        with np.errstate(all="ignore"):
            assert np.array_equal(u64(got[:37]), u64(np.exp(a[:37])))
