"""Padé approximants of a power series: in float64, and exactly in rational numbers.

The [n/m] approximant of f = Σ a_k x^k is p/q, deg p <= n, deg q <= m,
q(0) = 1, whose Taylor series agrees with f through x^(m+n): the
coefficients of q·f − p vanish there. Those of x^(n+1) … x^(n+m) involve q
alone,

    Σ_{j=1..m} q_j a_{k−j} = −a_k,   k = n+1 … n+m,

an m × m Toeplitz system (entry (i, j) depends on i − j only); then p is q·f
cut after x^n. :func:`pade_coefficients` solves the whole (m+n+1)-square
system in float64 as ``scipy.interpolate.pade`` did. At the orders of
:mod:`sunset.model.series` that system is so badly conditioned that the
answer is round-off, and which round-off depends on the machine's linear
algebra kernels: :func:`pade_exact` solves it exactly instead.

It does so the way computer algebra does. Times the common denominator of
the a_k, the system has integer entries, and modulo a prime p it is solved
in machine integers (by Levinson's recursion, which uses the Toeplitz form:
O(m²) operations, for hundreds of primes at once in NumPy). The Chinese
remainder theorem combines the solutions modulo many primes into one modulo
their product M, and Wang's rational reconstruction reads off the fractions
q_j = a_j / d whose numerators and denominator are below √(M/2). Primes are
added until the fractions found satisfy the system exactly, in Python
integers: the answer is checked, not trusted, and it is the same integers on
every machine.
"""

from __future__ import annotations

import math
import warnings
from fractions import Fraction
from typing import NamedTuple

import numpy as np
import scipy.linalg

from ..errors import SunsetError, real_array, shown

__all__ = ["pade_coefficients", "pade_exact", "RationalPade", "SingularPade"]

#: Highest degree m + n of an approximant: the exact one costs about (m + n)³ operations on numbers
#: of (m + n)·digits bits (0.2 s at 40 from order-80 coefficients); the series module asks for at most 400.
MAX_PADE_DEGREE = 400


class SingularPade(SunsetError):
    """The float64 system of a Padé approximant is singular (:func:`pade_coefficients`)."""


def _check_degrees(m: int, n: int, count: int) -> None:
    for name, v in (("m", m), ("n", n)):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or not 0 <= v <= MAX_PADE_DEGREE:
            raise SunsetError(f"{name}, a degree of the Padé approximant, must be a whole number in "
                              f"0..{MAX_PADE_DEGREE}, got {shown(v)}")
    if m + n > MAX_PADE_DEGREE:
        raise SunsetError(f"a Padé approximant of degrees {n}/{m} is past the most, m + n = {MAX_PADE_DEGREE}")
    if m + n > count - 1:
        raise SunsetError(f"a Padé approximant of degrees {n}/{m} needs the {m + n + 1} coefficients of x^0 .. "
                          f"x^{m + n}, got {count}")


def _sequence(an) -> list:
    """``an`` as a list (a sequence or a 1-D array of numbers), else SunsetError."""
    if (isinstance(an, (str, bytes, bytearray, dict, set)) or not hasattr(an, "__len__")
            or (isinstance(an, np.ndarray) and an.ndim != 1)):
        raise SunsetError(f"the coefficients must be a sequence of numbers, got {shown(an)}")
    values = list(an)
    for k, v in enumerate(values):
        if isinstance(v, np.ndarray) and v.ndim == 0:
            values[k] = v = v.item()
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, Fraction, np.integer, np.floating)):
            raise SunsetError(f"coefficient {k} must be a number (an int, a Fraction or a float), got {shown(v)}")
        if isinstance(v, (float, np.floating)) and not math.isfinite(v):
            raise SunsetError(f"coefficient {k} must be finite, got {shown(v)}")
    return values


def pade_coefficients(an, m: int, n: int) -> tuple[np.poly1d, np.poly1d]:
    """The Padé approximant p/q of the power series with coefficients ``an``: q of degree m, p of degree n.

    p and q (q(0) = 1) are fixed by the Taylor coefficients of q·f − p
    vanishing through order m + n, one linear system of m + n + 1 equations
    in the coefficients of p and q₁ … q_m: the construction of
    ``scipy.interpolate.pade`` (deprecated in SciPy 1.18, removed in 1.20),
    solved the same way, so the results are the same to the last bit.

    Returns
    -------
    p, q : numpy.poly1d

    Raises
    ------
    SunsetError
        For coefficients that are not finite numbers, degrees that are not
        whole numbers >= 0 or that need more coefficients than given, and
        (:class:`SingularPade`) a singular system.
    """
    an = real_array("coefficients", _sequence(an))
    if not np.all(np.isfinite(an)):
        raise SunsetError("the coefficients must be finite in float64")
    _check_degrees(m, n, len(an))
    N = m + n
    an = an[: N + 1]
    rows = np.zeros((N + 1, m))
    for row in range(1, N + 1):
        k = min(row, m)
        rows[row, :k] = -an[row - k:row][::-1]
    try:
        with warnings.catch_warnings():      # at high order the system is badly conditioned: said above
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            pq = scipy.linalg.solve(np.hstack((np.eye(N + 1, n + 1), rows)), an)
    except np.linalg.LinAlgError:
        raise SingularPade(f"the float64 system of the {n}/{m} Padé approximant is singular: lower m "
                           f"(pade_exact lowers it itself)") from None
    return np.poly1d(pq[: n + 1][::-1]), np.poly1d(np.r_[1.0, pq[n + 1:]][::-1])


class RationalPade(NamedTuple):
    """An exact Padé approximant: p_k = P_k / Q_0 and q_k = Q_k / Q_0 (so q(0) = 1), all P_k, Q_k integers."""

    P: tuple[int, ...]   #: numerator coefficients, power k at index k, times Q_0
    Q: tuple[int, ...]   #: denominator coefficients, times Q_0 (> 0)

    def fractions(self) -> tuple[tuple[Fraction, ...], tuple[Fraction, ...]]:
        """p and q as :class:`fractions.Fraction` coefficients, power k at index k."""
        return tuple(Fraction(c, self.Q[0]) for c in self.P), tuple(Fraction(c, self.Q[0]) for c in self.Q)

    def __call__(self, t) -> Fraction:
        """p(t)/q(t), exactly, for a rational t (an int, a Fraction or a float, taken as the number it is)."""
        values = _sequence([t])
        t = Fraction(values[0])
        num, den = _homogeneous(self.P, t), _homogeneous(self.Q, t)
        if den == 0:
            raise SunsetError(f"the Padé approximant has a pole at t = {t}")
        return Fraction(num * t.denominator ** (len(self.Q) - 1), den * t.denominator ** (len(self.P) - 1))


def _homogeneous(coeffs, t: Fraction) -> int:
    """v^d · Σ c_k (u/v)^k for t = u/v and d = len(coeffs) − 1, by Horner's rule in integers."""
    u, v = t.numerator, t.denominator
    acc, w = coeffs[-1], 1
    for c in coeffs[-2::-1]:
        w *= v
        acc = acc * u + c * w
    return acc


def pade_exact(an, m: int, n: int) -> RationalPade:
    """The [n/m] Padé approximant of Σ an[k] x^k in exact rational arithmetic.

    ``an`` holds integers, Fractions or floats (taken as the exact
    binary fractions they are). Where the m × m system is singular, the
    denominator's degree is lowered until it is not (the approximant then
    satisfies the definition through x^(n+m') for the m' found; a series that
    is a polynomial of degree <= n is its own approximant, q = 1).

    Returns
    -------
    RationalPade
        Integer coefficients; the system is verified exactly before returning.
    """
    an = _sequence(an)
    _check_degrees(m, n, len(an))
    a = [Fraction(v) for v in an[: m + n + 1]]
    L = math.lcm(*(v.denominator for v in a))
    G = [v.numerator * (L // v.denominator) for v in a]
    q = None
    while m > 0 and any(G[n + 1: n + m + 1]):
        q = _denominator(G, m, n)
        if q is not None:
            break
        m -= 1
    q = q if q is not None and m > 0 else [1]
    P = [sum(q[j] * G[k - j] for j in range(min(k, len(q) - 1) + 1)) for k in range(n + 1)]
    Q = [c * L for c in q]
    g = math.gcd(*P, *Q)
    return RationalPade(tuple(c // g for c in P), tuple(c // g for c in Q))


# --------------------------------------------------------------------------- modulo primes
_PRIMES: list[int] = []


def _primes(count: int) -> np.ndarray:
    """The ``count`` largest primes below 2³¹ (so that a product of two residues fits in int64)."""
    candidate = _PRIMES[-1] - 2 if _PRIMES else 2**31 - 1
    while len(_PRIMES) < count:
        if all(_strong_probable_prime(candidate, base) for base in (2, 7, 61)):  # exact below 4.7e9
            _PRIMES.append(candidate)
        candidate -= 2
    return np.array(_PRIMES[:count], dtype=np.int64)


def _strong_probable_prime(n: int, base: int) -> bool:
    d, s = n - 1, 0
    while d % 2 == 0:
        d, s = d // 2, s + 1
    x = pow(base, d, n)
    if x in (1, n - 1):
        return True
    for _ in range(s - 1):
        x = x * x % n
        if x == n - 1:
            return True
    return False


def _residues(G, p: np.ndarray) -> np.ndarray:
    """G[k] mod p[i] as an int64 array (len(p), len(G)), for integers G of any size.

    Horner's rule over the 32-bit digits of |G[k]|, for every prime at once.
    """
    width = max(1, (max(abs(v).bit_length() for v in G) + 31) // 32)
    digits = np.frombuffer(b"".join(abs(v).to_bytes(4 * width, "big") for v in G), dtype=">u4")
    digits = digits.reshape(len(G), width).astype(np.uint64)
    q = p.astype(np.uint64)[:, None]
    r = np.zeros((len(p), len(G)), dtype=np.uint64)
    for w in range(width):  # r < 2³¹, so r·2³² + digit < 2⁶³
        r = ((r << np.uint64(32)) | digits[:, w]) % q
    r = r.astype(np.int64)
    return np.where(np.array([v < 0 for v in G]), -r % p[:, None], r)


def _inverse(a: np.ndarray, p: np.ndarray) -> np.ndarray:
    """a^(p−2) mod p (Fermat), elementwise: the inverse of a modulo the prime p < 2³¹, 0 for a ≡ 0."""
    e, out, base = p - 2, np.ones_like(a), a % p
    for bit in range(31):
        out = np.where((e >> bit) & 1 == 1, out * base % p, out)
        base = base * base % p
    return out


def _levinson(g: np.ndarray, m: int, n: int, p: np.ndarray):
    """Solve Σ_j g[n+i−j] x_j = −g[n+1+i] (i, j < m) modulo each prime by Levinson's recursion.

    Returns x (len(p), m) and the primes modulo which every leading minor is regular (the others failed).
    """
    P = p[:, None]
    t = np.zeros((len(p), 2 * m - 1), dtype=np.int64)   # t[:, m − 1 + d] = g[n + d]
    lo = max(0, m - 1 - n)
    t[:, lo:] = g[:, n - (m - 1) + lo: n + m]
    y = -g[:, n + 1: n + m + 1] % P
    ok = t[:, m - 1] != 0
    f = b = _inverse(t[:, m - 1], p)[:, None]          # T_k f = e_first, T_k b = e_last
    x = y[:, :1] * f % P
    for k in range(1, m):
        row, up = t[:, m - 1 + k: m - 1: -1], t[:, m - 2: m - 2 - k if m - 2 - k >= 0 else None: -1]
        ef = (row * f % P).sum(axis=1) % p
        eb = (up * b % P).sum(axis=1) % p
        s = (1 - ef * eb) % p
        ok &= s != 0
        s = _inverse(s, p)[:, None]
        fe, be = np.pad(f, ((0, 0), (0, 1))), np.pad(b, ((0, 0), (1, 0)))
        f = (fe - ef[:, None] * be % P) % P * s % P
        b = (be - eb[:, None] * fe % P) % P * s % P
        ex = (row * x % P).sum(axis=1) % p
        x = (np.pad(x, ((0, 0), (0, 1))) + (y[:, k] - ex)[:, None] % P * b % P) % P
    return x, ok


def _eliminate(g: np.ndarray, m: int, n: int, p: np.ndarray):
    """The same system by Gauss–Jordan elimination with row pivoting (where Levinson's recursion fails)."""
    P = p[:, None, None]
    i = np.arange(m)
    index = n + i[:, None] - i[None, :]
    T = np.where(index >= 0, g[:, np.maximum(index, 0)], 0)
    A = np.concatenate([T, -g[:, n + 1: n + m + 1, None]], axis=2) % P
    rows, ok = np.arange(len(p)), np.ones(len(p), dtype=bool)
    for k in range(m):
        nonzero = A[:, k:, k] != 0
        ok &= nonzero.any(axis=1)
        pivot = k + np.argmax(nonzero, axis=1)
        A[rows, k], A[rows, pivot] = A[rows, pivot], A[rows, k].copy()
        A[:, k, k:] = A[:, k, k:] * _inverse(A[:, k, k], p)[:, None] % P[:, 0]
        factor = A[:, :, k].copy()
        factor[:, k] = 0
        A[:, :, k:] = (A[:, :, k:] - factor[:, :, None] * A[:, k, None, k:] % P) % P
    return A[:, :, m], ok


def _crt(items: list[tuple[list[int], int]]) -> tuple[list[int], int]:
    """The integers ≡ X_i (mod M_i) for every (X_i, M_i) of ``items``, modulo Π M_i: pairwise, as a tree."""
    while len(items) > 1:
        pairs = []
        for (X1, M1), (X2, M2) in zip(items[0::2], items[1::2]):
            inverse = pow(M1, -1, M2)
            pairs.append(([a + M1 * ((b - a) * inverse % M2) for a, b in zip(X1, X2)], M1 * M2))
        items = pairs + items[len(pairs) * 2:]
    return items[0]


def _crt_pairs(x: np.ndarray, p: np.ndarray) -> list[tuple[list[int], int]]:
    """The first level of :func:`_crt` in int64: residues modulo pairs of primes (products below 2⁶²)."""
    k = len(p) // 2 * 2
    p1, p2, x1, x2 = p[0:k:2], p[1:k:2], x[0:k:2], x[1:k:2]
    h = (x2 - x1) % p2[:, None] * _inverse(p1 % p2, p2)[:, None] % p2[:, None]
    items = list(zip((x1 + p1[:, None] * h).tolist(), (p1 * p2).tolist()))
    return items + list(zip(x[k:].tolist(), p[k:].tolist()))


def _denominator(G, m: int, n: int):
    """Integers q = (d, a_1 … a_m), d > 0: Σ_j q_j G[k − j] = 0 for k = n+1 … n+m.

    None where the system is singular modulo every prime tried (so singular).
    """
    X, M, used, candidate = None, 1, 0, None
    while True:
        count = 4 if candidate else max(64, used)  # 4 fresh primes test a candidate
        p = _primes(used + count)[used:]
        used += count
        g = _residues(G, p)
        x, ok = _levinson(g, m, n, p)
        if not ok.all():  # a leading minor vanishes: eliminate with pivoting
            x[~ok], ok[~ok] = _eliminate(g[~ok], m, n, p[~ok])
        if not ok.any():
            return None
        x, p = x[ok], p[ok]
        if candidate:
            d, a = candidate
            if _agrees(d, a, x, p) and _satisfies(G, m, n, [d] + a):
                return [d] + a
        items = _crt_pairs(x, p)
        X, M = _crt(items if X is None else [(X, M)] + items)
        candidate = None if candidate else _reconstruct(X, M)


def _agrees(d: int, a: list[int], x: np.ndarray, p: np.ndarray) -> bool:
    """Whether a/d ≡ x modulo each prime p."""
    primes = p.tolist()
    dp = np.array([d % q for q in primes], dtype=np.int64)
    ap = np.array([[v % q for v in a] for q in primes], dtype=np.int64)
    return bool(np.array_equal(dp[:, None] * x % p[:, None], ap))


def _reconstruct(X: list[int], M: int):
    """(d, [a_j]) with a_j/d ≡ X_j (mod M) and |a_j|, d <= √(M/2), or None."""
    bound = math.isqrt(M // 2)
    d, nums = 1, []
    for v in X:
        y = d * v % M
        a = y if y <= M // 2 else y - M
        if abs(a) > bound:
            r, t = _half_euclid(M, y, bound)
            if t == 0 or abs(t) > bound or d * abs(t) > bound:
                return None
            a, b = (r, t) if t > 0 else (-r, -t)
            d, nums = d * b, [u * b for u in nums]
        nums.append(a)
    return d, nums


def _half_euclid(r0: int, r1: int, bound: int) -> tuple[int, int]:
    """The extended Euclidean algorithm on (r0, r1), stopped at the first remainder r <= bound.

    Returns r and its cofactor t (r ≡ t·r1 mod r0): Wang's rational reconstruction.
    Lehmer's method: while the remainders are long, the quotients are found from
    their leading 60 bits, in small integers, and applied to the long ones at once.
    """
    t0, t1 = 0, 1
    while r1.bit_length() > bound.bit_length() + 64:
        shift = r0.bit_length() - 60
        a, b = r0 >> shift, r1 >> shift
        A, B, C, D = 1, 0, 0, 1
        while b + C != 0 and b + D != 0:
            q = (a + A) // (b + C)
            if q != (a + B) // (b + D):  # the leading bits no longer decide the quotient
                break
            A, B, C, D, a, b = C, D, A - q * C, B - q * D, b, a - q * b
        if B == 0:
            q = r0 // r1
            r0, r1, t0, t1 = r1, r0 - q * r1, t1, t0 - q * t1
        else:
            r0, r1, t0, t1 = A * r0 + B * r1, C * r0 + D * r1, A * t0 + B * t1, C * t0 + D * t1
    while r1 > bound:
        q = r0 // r1
        r0, r1, t0, t1 = r1, r0 - q * r1, t1, t0 - q * t1
    return r1, t1


def _satisfies(G, m: int, n: int, q) -> bool:
    return all(sum(q[j] * G[k - j] for j in range(m + 1) if j <= k) == 0 for k in range(n + 1, n + m + 1))
