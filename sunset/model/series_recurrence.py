"""Stokes' expansion by computer: the recurrence and its arithmetic (see :mod:`sunset.model.series`).

The recurrence
--------------
Everything is dimensionless (g = k = 1). The water under one wavelength is the
conformal image of the lower half plane, the surface that of the real line
(see :mod:`sunset.stokes`), and the surface elevation y(u) = Σ y_n cos n u in
the conformal variable u satisfies Babenko's equation

    c² 𝒦y − y − y 𝒦y − ½ 𝒦(y²) = 0,      𝒦 cos n u = n cos n u.

Write ζ = e^{iu} and expand in ε = kH/2, half the crest-to-trough height::

    y = Σ_{p>=1} ε^p Y_p(ζ),    c² = Σ_{j>=0} C_j ε^j,   C_0 = 1,

where the order-p term Y_p is a Laurent polynomial with only the powers
ζ^{−p}, ζ^{−p+2}, …, ζ^p (the n-th harmonic first appears at order n, and
with the parity of p). The coefficient of ε^p in Babenko's equation reads

    (𝒦 − 1) Y_p + C_{p−1} 𝒦Y_1 = R_p,
    R_p = Σ_{j=1}^{p−1} [Y_j 𝒦Y_{p−j} + ½ 𝒦(Y_j Y_{p−j})] − Σ_{j=2}^{p−2} C_j 𝒦Y_{p−j},

with a right side R_p made of lower orders only. 𝒦 − 1 multiplies the
harmonic ζ^{±m} by |m| − 1, so it is inverted harmonic by harmonic except at
|m| = 1, where it vanishes: that component of the equation fixes the speed
coefficient C_{p−1} instead (Stokes' condition that removes the secular term),
the mean (m = 0) gives −Y_p's constant term, and the first harmonic of Y_p,
free so far, is fixed by the normalization: the wave height y(0) − y(π) = 2ε
exactly, so the odd harmonics of every Y_p, p >= 2, add up to zero.

The paper's coefficients are those of the Eulerian elevation z(x) = Σ a_n
cos n x, in the physical abscissa x = u + s(u), s = Σ y_n sin n u. Integrating
by parts, a_n = −(1/nπ) ∮ y'(u) sin n x(u) du, and with i s = T(ζ) =
Σ_m sign(m) Y_m ζ^m (real coefficients),

    a_n = −(2/n) Σ_m m Y_m [e^{nT}]_{−m−n},

where [·]_k is the coefficient of ζ^k: a series exponential, computed by the
recurrence p G_p = n Σ_j j T_j G_{p−j}, of which only the few harmonics the
sum needs are kept. Other quantities follow from the same Y_p: the speed
c = √(c²), the crest curvature κ/k = Σ m² Y_m / (1 + Σ |m| Y_m)² (the crest
is at u = 0, where x'(0) = 1 + Σ |m| Y_m), and Longuet-Higgins's parameter
ω = 1 − q_c²/c² = 1 − 1/x'(0)², with q_c the water's speed at the crest in
the frame of the wave (0 for a linear wave, 1 for the highest one).

Series in α = k a₁ (the paper's parameter) or in ω follow by reverting the
series a₁(ε) or ω(ε) (Lagrange inversion) and composing.

Arithmetic
----------
With ``exact=True`` (the default) every coefficient is a
:class:`fractions.Fraction`: the recurrence only adds, multiplies and divides
by integers. With ``exact=False`` it runs in float64, the same code, fast to
orders in the hundreds; but the float coefficients drift from the exact ones
by round-off that grows with the order: about 1e-11 relative at order 30
(tested), and a digit lost every eight or nine orders beyond: at each order
the largest conformal coefficient (a high harmonic, m near 0.8 p) outgrows
the physical coefficients summed from such terms by about 1.3 per order, so
the sums cancel more and more digits. The Padé continuation of the book
therefore uses the exact series.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import NamedTuple

import numpy as np

__all__ = ["Ring", "mul", "inverse", "sqrt", "split", "join", "pair_powers", "revert", "compose", "modes",
           "conformal_rows", "eulerian_amplitude"]


# --------------------------------------------------------------------------- arithmetic on truncated series
class Ring(NamedTuple):
    """The numbers a series is made of: Fractions in object arrays, or float64."""

    exact: bool

    @property
    def dtype(self):
        return object if self.exact else np.float64

    @property
    def one(self):
        return Fraction(1) if self.exact else 1.0

    def zeros(self, n: int) -> np.ndarray:
        if self.exact:
            out = np.empty(n, dtype=object)
            out[:] = Fraction(0)
            return out
        return np.zeros(n)


def mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Product of two power series, truncated to len(a) terms."""
    return np.convolve(a, b)[: len(a)]


def inverse(a: np.ndarray, ring: Ring) -> np.ndarray:
    """1 / a(x) as a power series (a[0] != 0)."""
    out = ring.zeros(len(a))
    out[0] = ring.one / a[0]
    for p in range(1, len(a)):
        out[p] = -np.dot(a[1:p + 1], out[p - 1::-1]) / a[0]
    return out


def sqrt(a: np.ndarray, ring: Ring) -> np.ndarray:
    """√a(x) as a power series, for a[0] = 1."""
    out = ring.zeros(len(a))
    out[0] = ring.one
    for p in range(1, len(a)):
        out[p] = (a[p] - np.dot(out[1:p], out[p - 1:0:-1])) / 2
    return out


def split(a: np.ndarray, ring: Ring):
    """A series as (numerators, common denominator): integers when exact."""
    if not ring.exact:
        return a, 1
    den = math.lcm(*(v.denominator for v in a))
    return np.array([v.numerator * (den // v.denominator) for v in a], dtype=object), den


def join(num: np.ndarray, den, ring: Ring) -> np.ndarray:
    """The inverse of :func:`split`."""
    if not ring.exact:
        return num / den
    out = np.empty(len(num), dtype=object)
    out[:] = [Fraction(int(v), den) for v in num]
    return out


def pair_powers(b: np.ndarray, ring: Ring) -> list[tuple[np.ndarray, int]]:
    """b(t)^j, j = 0..P, truncated to P + 1 terms, as (numerators, denominator) pairs.

    Exact powers multiply integer numerators (one gcd per power, not one per
    operation), which is what keeps the conversions to α and ω fast.
    """
    num, den = split(b, ring)
    first = _int_zeros(len(b), ring)
    first[0] = 1
    out = [(first, 1)]
    for _ in range(1, len(b)):
        prev, pden = out[-1]
        out.append(_reduce(mul(prev, num), pden * den, ring))
    return out


def revert(a: np.ndarray, ring: Ring) -> np.ndarray:
    """The inverse series b(t), a(b(t)) = t, of a(x) = a₁x + …, by Lagrange inversion.

    [t^k] b = (1/k) [x^{k−1}] (x / a(x))^k.
    """
    P = len(a) - 1
    shifted = np.concatenate([a[1:], ring.zeros(1)])  # a(x) / x
    powers = pair_powers(inverse(shifted, ring), ring)
    out = ring.zeros(P + 1)
    for k in range(1, P + 1):
        num, den = powers[k]
        out[k] = Fraction(int(num[k - 1]), den * k) if ring.exact else num[k - 1] / k
    return out


def compose(f: np.ndarray, powers: list[tuple[np.ndarray, int]], ring: Ring) -> np.ndarray:
    """f(b(t)) from the powers of b (b(0) = 0), as given by :func:`_pair_powers`."""
    parts = []
    for j in range(len(f)):
        if f[j] != 0:
            fn, fd = _as_pair(f[j], ring)
            parts.append((fn * powers[j][0], fd * powers[j][1]))
    num, den = _sum_rows(parts, len(f), ring)
    return join(num, den, ring)


# --------------------------------------------------------------------------- the recurrence
# A row of order p is the pair (numerators, denominator): the coefficients of
# ζ^{−p}, ζ^{−p+2}, …, ζ^p of an ε^p term are numerators / denominator. Exact
# rows hold Python integers over one common denominator, so that the long
# convolutions multiply and add integers (no gcd per operation, as Fractions
# would take) and each row is reduced once; float rows have denominator 1.
def modes(p: int) -> np.ndarray:
    """The harmonics m = −p, −p+2, …, p of an order-p row."""
    return -p + 2 * np.arange(p + 1)


def _as_pair(x, ring: Ring):
    """A scalar as (numerator, denominator)."""
    return (x.numerator, x.denominator) if ring.exact else (x, 1)


def _sum_rows(parts, size: int, ring: Ring):
    """Σ num/den over ``parts`` [(num, den)], as one (num, den)."""
    if not parts:
        return _int_zeros(size, ring), 1
    if not ring.exact:
        return sum(num / den for num, den in parts), 1
    L = math.lcm(*(den for _, den in parts))
    return sum(num * (L // den) for num, den in parts), L


def _reduce(num: np.ndarray, den, ring: Ring):
    """Cancel the common factor of an exact row."""
    if ring.exact and len(num):
        g = math.gcd(den, *num.tolist())
        if g > 1:
            return num // g, den // g
    return num, den


def _int_zeros(n: int, ring: Ring) -> np.ndarray:
    return np.zeros(n, dtype=object) * 0 if ring.exact else np.zeros(n)


def conformal_rows(P: int, ring: Ring):
    """Babenko's equation order by order in ε = kH/2 (module docstring).

    Returns the rows Y_p = (numerators, denominator), p = 0..P, and C_j,
    j = 0..P−1, the coefficients of c² (C_{P−1} needs order P).
    """
    # Y_1 = (ζ + 1/ζ)/2: y = ε cos u
    rows = [(_int_zeros(1, ring), 1), (_int_zeros(2, ring) + 1, 2)]
    mods = [np.abs(modes(p)) for p in range(P + 1)]
    C = ring.zeros(P)
    C[0] = ring.one
    for p in range(2, P + 1):
        m = mods[p]
        parts = []
        for j in range(1, p):
            (a, da), (b, db) = rows[j], rows[p - j]
            # Y_j 𝒦Y_{p−j} + ½ 𝒦(Y_j Y_{p−j}), over 2 da db
            term = 2 * np.convolve(a, mods[p - j] * b) + m * np.convolve(a, b)
            parts.append((term, 2 * da * db))
        for j in range(2, p - 1, 2):  # − C_j 𝒦Y_{p−j}; C_j = 0 for odd j
            cn, cd = _as_pair(C[j], ring)
            b, db = rows[p - j]
            embedded = _int_zeros(p + 1, ring)
            embedded[j // 2: j // 2 + p - j + 1] = -cn * (mods[p - j] * b)
            parts.append((embedded, cd * db))
        R, L = _sum_rows(parts, p + 1, ring)
        inner = m >= 2
        row = _int_zeros(p + 1, ring)
        # (𝒦 − 1)^{−1}: divide harmonic m by |m| − 1, over one denominator M
        if ring.exact:
            M = math.lcm(*(int(v) - 1 for v in m[inner])) if inner.any() else 1
            factors = [M // (int(v) - 1) for v in m[inner]]
            row[inner] = R[inner] * np.array(factors, dtype=object)
        else:
            M = 1
            row[inner] = R[inner] / (m[inner] - 1)
        row[m == 0] = -M * R[m == 0]  # the mean: −Y_p = R_p there
        den = L * M
        if p % 2 == 1:
            i1 = (p + 1) // 2  # the index of ζ^{+1}
            # The ζ^{±1} component: C_{p−1} · ½ = R_p there (𝒦 − 1 is 0 on it).
            C[p - 1] = Fraction(2 * R[i1], L) if ring.exact else 2 * R[i1]
            # Its free first harmonic makes the odd harmonics add up to 0:
            # the height is exactly 2ε.
            row, den = 2 * row, 2 * den
            half = (-row.sum()) // 2 if ring.exact else -row.sum() / 2
            row[i1] = row[i1 - 1] = half
        rows.append(_reduce(row, den, ring))
    return rows, C


def eulerian_amplitude(rows, n: int, P: int, ring: Ring) -> np.ndarray:
    """k a_n as a series in ε to order P: a_n = −(2/n) Σ_m m Y_m [e^{nT}]_{−m−n}.

    G = e^{nT} follows from p G_p = n Σ_j j T_j G_{p−j}. Row q of G is only
    needed at the harmonics k with |k + n| <= P − q, and those depend on the
    same window of the rows below, so only that window is computed.
    """
    T = [(num * np.sign(modes(p)), den)
         for p, (num, den) in enumerate(rows[: P + 1])]
    W = [(num * modes(p), den) for p, (num, den) in enumerate(rows[: P + 1])]

    def window(q: int) -> tuple[int, int]:
        return max(0, -((n + P - 2 * q) // 2)), min(q, (P - n) // 2)

    G = [(0, _int_zeros(1, ring) + 1, 1)]  # (first index, numerators, denominator)
    for p in range(1, P):
        lo, hi = window(p)
        size = max(hi - lo + 1, 0)
        parts = []
        for j in range(1, p + 1):
            glo, g, gden = G[p - j]
            if len(g) == 0 or size == 0:
                continue
            conv = np.convolve(T[j][0], g)  # entry t is index glo + t of row p
            a, b = max(lo, glo), min(hi, glo + len(conv) - 1)
            if b >= a:
                part = _int_zeros(size, ring)
                part[a - lo:b - lo + 1] = (j * n) * conv[a - glo:b - glo + 1]
                parts.append((part, T[j][1] * gden))
        num, den = _sum_rows(parts, size, ring)
        num, den = _reduce(num, den * p, ring) if ring.exact else (num / p, 1)
        G.append((lo, num, den))
    out = ring.zeros(P + 1)
    for p in range(n, P + 1, 2):
        h = (p - n) // 2  # G_{p−j}[h − i] pairs with W_j[i]: harmonic −m − n
        total = ring.zeros(1)[0]
        for j in range(1, p + 1):
            glo, g, gden = G[p - j]
            i_lo, i_hi = max(0, h - glo - len(g) + 1), min(j, h - glo)
            if i_hi >= i_lo:
                g_part = g[h - glo - i_hi:h - glo - i_lo + 1][::-1]
                dot = np.dot(W[j][0][i_lo:i_hi + 1], g_part)
                d = W[j][1] * gden
                total += Fraction(int(dot), d) if ring.exact else dot / d
        out[p] = -2 * total / n
    return out
