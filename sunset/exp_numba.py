"""NumPy's float64 ``exp``, compiled, bit for bit, whichever of its two algorithms this process uses.

Why this exists. A compiled twin that must give a NumPy reference's exact
bits has to take each ``exp`` exactly as ``np.exp`` does, and which ``exp``
that is depends on the CPU NumPy finds at run time:

* without AVX-512 (and on other architectures' builds that have no vector
  float64 ``exp``) NumPy calls the C library's ``exp``, which is what
  Numba's ``math.exp`` calls: :data:`LIBM`;
* on an x86 CPU with AVX-512 (Skylake-X and later, AMD Zen 4), NumPy's Linux
  wheels call Intel's SVML routine ``__svml_exp8_ha``, whose last bits
  differ from the C library's for about one argument in twenty:
  :data:`SVML`. :func:`exp_svml` computes its algorithm one operation at a
  time.

The SVML algorithm (Intel's Short Vector Math Library as NumPy vendors it
in ``numpy/SVML`` and links into its Linux wheels, BSD-3-Clause, read from
the routine NumPy 2.4 ships; the constants below are its, the tables of
2^(j/n) are computed here from exact integer roots, the code is ours):

1. N = x·log₂e rounded *down* to a multiple of 1/16 (a fused multiply-add
   with a shifter, rounded towards zero), so x = N ln 2 + R with
   R = x − N·L₁ − N·L₂ (ln 2 in two parts, two fused multiply-adds);
2. with j the 16ths of N, 2^(j/16) ≈ Th_j (1 + Tl_j): Th_j the nearest
   double, Tl_j the rest relative to it;
3. e^R − 1 ≈ R·P(R), P of degree 5 evaluated in pairs (Estrin) with fused
   multiply-adds; the result Th_j·(R·P(R) + Tl_j) + Th_j, times
   2^floor(N) (``vscalefpd``).

Arguments with |x| ≥ 707.70 (and infinities) go to a scalar routine of its
own: 2^(j/64) from a 64-entry table, a degree-6 polynomial by Horner's rule
in separate multiplies and adds, +∞ above 709.78, 0 below −745.13, and
results below 2⁻¹⁰²² computed scaled by 2⁶⁰, split in two parts and scaled back.
:func:`exp_in_place` takes a block of arguments at once: where none needs the
scalar routine, the vector path has no branch and the loop vectorises.
NaN comes back as the same NaN, quietened.

Which one NumPy uses in this process is decided once, by :func:`choice`,
which compares both with ``np.exp`` on :func:`probe` (the whole range,
arguments whose results are denormal or 0, and the edges between the
algorithm's paths).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from .kernels import jit as _jit
from .trig_numba import fma64

__all__ = ["LIBM", "SVML", "exp_svml", "exp64", "exp_in_place", "exp_into", "probe", "choice", "EXPS"]

#: The ``exp`` NumPy takes for float64: the C library's or SVML's.
LIBM, SVML = 0, 1
EXPS = {LIBM: "the C library's exp", SVML: "SVML's __svml_exp8_ha"}


@intrinsic
def _from_bits(typingctx, bits):
    """The float64 whose bit pattern is the int64 ``bits``."""
    sig = types.float64(types.int64)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())
    return sig, codegen


@intrinsic
def _float_bits(typingctx, x):
    """The int64 bit pattern of the float64 ``x``."""
    sig = types.int64(types.float64)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))
    return sig, codegen


def _two_to_the(j: int, n: int) -> tuple[float, float]:
    """2^(j/n) as (Th, Tl): Th the nearest double, Tl = (2^(j/n) − Th)/Th rounded (exact integer roots)."""
    bits = 120
    x = 1 << (j + bits * n)
    while n > 1:                              # n a power of two: square roots, floored
        x = math.isqrt(x)
        n //= 2
    v = Fraction(x, 1 << bits)
    hi = float(v)
    return hi, float((v - Fraction(hi)) / Fraction(hi))


_h = float.fromhex
_TH16, _TL16 = (np.array(t) for t in zip(*(_two_to_the(j, 16) for j in range(16))))
_TH64, _TL64 = (np.array(t) for t in zip(*(_two_to_the(j, 64) for j in range(64))))

#: The vector path: log₂e, the shifter 1.5·2⁴⁸ + 1023 (its ulp is 1/16), ln 2 in two parts, P's coefficients.
_LOG2E, _SHIFT = _h("0x1.71547652b82fep+0"), _h("0x1.8000000003ff0p+48")
_L1, _L2 = _h("0x1.62e42fefa39efp-1"), _h("0x1.abc9e3b39803fp-56")
_P5, _P4, _P3 = _h("0x1.7411836940c04p-10"), _h("0x1.1101cbbc265c0p-7"), _h("0x1.55557242d68fep-5")
_P2, _P1, _P0 = _h("0x1.5555553939732p-3"), _h("0x1.000000000d008p-1"), _h("0x1.fffffffffff70p-1")
_RARE = _h("0x1.61da04cbafe44p+9")            # |x| from which the scalar routine runs (707.70)
#: The scalar routine: 64/ln 2, the shifter 1.5·2⁵², ln 2/64 in two parts, Horner's coefficients, limits.
_INV64, _SHIFT52 = _h("0x1.71547652b82fep+6"), _h("0x1.8p+52")
_M1, _M2 = _h("0x1.62e42fefa0000p-7"), _h("0x1.cf79abc9e3b3ap-46")
_C6, _C5, _C4, _C3 = _h("0x1.6c16a1c2a3ffdp-10"), _h("0x1.111123aaf20d3p-7"), _h("0x1.5555555558fccp-5"), \
    _h("0x1.55555555548f8p-3")
_OVER, _SUB, _UNDER = _h("0x1.62e42fefa39efp+9"), _h("-0x1.6232bdd7abcd2p+9"), _h("-0x1.74910d52d3051p+9")
_SPLIT, _TWO_M60 = _h("0x1.8p+32"), _h("0x1p-60")


@_jit
def _rare(x):
    """SVML's scalar routine for |x| ≥ 707.70, infinities: one rounding per operation, no fused multiply-add."""
    if x == math.inf:
        return x
    if x == -math.inf or x < _UNDER:
        return 0.0
    if x > _OVER:
        return math.inf
    s = x * _INV64 + _SHIFT52                 # two roundings: the product, then the sum
    low = np.int64(_float_bits(s)) & 0xFFFFFFFF
    j = low & 63
    k = s - _SHIFT52
    r = (x - k * _M1) - k * _M2
    p = (((_C6 * r + _C5) * r + _C4) * r + _C3) * r
    p = ((((p + 0.5) * r) * r + r) + _TL64[j]) * _TH64[j]
    m = low >> 6
    if x >= _SUB:
        e = (m + 1023) & 0x7FF
        y = p + _TH64[j]
        if e > 0x7FE:
            return y * _from_bits(np.int64(e - 1) << 52) * 2.0
        return y * _from_bits(np.int64(e) << 52)
    e = (m + 1083) & 0x7FF                    # a result below 2⁻¹⁰²²: scaled up by 2⁶⁰ first
    scale = _from_bits(np.int64(e) << 52)
    a = p * scale
    b = scale * _TH64[j]
    y = b + a
    if e <= 50:
        return y * _TWO_M60
    lo = (b - y) + a
    c = y * _SPLIT
    hi = (y + c) - c
    return hi * _TWO_M60 + (lo + (y - hi)) * _TWO_M60


@_jit
def _svml_vector(x):
    """SVML's vector path for |x| < 707.70 (no branch: a loop of it vectorises)."""
    t = fma64(x, _LOG2E, _SHIFT)              # rounded to nearest; SVML rounds towards zero:
    low = fma64(x, _LOG2E, _SHIFT - t) < 0.0  # the exact sum was below t, so one ulp (1/16) down
    t = t - 0.0625 if low else t
    n = t - _SHIFT                            # x·log₂e rounded down to 16ths, exactly
    j = np.int64(n * 16.0) & 15
    r = fma64(-n, _L1, x)
    r = fma64(-_L2, n, r)
    r2 = r * r
    p = fma64(fma64(_P5, r, _P4), r2, fma64(_P3, r, _P2))
    p = fma64(p, r2, fma64(_P1, r, _P0))
    y = fma64(fma64(p, r, _TL16[j]), _TH16[j], _TH16[j])
    return y * _from_bits((np.int64(math.floor(n)) + 1023) << 52)


@_jit
def exp_svml(x):
    """e^x as NumPy's float64 ``np.exp`` computes it with SVML (``__svml_exp8_ha``), bit for bit."""
    if x != x:
        return x + x
    if not abs(x) < _RARE:
        return _rare(x)
    return _svml_vector(x)


@_jit
def exp64(x, which):
    """e^x by the ``exp`` NumPy uses: ``which`` is :data:`SVML` or :data:`LIBM` (from :func:`choice`)."""
    if which == SVML:
        return exp_svml(x)
    return math.exp(x)


@_jit
def exp_in_place(a, n, which):
    """a[:n] = e^a[:n] by the ``exp`` ``which`` names; with SVML's, one vectorised loop where no |a| ≥ 707.70."""
    if which != SVML:
        for i in range(n):
            a[i] = math.exp(a[i])
        return
    vector = True
    for i in range(n):
        vector &= abs(a[i]) < _RARE           # False for NaN too
    if vector:
        for i in range(n):
            a[i] = _svml_vector(a[i])
    else:
        for i in range(n):
            a[i] = exp_svml(a[i])


@_jit
def _exp_into(x, which, out):
    for i in range(x.shape[0]):
        out[i] = exp64(x[i], which)


def exp_into(x: np.ndarray, which: int) -> np.ndarray:
    """e^x of a 1-D float64 array by :func:`exp64` (a new array)."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    out = np.empty_like(x)
    _exp_into(x, int(which), out)
    return out


def probe() -> np.ndarray:
    """The float64 arguments :func:`choice` checks: the whole range, dense where the paths and results change.

    Random arguments over [−760, 720] and over [−30, 5] (the sky's heights and
    depths), the region of denormal results [−745.2, −708], every path's edge
    and its neighbours, tiny arguments, ±0, ±∞ and NaN.
    """
    rng = np.random.default_rng(20261202)
    edges = np.array([_RARE, -_RARE, _OVER, _SUB, _UNDER, -709.0896, -744.44, -745.13321910194122, 0.0, 1e-300])
    near = (edges[:, None] + np.arange(-8, 9) * np.spacing(np.abs(edges))[:, None]).ravel()
    return np.concatenate([
        rng.uniform(-760.0, 720.0, 40000), rng.uniform(-30.0, 5.0, 40000), rng.uniform(-745.2, -708.0, 20000),
        -np.exp(rng.uniform(-40.0, 6.6, 10000)), near, -near,
        np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 5e-324, -5e-324, 2.0 ** -54, -(2.0 ** -54)])])


_verdict: dict = {}


def choice() -> int | None:
    """Which ``exp`` gives ``np.exp``'s bits on :func:`probe` in this process (:data:`LIBM`, :data:`SVML`, or None).

    Checked once per process; the C library's first, where both agree.
    """
    if "which" not in _verdict:
        x = probe()
        with np.errstate(all="ignore"):
            want = np.exp(x).view(np.uint64)
        _verdict["which"] = next((w for w in (LIBM, SVML) if np.array_equal(exp_into(x, w).view(np.uint64), want)),
                                 None)
    return _verdict["which"]
