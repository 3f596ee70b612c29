"""A float32 sine and cosine of our own for the compiled kernels: one that the compiler vectorises.

Why this exists. The sea's profile and slopes are sums of cosines and sines
of float32 phases, about 18 million of them in a 1024² frame of the default
scene. Numba's ``math.cos`` of a float32 calls the C library's ``cosf`` once
per element, which no loop vectorises: about 34 million a second on one core
of the machine of chapter 10, where a loop of the arithmetic below runs at
600 to 1200 million. The result is not NumPy's ``np.cos`` and does not try
to be (that one depends on the SIMD code NumPy picked for the processor); it
is tested against the correctly rounded cosine in units in the last place
(``tests/vector/test_sincos_numba.py``): within :data:`MAX_ULP`.

The algorithm is the textbook one (Cody and Waite's reduction, then
polynomials), in float32 with fused multiply-adds (:func:`fma32`):

1. the quadrant q = rint(x·2/π), rounded to an integer by adding and
   subtracting 1.5·2²³;
2. r = x − q·π/2 with π/2 split into three float32 parts (:func:`split`):
   the first has 20 significant bits, so that x − q·π/2's first step loses
   nothing, the other two carry the rest, 68 bits in all;
3. the Taylor polynomials of cos r and sin r on [−π/4, π/4] by Horner's
   rule (the first terms left out are below 2·10⁻⁹);
4. the quadrant picks ±sin r or ±cos r.

Beyond :data:`LIMIT` (where the rounding of q·π/2 begins to show), and for
infinities and NaN, the C library's ``cosf`` and ``sinf`` are called; an
array with such an element is taken element by element, so that the loop
over the others has no branch.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from ..kernels import jit as _jit

__all__ = ["LIMIT", "MAX_ULP", "fma32", "split", "parts", "cos_of", "sin_of", "cos32", "sin32", "cos_into",
           "LIMIT64", "MAX_ULP64", "fma64", "split64", "parts64", "sincos64", "sincos64_into",
           "sincos_into"]

_F = np.float32

#: π to 60 digits, for the parts of π/2.
_PI = Fraction("3.14159265358979323846264338327950288419716939937510582097494459")


def _rounded(v: Fraction, bits: int) -> float:
    """v rounded to ``bits`` significant bits (to nearest), exactly."""
    e = math.floor(math.log2(abs(v)))
    scale = Fraction(2) ** (bits - 1 - e)
    return float(Fraction(round(v * scale)) / scale)


def split() -> tuple[float, float, float]:
    """π/2 = A + B + C (to 2⁻⁷⁰): A with 20 significant bits, B and C float32s."""
    half = _PI / 2
    a = _rounded(half, 20)
    b = _rounded(half - Fraction(a), 24)
    c = _rounded(half - Fraction(a) - Fraction(b), 24)
    return a, b, c


_A, _B, _C = (_F(-v) for v in split())
_TWO_OVER_PI = _F(2.0 / math.pi)
_RINT = _F(1.5 * 2**23)
#: |x| up to which the reduction above is used.
LIMIT = _F(2.0**17)
#: The largest error of :func:`cos32` and :func:`sin32` against the correctly rounded value up to
#: :data:`LIMIT`, float32 ulp (measured 1.47; the tests hold it).
MAX_ULP = 1.5
#: Taylor coefficients: cos r ≈ 1 + r²(C2 + r²(C4 + …)), sin r ≈ r + r³(S3 + r²(S5 + …)).
_C2, _C4, _C6, _C8, _C10 = (_F(-1.0 / 2), _F(1.0 / 24), _F(-1.0 / 720), _F(1.0 / 40320), _F(-1.0 / 3628800))
_S3, _S5, _S7, _S9 = _F(-1.0 / 6), _F(1.0 / 120), _F(-1.0 / 5040), _F(1.0 / 362880)
_ONE = _F(1.0)


@intrinsic
def fma32(typingctx, a, b, c):
    """a·b + c rounded once, float32 (LLVM's ``llvm.fma.f32``: one instruction where the processor has it)."""
    sig = types.float32(types.float32, types.float32, types.float32)

    def codegen(context, builder, signature, args):
        f32 = ir.FloatType()
        fn = builder.module.declare_intrinsic("llvm.fma", [f32], ir.FunctionType(f32, [f32] * 3))
        return builder.call(fn, args)
    return sig, codegen


@_jit
def parts(x):
    """(quadrant q as int32, sin r, cos r) for a float32 x, |x| <= LIMIT.

    x = q·π/2 + r with |r| <= π/4.
    """
    q = fma32(x, _TWO_OVER_PI, _RINT) - _RINT
    r = fma32(q, _A, x)
    r = fma32(q, _B, r)
    r = fma32(q, _C, r)
    r2 = r * r
    c = fma32(fma32(fma32(_C10, r2, _C8), r2, _C6), r2, _C4)
    c = fma32(fma32(c, r2, _C2), r2, _ONE)
    s = fma32(fma32(fma32(_S9, r2, _S7), r2, _S5), r2, _S3)
    s = fma32(s, r2 * r, r)
    return np.int32(q), s, c


@_jit
def cos_of(q, s, c):
    """cos x from :func:`parts`: cos r, −sin r, −cos r, sin r in quadrants 0, 1, 2, 3."""
    v = s if q & 1 else c
    return -v if (q + 1) & 2 else v


@_jit
def sin_of(q, s, c):
    """sin x from :func:`parts`: sin r, cos r, −sin r, −cos r in quadrants 0, 1, 2, 3."""
    v = c if q & 1 else s
    return -v if q & 2 else v


@_jit
def cos32(x):
    """cos x of one float32 x (the C library's ``cosf`` beyond :data:`LIMIT`, for ±∞ and NaN)."""
    if abs(x) <= LIMIT:
        q, s, c = parts(x)
        return cos_of(q, s, c)
    return math.cos(x)


@_jit
def sin32(x):
    """sin x of one float32 x (the C library's ``sinf`` beyond :data:`LIMIT`, for ±∞ and NaN)."""
    if abs(x) <= LIMIT:
        q, s, c = parts(x)
        return sin_of(q, s, c)
    return math.sin(x)


@_jit
def rare(x) -> bool:
    """Whether some |x[i]| exceeds :data:`LIMIT` or is NaN (a loop of its own, which vectorises)."""
    out = False
    for i in range(x.shape[0]):
        out |= not abs(x[i]) <= LIMIT
    return out


@_jit
def _cos_loop(x, out):
    for i in range(x.shape[0]):
        q, s, c = parts(x[i])
        out[i] = cos_of(q, s, c)


@_jit
def _sincos_loop(x, sin_out, cos_out):
    for i in range(x.shape[0]):
        q, s, c = parts(x[i])
        sin_out[i] = sin_of(q, s, c)
        cos_out[i] = cos_of(q, s, c)


@_jit
def cos_into(x, out):
    """out[i] = cos x[i] for 1-D float32 arrays (they may be the same array); returns out.

    One loop with no branch where every |x| is within :data:`LIMIT`, else element by element (:func:`cos32`).
    """
    if rare(x):
        for i in range(x.shape[0]):
            out[i] = cos32(x[i])
    else:
        _cos_loop(x, out)
    return out


@_jit
def sincos_into(x, sin_out, cos_out):
    """sin and cos of 1-D float32 x from one reduction, as :func:`cos_into` (x must not be an output)."""
    if rare(x):
        for i in range(x.shape[0]):
            sin_out[i] = sin32(x[i])
            cos_out[i] = cos32(x[i])
    else:
        _sincos_loop(x, sin_out, cos_out)


# --------------------------------------------------------------------------- float64

#: |x| up to which :func:`sincos64` reduces the argument itself (the quotient q < 2²⁰, q·A exact).
LIMIT64 = 2.0**20
#: The largest error of :func:`sincos64` against the 64-bit-mantissa ``cosl`` and ``sinl`` up to
#: :data:`LIMIT64`, float64 ulp at the true value (the tests hold it).
MAX_ULP64 = 1.5


def split64() -> tuple[float, float, float]:
    """π/2 = A + B + C (to 2⁻¹³⁰): A with 33 significant bits (q·A exact for q < 2²⁰), B and C float64s."""
    half = _PI / 2
    a = _rounded(half, 33)
    b = _rounded(half - Fraction(a), 53)
    c = _rounded(half - Fraction(a) - Fraction(b), 53)
    return a, b, c


_A64, _B64, _C64 = (-v for v in split64())
_TWO_OVER_PI64 = 2.0 / math.pi
_RINT64 = 1.5 * 2.0**52
#: Taylor coefficients 1/n! with alternating signs: cos up to r¹⁶, sin up to r¹⁷ (the next terms are below
#: 3·10⁻¹⁸ on [−π/4, π/4]).
_COS64 = tuple(float((-1) ** (k // 2) * Fraction(1, math.factorial(k))) for k in range(16, 0, -2))
_SIN64 = tuple(float((-1) ** ((k - 1) // 2) * Fraction(1, math.factorial(k))) for k in range(17, 2, -2))


@intrinsic
def fma64(typingctx, a, b, c):
    """a·b + c rounded once, float64 (LLVM's ``llvm.fma.f64``)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        f64 = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [f64], ir.FunctionType(f64, [f64] * 3))
        return builder.call(fn, args)
    return sig, codegen


@_jit
def parts64(x):
    """(quadrant q as int64, sin r, cos r) for a float64 x, |x| <= LIMIT64: x = q·π/2 + r, |r| <= π/4."""
    q = fma64(x, _TWO_OVER_PI64, _RINT64) - _RINT64
    r = fma64(q, _A64, x)
    r = fma64(q, _B64, r)
    r = fma64(q, _C64, r)
    r2 = r * r
    c = _COS64[0]
    c = fma64(c, r2, _COS64[1])
    c = fma64(c, r2, _COS64[2])
    c = fma64(c, r2, _COS64[3])
    c = fma64(c, r2, _COS64[4])
    c = fma64(c, r2, _COS64[5])
    c = fma64(c, r2, _COS64[6])
    c = fma64(c, r2, _COS64[7])
    c = fma64(c, r2, 1.0)
    s = _SIN64[0]
    s = fma64(s, r2, _SIN64[1])
    s = fma64(s, r2, _SIN64[2])
    s = fma64(s, r2, _SIN64[3])
    s = fma64(s, r2, _SIN64[4])
    s = fma64(s, r2, _SIN64[5])
    s = fma64(s, r2, _SIN64[6])
    s = fma64(s, r2, _SIN64[7])
    s = fma64(s, r2 * r, r)
    return np.int64(q), s, c


@_jit
def sincos64(x):
    """(sin x, cos x) of one float64 x (the C library's ``sin`` and ``cos`` beyond :data:`LIMIT64`, ±∞, NaN)."""
    if abs(x) <= LIMIT64:
        q, s, c = parts64(x)
        return sin_of(q, s, c), cos_of(q, s, c)
    return math.sin(x), math.cos(x)


@_jit
def sincos64_into(x, sin_out, cos_out):
    """sin and cos of the float64 x[i] into ``sin_out``, ``cos_out`` (not x), as :func:`sincos_into`: one loop
    without a branch where every |x| is within :data:`LIMIT64`, else element by element (:func:`sincos64`)."""
    rare = False
    for i in range(x.shape[0]):
        rare |= not abs(x[i]) <= LIMIT64
    if rare:
        for i in range(x.shape[0]):
            sin_out[i], cos_out[i] = sincos64(x[i])
    else:
        for i in range(x.shape[0]):
            q, s, c = parts64(x[i])
            sin_out[i] = sin_of(q, s, c)
            cos_out[i] = cos_of(q, s, c)
