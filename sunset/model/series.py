"""Stokes' expansion by computer, as Schwartz (1974) did it: exact coefficients to high order.

Stokes (1847) expanded the deep-water wave of permanent form in powers of a
small amplitude and worked out the first few terms by hand; the paper (after
its eq. 2) prints four of them. Schwartz (1974) let a computer carry the same
expansion to high order and summed it, beyond where it
converges, with Padé approximants. This module does both.

The recurrence that produces the coefficients, derived step by step, is in
:mod:`sunset.model.series_recurrence`; this module holds what is done with
them: the series in the paper's α = k a₁, in ε = kH/2 and in Longuet-Higgins's
ω = 1 − q_crest²/c², their sums (partial and Padé), the Domb–Sykes ratio test,
and the estimates of the highest and of the fastest wave.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction
from typing import NamedTuple

import numpy as np
from scipy.optimize import minimize_scalar

from ..constants import (STOKES_MAX_STEEPNESS, STOKES_SERIES_MAX_ORDER_EXACT, STOKES_SERIES_MAX_ORDER_FLOAT,
                         STOKES_MAX_AMPLITUDES, STOKES_SERIES_MAX_X)
from ..errors import SunsetError, real_array, real_number, require_int_range, shown, typed
from .pade import RationalPade, SingularPade, pade_coefficients, pade_exact
from .pade import _sequence as _pade_sequence
from .series_recurrence import Ring, compose, conformal_rows, eulerian_amplitude, inverse, join, modes, mul, \
    pair_powers, revert, sqrt

__all__ = ["StokesSeries", "stokes_series", "DombSykes", "domb_sykes", "SeriesWave", "pade_coefficients"]

#: Expansion parameters: α = k a₁ (the paper's), ε = kH/2, ω = 1 − q_crest²/c² (Longuet-Higgins).
PARAMETERS = ("alpha", "epsilon", "omega")

#: Quantities that :meth:`StokesSeries.coefficients` expands (and ``"a1"``, ``"a2"``, … for k a_n).
QUANTITIES = ("speed", "speed_squared", "crest_curvature", "height", "alpha", "omega")

#: Typical radius of convergence of each parameter: Padé approximants are built in x / scale,
#: which keeps their coefficients of order one (a conditioning matter only).
_PADE_SCALE = {"alpha": 0.3, "epsilon": 0.44, "omega": 1.0}


# --------------------------------------------------------------------------- the series object
class SeriesWave(NamedTuple):
    """A Stokes wave summed from the series (Padé approximants in ε = kH/2)."""

    steepness: float          #: H/λ
    speed: float              #: c/√(g/k)
    amplitudes: np.ndarray    #: k a_n, n = 1..len
    crest_curvature: float    #: κ/k

    @property
    def alpha(self) -> float:
        """α = k a₁."""
        return float(self.amplitudes[0])


def _float_pade(g: np.ndarray, N: int) -> tuple[np.poly1d, np.poly1d]:
    """The float64 diagonal approximant of degree N of ``g``; where its system is singular (a series
    that ends, as the height in ε), the denominator's degree is lowered, as :func:`pade_exact` does."""
    m = N // 2
    while True:
        try:
            return pade_coefficients(g, m, N - m)
        except SingularPade:
            if m == 0:          # pragma: no cover - the system of m = 0 is the identity
                raise
            m -= 1


class StokesSeries:
    """Stokes' expansion to a given order (from ``sunset.stokes_series``).

    The coefficient of x^p is at index p of every tuple, p = 0..order, with x
    the expansion parameter: ``"alpha"`` (α = k a₁, the paper's, the default),
    ``"epsilon"`` (ε = kH/2) or ``"omega"`` (ω = 1 − q_crest²/c²).
    Coefficients are :class:`fractions.Fraction` when ``exact``, floats otherwise.
    """

    def __init__(self, order: int, exact: bool = True):
        _check_order(order, exact)
        self.order = int(order)
        self.exact = bool(exact)
        self._ring = Ring(self.exact)
        P = self.order
        ring = self._ring
        rows, C = conformal_rows(P + 1, ring)
        self._int_rows = rows
        Y = [join(num, den, ring) for num, den in rows[: P + 1]]
        self._rows = Y
        m_abs = [np.abs(modes(p)) for p in range(P + 1)]
        crest_slope = ring.zeros(P + 1)          # x'(0) = 1 + Σ |m| Y_m
        crest_bend = ring.zeros(P + 1)           # −y''(0) = Σ m² Y_m
        crest_slope[0] = ring.one
        for p in range(1, P + 1):
            crest_slope[p] = np.dot(m_abs[p], Y[p])
            crest_bend[p] = np.dot(m_abs[p] ** 2, Y[p])
        inv_sq = inverse(mul(crest_slope, crest_slope), ring)
        height = ring.zeros(P + 1)
        height[1] = ring.one
        omega = -inv_sq
        omega[0] = omega[0] + ring.one
        self._eps: dict[str, np.ndarray] = {
            "speed_squared": C[: P + 1],
            "speed": sqrt(C[: P + 1], ring),
            "crest_curvature": mul(crest_bend, inv_sq),
            "height": height,
            "omega": omega,
        }
        self._amplitudes: dict[int, np.ndarray] = {}
        self._powers: dict[str, list[tuple[np.ndarray, int]]] = {}
        self._converted: dict[tuple[str, str], np.ndarray] = {}
        self._pades: dict[tuple[str, str, int], tuple[RationalPade, int, int]] = {}

    def __repr__(self) -> str:
        return f"StokesSeries(order={self.order}, exact={self.exact})"

    # ------------------------------------------------------------------ coefficients
    def _amplitude_eps(self, n: int) -> np.ndarray:
        if n not in self._amplitudes:
            self._amplitudes[n] = eulerian_amplitude(self._int_rows, n, self.order, self._ring)
        return self._amplitudes[n]

    def _in_eps(self, quantity: str) -> np.ndarray:
        if quantity == "alpha":
            return self._amplitude_eps(1)
        if quantity in self._eps:
            return self._eps[quantity]
        if isinstance(quantity, str) and quantity.startswith("a") and quantity[1:].isdigit():
            n = int(quantity[1:])
            if not 1 <= n <= self.order:
                raise SunsetError(f"amplitude n must be in 1..{self.order} (the order), got {n}")
            return self._amplitude_eps(n)
        raise SunsetError(f"unknown quantity {shown(repr(quantity))}; expected one of {', '.join(QUANTITIES)} or a1, a2, …")

    def _powers_of(self, parameter: str) -> list[tuple[np.ndarray, int]]:
        """Powers of ε(x), for x = α or ω (computed once)."""
        if parameter not in self._powers:
            source = self._in_eps("alpha" if parameter == "alpha" else "omega")
            self._powers[parameter] = pair_powers(revert(source, self._ring), self._ring)
        return self._powers[parameter]

    def _series(self, quantity: str, parameter: str) -> np.ndarray:
        _check_names(quantity, parameter)
        key = (quantity, parameter)
        if key not in self._converted:
            self._converted[key] = self._convert(quantity, parameter)
        return self._converted[key]

    def _convert(self, quantity: str, parameter: str) -> np.ndarray:
        if parameter not in PARAMETERS:
            raise SunsetError(f"parameter must be one of {', '.join(PARAMETERS)}, got {shown(parameter)}")
        eps = self._in_eps(quantity)
        if parameter == "epsilon":
            return eps
        if (quantity, parameter) in (("alpha", "alpha"), ("a1", "alpha"), ("omega", "omega")):
            out = self._ring.zeros(self.order + 1)  # the parameter itself, free of round-off
            out[1] = self._ring.one
            return out
        return compose(eps, self._powers_of(parameter), self._ring)

    def coefficients(self, quantity: str, parameter: str = "alpha") -> tuple:
        """Coefficients of ``quantity`` in powers of ``parameter``, index p = power p.

        Parameters
        ----------
        quantity : str
            ``"speed"`` (c/√(g/k)), ``"speed_squared"`` (c²k/g), ``"crest_curvature"``
            (κ/k), ``"height"`` (ε = kH/2), ``"alpha"`` (k a₁), ``"omega"``, or
            ``"a<n>"`` (k a_n, the paper's eq. 2 amplitudes).
        parameter : str
            ``"alpha"``, ``"epsilon"`` or ``"omega"``.
        """
        return tuple(self._series(quantity, parameter).tolist())

    def amplitude(self, n: int, parameter: str = "alpha") -> tuple:
        """k a_n (eq. 2) in powers of ``parameter``: index p holds the coefficient of x^p.

        ``stokes_series(8).amplitude(2)[4] == Fraction(17, 24)``: the paper's 17/24.
        """
        require_int_range("n", n, 1, self.order)
        return self.coefficients(f"a{int(n)}", parameter)

    def speed(self, parameter: str = "alpha") -> tuple:
        """c/√(g/k) in powers of ``parameter`` (1 + α²/2 + α⁴/2 + …)."""
        return self.coefficients("speed", parameter)

    def speed_squared(self, parameter: str = "alpha") -> tuple:
        """c²k/g in powers of ``parameter`` (1 + α² + 5α⁴/4 + …)."""
        return self.coefficients("speed_squared", parameter)

    def crest_curvature(self, parameter: str = "alpha") -> tuple:
        """κ/k at the crest in powers of ``parameter`` (α + 2α² + 27α³/8 + …)."""
        return self.coefficients("crest_curvature", parameter)

    def height(self, parameter: str = "alpha") -> tuple:
        """ε = kH/2 in powers of ``parameter``."""
        return self.coefficients("height", parameter)

    def conformal(self, n: int) -> tuple:
        """y_n, the n-th cosine coefficient of y(u) (conformal variable), in powers of ε."""
        require_int_range("n", n, 0, self.order)
        out = self._ring.zeros(self.order + 1)
        for p in range(n, self.order + 1, 2):
            out[p] = self._rows[p][(p + n) // 2] * (1 if n == 0 else 2)
        return tuple(out.tolist())

    # ------------------------------------------------------------------ summing the series
    def partial_sum(self, quantity: str, x, parameter: str = "epsilon", terms: int | None = None):
        """Σ_{p<=terms} b_p x^p of the series of ``quantity`` in ``parameter`` (any shape of x)."""
        X = _x(x)
        b = self._float(quantity, parameter, terms)
        return np.polynomial.polynomial.polyval(X, b)

    def _float(self, quantity: str, parameter: str, terms: int | None) -> np.ndarray:
        terms = self.order if terms is None else terms
        require_int_range("terms", terms, 1, self.order)
        return self._floats(quantity, parameter)[: terms + 1]

    def _floats(self, quantity: str, parameter: str) -> np.ndarray:
        _check_names(quantity, parameter)
        key = (quantity, parameter, "float")
        if key not in self._converted:
            self._converted[key] = np.array([float(v) for v in self._series(quantity, parameter)])
        return self._converted[key]

    def pade(self, quantity: str, x, parameter: str = "epsilon",
             terms: int | None = None):
        """The diagonal Padé approximant of ``quantity``'s series, evaluated at x.

        Built from the first ``terms`` + 1 coefficients. A series that is even
        or odd (the speed and the amplitudes in α or ε) is continued in x², so
        that the approximant keeps that symmetry. For an exact series the
        approximant is exact (``pade_exact``, made once and kept) and so is
        its value at each x, rounded once to float64: the same bits on every
        machine. For a float series it is ``pade_coefficients``' float64
        solution, whose linear system is badly conditioned at high order;
        where it is singular, the denominator's degree is lowered, as the
        exact approximant's is.
        """
        X = _x(x)
        if self.exact:
            pq, shift, stride = self._exact_pade(quantity, parameter, terms)
            exact = [Fraction(v) ** shift * pq(Fraction(v) ** stride)
                     for v in X.ravel().tolist()]
            try:
                return np.array([float(v) for v in exact]).reshape(X.shape)[()]
            except OverflowError:
                raise SunsetError(f"the Padé approximant of {quantity} is beyond "
                                  "float64 at some x (next to a pole)") from None
        b = self._float(quantity, parameter, terms)
        shift, stride = _symmetry(b)
        g = b[shift::stride]
        scale = _PADE_SCALE[parameter] ** stride
        g = g * scale ** np.arange(len(g))
        N = len(g) - 1
        p, q = _float_pade(g, N)
        t = X**stride / scale
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            out = X**shift * p(t) / q(t)
        if not np.all(np.isfinite(out)):
            raise SunsetError(f"the float64 Padé approximant of {quantity} is not "
                              "finite at some x (a pole, or beyond float64)")
        return out

    def _exact_pade(self, quantity: str, parameter: str, terms: int | None) -> tuple[RationalPade, int, int]:
        """The exact diagonal approximant (in x^stride, times x^shift), computed once per (quantity, parameter, terms)."""
        terms = self.order if terms is None else terms
        require_int_range("terms", terms, 1, self.order)
        _check_names(quantity, parameter)
        key = (quantity, parameter, terms)
        if key not in self._pades:
            b = self._series(quantity, parameter)[: terms + 1]
            shift, stride = _symmetry(b)
            N = len(b[shift::stride]) - 1
            self._pades[key] = pade_exact(b[shift::stride], N // 2, N - N // 2), shift, stride
        return self._pades[key]

    def at_steepness(self, steepness: float, n_amplitudes: int = 4, terms: int | None = None) -> SeriesWave:
        """The wave of steepness H/λ summed from the series by Padé approximants in ε = π H/λ.

        ``steepness`` in 0..STOKES_MAX_STEEPNESS (the highest wave's 0.141063);
        ``n_amplitudes`` at most the order and STOKES_MAX_AMPLITUDES (16: each is an exact Padé
        approximant; 16 of the order-80 series take about half a minute).
        """
        s = real_number("steepness", steepness)
        if not 0.0 <= s <= STOKES_MAX_STEEPNESS:
            raise SunsetError(f"steepness must be in 0..{STOKES_MAX_STEEPNESS} (H/λ of the highest wave, "
                              f"Williams 1981), got {steepness!r}")
        require_int_range("n_amplitudes", n_amplitudes, 1, min(self.order, STOKES_MAX_AMPLITUDES))
        e = math.pi * s
        amps = np.array([float(self.pade(f"a{n}", e, "epsilon", terms)) for n in range(1, n_amplitudes + 1)])
        return SeriesWave(s, float(self.pade("speed", e, "epsilon", terms)), amps,
                          float(self.pade("crest_curvature", e, "epsilon", terms)))

    def highest_wave(self, terms: int | None = None) -> float:
        """H/λ of the highest wave, from the series alone.

        In ω = 1 − q_crest²/c² the highest wave, whose crest is a stagnation
        point, is ω = 1 by definition; its height is the Padé approximant of
        ε(ω) = kH/2 there, divided by π.
        """
        return float(self.pade("height", 1.0, "omega", terms)) / math.pi

    def speed_maximum(self, terms: int | None = None) -> tuple[float, float]:
        """(H/λ, c/√(g/k)) of the fastest wave, from Padé approximants in ω."""
        res = minimize_scalar(lambda w: -float(self.pade("speed", w, "omega", terms)), bounds=(0.5, 0.999),
                              method="bounded", options={"xatol": 1e-10})
        omega = float(res.x)
        return float(self.pade("height", omega, "omega", terms)) / math.pi, float(-res.fun)


def _symmetry(b) -> tuple[int, int]:
    """(shift, stride): (0, 2) for an even series, (1, 2) for an odd one, (0, 1) otherwise."""
    if np.all(b[1::2] == 0):
        return 0, 2
    if np.all(b[0::2] == 0):
        return 1, 2
    return 0, 1


@functools.lru_cache(maxsize=8)
def _cached(order: int, exact: bool) -> StokesSeries:
    return StokesSeries(order, exact)


def stokes_series(order: int, exact: bool = True) -> StokesSeries:
    """Stokes' deep-water expansion to ``order``, by the recurrence of this module.

    Parameters
    ----------
    order : int
        Highest power kept, >= 1; at most 80 exact, 400 in floating point.
    exact : bool
        Rational coefficients (:class:`fractions.Fraction`) when True, float64 otherwise.

    Returns
    -------
    StokesSeries
        Cached: the same arguments give the same object.

    Raises
    ------
    SunsetError
        For an order that is not an integer in range.
    """
    _check_order(order, exact)
    return _cached(int(order), bool(exact))


def _check_order(order, exact) -> None:
    if not isinstance(exact, (bool, np.bool_)):        # 'no' is not False
        raise SunsetError(f"exact must be True or False, got {typed(exact)}")
    limit = STOKES_SERIES_MAX_ORDER_EXACT if exact else STOKES_SERIES_MAX_ORDER_FLOAT
    require_int_range("order", order, 1, limit)


def _check_names(quantity, parameter) -> None:
    """Raise SunsetError unless ``quantity`` is text and ``parameter`` one of PARAMETERS (before any lookup)."""
    if not isinstance(quantity, str):
        raise SunsetError(f"quantity must be text ({', '.join(QUANTITIES)} or a1, a2, …), got {shown(quantity)}")
    if not isinstance(parameter, str) or parameter not in PARAMETERS:
        raise SunsetError(f"parameter must be one of {', '.join(PARAMETERS)}, got {shown(parameter)}")


def _x(x) -> np.ndarray:
    """The point(s) at which a series is summed: finite numbers with |x| <= STOKES_SERIES_MAX_X, any shape."""
    X = real_array("x", x)
    if not np.all(np.isfinite(X)):
        raise SunsetError(f"x must be a finite number, got {shown(x)}")
    if not np.all(np.abs(X) <= STOKES_SERIES_MAX_X):
        raise SunsetError(f"x must lie in [-{STOKES_SERIES_MAX_X:g}, {STOKES_SERIES_MAX_X:g}] (every wave's α, ε and "
                          f"ω do), got {shown(x)}")
    return X


# --------------------------------------------------------------------------- the ratio test
class DombSykes(NamedTuple):
    """Domb–Sykes analysis of a series Σ b_k t^k (t = x^stride)."""

    k: np.ndarray          #: indices of the ratios, k >= 1
    ratios: np.ndarray     #: b_k / b_{k−1}
    radius: float          #: radius of convergence in x (signed: negative for a singularity at x^stride < 0)
    exponent: float        #: γ of the nearest singularity (1 − t/t₀)^γ: ½ for a square-root branch point
    fit_from: int          #: first k of the straight-line fit
    intercept: float       #: of the line: 1/t₀
    slope: float           #: of the line: −(1 + γ)/t₀


def domb_sykes(coefficients, stride: int = 1, shift: int = 0, fit_last: int = 10) -> DombSykes:
    """Ratios of successive coefficients against 1/k, and the straight line through the last ones.

    If f = Σ b_k t^k has its nearest singularity at t₀, f ~ (1 − t/t₀)^γ, then
    b_k / b_{k−1} = (1/t₀) (1 − (1 + γ)/k + O(1/k²)): plotted against 1/k the
    ratios fall on a line whose intercept is 1/t₀ and whose slope gives γ.

    Parameters
    ----------
    coefficients : sequence
        Coefficients of x^p, p = 0..P (Fractions or floats).
    stride, shift : int
        Keep every ``stride``-th coefficient from ``shift``, so that b_k is the
        coefficient of x^(shift + stride k) (stride 2 for an even or odd series).
    fit_last : int
        Number of ratios, the last ones, in the fit.
    """
    values = _pade_sequence(coefficients)
    if len(values) < 3:                     # said first: the arguments below are bounded by the count
        raise SunsetError(f"domb_sykes: a line through 2 ratios needs at least 3 coefficients, got {len(values)}")
    require_int_range("stride", stride, 1, len(values) - 1)
    require_int_range("shift", shift, 0, len(values) - 1)
    require_int_range("fit_last", fit_last, 2)
    b = real_array("coefficients", values)[shift::stride]
    if not np.all(np.isfinite(b)):
        raise SunsetError("domb_sykes: the coefficients must be finite in float64")
    if len(b) <= fit_last:                  # the count, not fit_last's default, is what is short
        raise SunsetError(f"domb_sykes: {len(values)} coefficients, {len(b)} after stride {stride} and shift "
                          f"{shift}, give {len(b) - 1} ratios, fewer than the fit_last = {shown(fit_last)} fitted: "
                          f"pass more coefficients or a smaller fit_last")
    k = np.arange(1, len(b))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratios = b[1:] / b[:-1]
    sel = slice(len(k) - fit_last, len(k))
    if not np.all(np.isfinite(ratios[sel])) or not np.all(np.isfinite(1.0 / k[sel])):
        raise SunsetError("domb_sykes: a ratio in the fitted range is not finite (a coefficient is zero, or the "
                          "ratio is beyond float64); choose stride and shift so that only nonzero coefficients "
                          "are kept")
    with np.errstate(over="ignore", invalid="ignore"):
        slope, intercept = np.polyfit(1.0 / k[sel], ratios[sel], 1)
    if not (np.isfinite(slope) and np.isfinite(intercept)) or intercept == 0.0:
        raise SunsetError("domb_sykes: the ratios fit no line with a finite, nonzero intercept (no radius of "
                          "convergence to read off)")
    t0 = 1.0 / intercept
    radius = math.copysign(abs(t0) ** (1.0 / stride), t0)
    return DombSykes(k, ratios, radius, float(-slope / intercept - 1.0), int(k[sel][0]), float(intercept),
                     float(slope))
