"""The compiled float32 sine and cosine (sunset/trig_numba.py) against NumPy's own, bit for bit.

NumPy's ``np.sin``/``np.cos`` on float32 are the independent reference: the
compiled functions must return their exact bits, over every binade, at the
quadrant boundaries, beyond the Cody-Waite limits (where both call the C
library) and for NaN and infinities. A deliberately different rounding of
the quadrant (no fused multiply-add) must be caught by the probe that
sunset.kernels relies on.
"""

import math

import numpy as np
import pytest

numba = pytest.importorskip("numba")

from sunset import kernels, trig_numba as T  # noqa: E402


def bits(a):
    return np.asarray(a).view(np.uint8)


@pytest.mark.parametrize("scale", [1e-3, 1.0, 10.0, 300.0, 2e4, 7e4, 1.2e5, 1e7, 1e30])
def test_cos_and_sin_are_numpys_bits(scale):
    rng = np.random.default_rng(int(math.log10(scale) * 10) + 100)
    x = (rng.standard_normal(200_000) * scale).astype(np.float32)
    with np.errstate(invalid="ignore", over="ignore"):
        x = x[np.isfinite(x)]
        want_c, want_s = np.cos(x), np.sin(x)
    assert np.array_equal(bits(T.cos_into(x, np.empty_like(x))), bits(want_c))
    assert np.array_equal(bits(T.sin_into(x, np.empty_like(x))), bits(want_s))
    s, c = np.empty_like(x), np.empty_like(x)
    T.sincos_into(x, s, c)
    assert np.array_equal(bits(s), bits(want_s)) and np.array_equal(bits(c), bits(want_c))


def test_specials_and_limits():
    x = np.array([np.nan, np.inf, -np.inf, 0.0, -0.0, T.COS_LIMIT, np.nextafter(T.COS_LIMIT, np.float32(np.inf)),
                  T.SIN_LIMIT, np.nextafter(T.SIN_LIMIT, np.float32(np.inf)), -T.SIN_LIMIT], dtype=np.float32)
    with np.errstate(invalid="ignore"):
        want_c, want_s = np.cos(x), np.sin(x)
    got_c, got_s = T.cos_into(x, np.empty_like(x)), T.sin_into(x, np.empty_like(x))
    assert np.isnan(got_c[:3]).all() and np.isnan(got_s[:3]).all()
    assert np.array_equal(bits(got_c[3:]), bits(want_c[3:])) and np.array_equal(bits(got_s[3:]), bits(want_s[3:]))
    # the scalar forms agree with the array forms
    for v in x[3:]:
        assert np.float32(T.cos32(v)) == np.cos(v) and np.float32(T.sin32(v)) == np.sin(v)
    assert math.isnan(T.cos32(np.float32(np.nan)))


@pytest.mark.parametrize("big", [np.float32(1e6), np.float32(np.inf), np.float32(np.nan)])
def test_in_place_with_values_beyond_the_limit(big):
    x = np.linspace(-500, 500, 1001, dtype=np.float32)
    x[17] = big
    for fn, ref in ((T.cos_into, np.cos), (T.sin_into, np.sin)):
        y = x.copy()
        fn(y, y)
        with np.errstate(invalid="ignore"):
            assert np.array_equal(bits(y), bits(ref(x)))


def test_in_place_and_close_to_the_true_values():
    x = np.linspace(-50, 50, 10_001, dtype=np.float32)
    exact = np.cos(x.astype(np.float64))
    y = x.copy()
    T.cos_into(y, y)
    assert np.max(np.abs(y - exact)) < 2e-7           # a float32 cosine: ≤ 1.5 ulp of 1
    assert np.array_equal(bits(y), bits(np.cos(x)))


def test_the_probe_passes_here_and_the_kernels_use_it():
    assert T.matches_numpy()
    assert kernels.compiled_trig()
    p = T.probe()
    assert p.dtype == np.float32 and p.size > 500_000 and np.isnan(p).any()


def test_the_probe_catches_an_unfused_quadrant():
    """The same algorithm with the quadrant's multiply and add rounded separately differs from NumPy on the probe."""
    @numba.njit
    def unfused_cos(x, out):
        for i in range(x.shape[0]):
            xi = x[i]
            if not abs(xi) <= T.COS_LIMIT:
                out[i] = T.cos32(xi)
                continue
            q = (xi * T._TWO_OVER_PI + T._RINT) - T._RINT
            r = T.fma32(q, T._PIO2_HI, xi)
            r = T.fma32(q, T._PIO2_MED, r)
            r = T.fma32(q, T._PIO2_LO, r)
            r2 = r * r
            c = T.fma32(T.fma32(T.fma32(T.fma32(T._C8, r2, T._C6), r2, T._C4), r2, T._C2), r2, T._C0)
            s = T.fma32(T.fma32(T.fma32(T.fma32(T.fma32(T._S9, r2, T._S7), r2, T._S5), r2, T._S3), r2,
                                np.float32(0)), r, r)
            out[i] = T._pick(np.int32(q) + np.int32(1), s, c)

    p = T.probe()
    with np.errstate(invalid="ignore"):
        want = np.cos(p)
    got = np.empty_like(p)
    unfused_cos(p, got)
    assert np.count_nonzero(got.view(np.uint32) != want.view(np.uint32)) > 0


def test_a_twin_that_needs_the_trig_falls_back_where_it_fails(monkeypatch):
    calls = []

    @kernels.twin("sunset.vector.heightfield_numba", numpy_trig=True)
    def sea_scan(*args):
        calls.append("reference")
        return "reference"

    monkeypatch.setitem(kernels._state, "trig", False)
    with kernels.use_compiled(True):
        assert sea_scan() == "reference"
    assert calls == ["reference"]
