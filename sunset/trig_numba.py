"""NumPy's single-precision sine and cosine, compiled, bit for bit.

Why this exists. The sea is sampled in float32 and its profile and slopes
are sums of ``np.cos`` and ``np.sin`` of float32 phases. NumPy does not call
the C library for those: on x86 with FMA (and on ARM, POWER, s390x) its
``float32`` sine and cosine are its own vectorised algorithm, which the C
library's ``cosf`` does not reproduce bit for bit. A compiled twin that
must give the NumPy reference's exact bytes therefore has to compute the
same algorithm, operation for operation. It is short:

1. the quadrant q = rint(x · 2/π), rounded to an integer by adding and
   subtracting 1.5·2²³ (the multiply and the first add are one fused
   multiply-add in NumPy's build);
2. Cody and Waite's reduction r = x − q·π/2 with π/2 split into three
   float32 parts, each step a fused multiply-add;
3. two minimax polynomials in r² on [−π/4, π/4], one for the cosine and one
   for the sine, by Horner's rule in fused multiply-adds;
4. the quadrant picks sin or cos and the sign: cos x = sin(r) or cos(r) with
   the sign of q + 1 mod 4, computed as 0 − v where it is negated.

NumPy hands |x| beyond 71476.0625 (cosine) or 117435.992 (sine) and
infinities to the C library's ``cosf``/``sinf``, which is what Numba's
``math.cos`` calls for a float32, and returns NaN for NaN. The constants
are NumPy's (``numpy/_core/src/umath/loops_trigonometric.dispatch.cpp``,
BSD licence); the code is ours.

Whether a given NumPy build really computes this (it depends on the CPU
target NumPy chose at run time and on its compiler's contraction of the
first multiply-add) is checked once per process by :func:`matches_numpy`
on a probe of float32 values; :mod:`sunset.kernels` uses the compiled
sine and cosine only where it passes, and the NumPy reference otherwise.
For float64, NumPy calls the C library (``npy_cos``), as Numba does: the
probe checks that too.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from .kernels import jit as _jit

__all__ = ["fma32", "fma64", "cos32", "sin32", "cos_into", "sin_into", "sincos_into", "matches_numpy", "probe"]

_F = np.float32


def _hex(s: str) -> np.float32:
    return _F(float.fromhex(s))


#: 2/π and −π/2 in three float32 parts (Cody and Waite); 1.5·2²³ rounds a float32 to an integer.
_TWO_OVER_PI = _hex("0x1.45f306p-1")
_PIO2_HI, _PIO2_MED, _PIO2_LO = _hex("-0x1.921fb0p+00"), _hex("-0x1.5110b4p-22"), _hex("-0x1.846988p-48")
_RINT = _hex("0x1.8p+23")
#: cos r ≈ 1 + r²(C2 + r²(C4 + r²(C6 + r² C8))), sin r ≈ r + r·r²(S3 + r²(S5 + r²(S7 + r² S9))).
_C8, _C6, _C4 = _hex("0x1.98e616p-16"), _hex("-0x1.6c06dcp-10"), _hex("0x1.55553cp-05")
_C2, _C0 = _F(-0.5), _F(1.0)
_S9, _S7, _S5, _S3 = _hex("0x1.7d3bbcp-19"), _hex("-0x1.a06bbap-13"), _hex("0x1.11119ap-07"), _hex("-0x1.555556p-03")
#: Beyond these magnitudes NumPy calls the C library.
COS_LIMIT, SIN_LIMIT = _F(71476.0625), _F(117435.992)
_ZERO = _F(0.0)


def _fma_intrinsic(numba_type, llvm_type, doc: str):
    @intrinsic
    def fma(typingctx, a, b, c):
        sig = numba_type(numba_type, numba_type, numba_type)

        def codegen(context, builder, signature, args):
            fn = builder.module.declare_intrinsic("llvm.fma", [llvm_type],
                                                  ir.FunctionType(llvm_type, [llvm_type] * 3))
            return builder.call(fn, args)
        return sig, codegen
    fma.__doc__ = doc
    return fma


#: a·b + c rounded once (LLVM's ``llvm.fma``), float32 and float64.
fma32 = _fma_intrinsic(types.float32, ir.FloatType(), "a·b + c rounded once (LLVM's ``llvm.fma.f32``), float32.")
fma64 = _fma_intrinsic(types.float64, ir.DoubleType(), "a·b + c rounded once (LLVM's ``llvm.fma.f64``), float64.")


@_jit
def _reduce(x):
    """(quadrant q, sin r, cos r) of a float32 x within the limits."""
    q = fma32(x, _TWO_OVER_PI, _RINT)
    q = q - _RINT
    r = fma32(q, _PIO2_HI, x)
    r = fma32(q, _PIO2_MED, r)
    r = fma32(q, _PIO2_LO, r)
    r2 = r * r
    c = fma32(_C8, r2, _C6)
    c = fma32(c, r2, _C4)
    c = fma32(c, r2, _C2)
    c = fma32(c, r2, _C0)
    s = fma32(_S9, r2, _S7)
    s = fma32(s, r2, _S5)
    s = fma32(s, r2, _S3)
    s = fma32(s, r2, _ZERO)
    s = fma32(s, r, r)
    return np.int32(q), s, c


@_jit
def _pick(iq, s, c):
    """sin x from the quadrant (cos x: pass q + 1): sin r or cos r, negated as 0 − v in quadrants 2 and 3."""
    v = s if (iq & 1) == 0 else c
    return (_ZERO - v) if (iq & 2) == 2 else v


@_jit
def cos32(x):
    """cos x of a float32 x, NumPy's float32 ``np.cos`` bit for bit."""
    if x != x:
        return _F(np.nan)
    if abs(x) <= COS_LIMIT:
        iq, s, c = _reduce(x)
        return _pick(iq + np.int32(1), s, c)
    return math.cos(x)


@_jit
def sin32(x):
    """sin x of a float32 x, NumPy's float32 ``np.sin`` bit for bit."""
    if x != x:
        return _F(np.nan)
    if abs(x) <= SIN_LIMIT:
        iq, s, c = _reduce(x)
        return _pick(iq, s, c)
    return math.sin(x)


@_jit
def _rare(x, limit):
    """Whether any |x[i]| exceeds ``limit`` or is NaN (a loop of its own: a counter in the main loop
    halves the width LLVM vectorises it at)."""
    rare = False
    for i in range(x.shape[0]):
        rare |= not abs(x[i]) <= limit
    return rare


@_jit
def cos_into(x, out):
    """out[i] = cos x[i] for 1-D float32 arrays (may be the same array); returns out.

    Where every |x| is within the limit, one loop with no branch, which LLVM
    vectorises; otherwise (a value beyond it, infinite or NaN) element by
    element with :func:`cos32`.
    """
    if _rare(x, COS_LIMIT):
        for i in range(x.shape[0]):
            out[i] = cos32(x[i])
        return out
    for i in range(x.shape[0]):
        iq, s, c = _reduce(x[i])
        out[i] = _pick(iq + np.int32(1), s, c)
    return out


@_jit
def sin_into(x, out):
    """out[i] = sin x[i] for 1-D float32 arrays (may be the same array), as :func:`cos_into`; returns out."""
    if _rare(x, SIN_LIMIT):
        for i in range(x.shape[0]):
            out[i] = sin32(x[i])
        return out
    for i in range(x.shape[0]):
        iq, s, c = _reduce(x[i])
        out[i] = _pick(iq, s, c)
    return out


@_jit
def sincos_into(x, sin_out, cos_out):
    """sin and cos of 1-D float32 x from one reduction; NumPy's bits for both (x may not alias the outputs)."""
    if _rare(x, COS_LIMIT):                   # the smaller of the two limits
        for i in range(x.shape[0]):
            sin_out[i] = sin32(x[i])
            cos_out[i] = cos32(x[i])
        return
    for i in range(x.shape[0]):
        iq, s, c = _reduce(x[i])
        sin_out[i] = _pick(iq, s, c)
        cos_out[i] = _pick(iq + np.int32(1), s, c)


@_jit
def _cos64_into(x, out):
    for i in range(x.shape[0]):
        out[i] = math.cos(x[i])


@_jit
def _sin64_into(x, out):
    for i in range(x.shape[0]):
        out[i] = math.sin(x[i])


def probe() -> np.ndarray:
    """The float32 values :func:`matches_numpy` checks: a lattice over every binade to 2¹⁷, both signs, and specials.

    Every 4093rd float32 bit pattern from the smallest normal to 2¹⁷ (past
    both limits), negated too, plus ±0, ±∞, NaN and the quadrant boundaries
    kπ/4 for |k| ≤ 4096, where a different rounding of the quadrant shows.
    """
    bits = np.arange(0x00800000, 0x48000000, 4093, dtype=np.uint32)
    lattice = bits.view(np.float32)
    k = np.arange(-4096, 4097, dtype=np.float64) * (math.pi / 4)
    edges = np.concatenate([np.nextafter(k.astype(_F), _F(-np.inf)), k.astype(_F),
                            np.nextafter(k.astype(_F), _F(np.inf))])
    special = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, COS_LIMIT, SIN_LIMIT], dtype=_F)
    return np.concatenate([lattice, -lattice, edges, special]).astype(_F)


_verdict: dict = {}


def matches_numpy() -> bool:
    """Whether the compiled sine and cosine give NumPy's bits in this process (checked once, on :func:`probe`)."""
    if "ok" not in _verdict:
        x = probe()
        with np.errstate(invalid="ignore"):
            want = [np.cos(x), np.sin(x)]
            got = [cos_into(x, np.empty_like(x)), sin_into(x, np.empty_like(x))]
            s, c = np.empty_like(x), np.empty_like(x)
            sincos_into(x, s, c)
            got += [c, s]
            want += [want[0], want[1]]
            x64 = x.astype(np.float64) * 1.000000001
            want += [np.cos(x64), np.sin(x64)]
            got += [np.empty_like(x64), np.empty_like(x64)]
            _cos64_into(x64, got[-2])
            _sin64_into(x64, got[-1])
        _verdict["ok"] = all(np.array_equal(a.view(np.uint8), b.view(np.uint8)) for a, b in zip(want, got))
    return _verdict["ok"]
