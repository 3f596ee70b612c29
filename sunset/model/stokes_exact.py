"""The exact Stokes wave on deep water, computed numerically (Babenko's equation).

The paper's expansion (:mod:`sunset.model.stokes`) is checked against waves
solved here to rounding error.

The exact solver
----------------
The fluid below the surface is the conformal image of the lower half plane
w = u + iv, the surface being the image of the real line v = 0:

    x(u) = u + Σ_{n>=1} y_n sin n u,      y(u) = Σ_{n>=0} y_n cos n u,

so that z = x + i y = w + i Σ y_n e^{−inw} is analytic and tends to w at
great depth. In the frame of the wave the complex potential is −c w, the
surface is a streamline, and Bernoulli's law ½|velocity|² + g y = const on it
becomes Babenko's (1987) equation

    c² 𝒦y − y − y 𝒦y − ½ 𝒦(y²) = 0,      𝒦 = H ∂_u  (𝒦 cos n u = n cos n u),

with H the periodic Hilbert transform. Its mean (n = 0) component says that
the mean level of the Eulerian elevation is zero. With the wave height
y(0) − y(π) = kH given, the unknowns are the surface y and the speed c.

The equation is collocated at the points q_m = m π / N, m = 0..N of an
auxiliary variable q with u = 2 arctan(L tan(q/2)) (Lushnikov, Dyachenko &
Silantyev 2017): the map is conformal, so Hilbert transforms in u and q differ
only by a constant, and for L < 1 it crowds the points at the crest, where a
steep wave bends sharply. Newton's method (dense Jacobian, LU factorization
with SciPy) solves the collocation equations, continued in steps of k·H from
a linear wave; the number of modes N doubles until the spectrum's tail is
below :data:`~sunset.constants.STOKES_TAIL_TOLERANCE`. The Eulerian
coefficients a_n follow by quadrature, a_n = (1/π)∮ y cos(n x) dx taken in q.
"""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import scipy.linalg

from ..constants import (
    STOKES_COARSE_MODES,
    STOKES_CONTINUATION_STEP,
    STOKES_MAP_FACTOR,
    STOKES_MAX_MODES,
    STOKES_MAP_STEEPNESS,
    STOKES_MAX_STEEPNESS,
    STOKES_MAX_SURFACE_POINTS,
    STOKES_MIN_MODES,
    STOKES_NEWTON_ITERATIONS,
    STOKES_NEWTON_TOLERANCE,
    STOKES_TAIL_TOLERANCE,
)
from ..errors import SunsetError, real_number, require_finite, require_int_range

__all__ = ["StokesWave", "StokesSurface", "solve_stokes"]


# --------------------------------------------------------------------------- the exact solver
class _Operators(NamedTuple):
    """Collocation grid and linear operators for N modes and map parameter L."""

    q: np.ndarray        # nodes q_m = m π / N, m = 0..N
    u: np.ndarray        # u(q_m)
    du: np.ndarray       # u'(q_m)
    cos: np.ndarray      # cos(n q_m): node values from cosine coefficients
    dct: np.ndarray      # cosine coefficients from node values (DCT-I)
    K: np.ndarray        # 𝒦 = H ∂_u acting on node values


def _map(q, L: float):
    """u(q) = 2 arctan(L tan(q/2)), continued so that u(q + 2π) = u(q) + 2π; and u'(q)."""
    q = np.asarray(q, dtype=float)
    turns = np.round(q / (2.0 * np.pi))
    r = q - 2.0 * np.pi * turns
    u = 2.0 * np.arctan2(L * np.sin(r / 2), np.cos(r / 2)) + 2.0 * np.pi * turns
    du = L / (np.cos(q / 2) ** 2 + (L * np.sin(q / 2)) ** 2)
    return u, du


@functools.lru_cache(maxsize=8)
def _operators(n_modes: int, L: float) -> _Operators:
    N = n_modes
    q = np.pi * np.arange(N + 1) / N
    modes = np.arange(N + 1)
    cos = np.cos(np.outer(q, modes))
    w = np.ones(N + 1)
    w[[0, N]] = 0.5
    dct = (2.0 / N) * (cos.T * w)
    dct[[0, N]] *= 0.5
    u, du = _map(q, L)
    inner = np.arange(1, N)
    sin = np.sin(np.outer(q, inner))
    derivative = sin @ (-inner[:, None] * dct[1:N])        # ∂_q: even node values -> odd
    hilbert = -cos[:, 1:N] @ ((2.0 / N) * sin.T)            # H_q: odd -> even (H sin nq = −cos nq)
    K = hilbert @ (derivative / du[:, None])                # H_q (1/u') ∂_q ...
    K -= np.outer(np.ones(N + 1), ((w * du) / N) @ K)       # ... minus its mean over u
    for arr in (q, u, du, cos, dct, K):
        arr.flags.writeable = False
    return _Operators(q, u, du, cos, dct, K)


def _newton(y, c, height, ops: _Operators):
    """Newton's method on the collocated Babenko equation; None if it fails."""
    N = len(y) - 1
    K = ops.K
    J = np.zeros((N + 2, N + 2))
    J[N + 1, 0], J[N + 1, N] = 1.0, -1.0
    F = np.empty(N + 2)
    diag = np.diag_indices(N + 1)
    for iteration in range(1, STOKES_NEWTON_ITERATIONS + 1):
        Ky = K @ y
        F[: N + 1] = c * c * Ky - y - y * Ky - 0.5 * (K @ (y * y))
        F[N + 1] = y[0] - y[N] - height
        J[: N + 1, : N + 1] = c * c * K - y[:, None] * K - K * y[None, :]
        J[diag] -= 1.0 + Ky
        J[: N + 1, N + 1] = 2.0 * c * Ky
        with warnings.catch_warnings():
            warnings.simplefilter("error", scipy.linalg.LinAlgWarning)
            try:
                lu = scipy.linalg.lu_factor(J, check_finite=False)
                step = scipy.linalg.lu_solve(lu, -F,
                                             check_finite=False)
            except (scipy.linalg.LinAlgWarning, np.linalg.LinAlgError, ValueError):
                return None
        if not np.all(np.isfinite(step)):
            return None
        y = y + step[: N + 1]
        c = c + step[N + 1]
        if np.max(np.abs(step)) < STOKES_NEWTON_TOLERANCE:
            return y, c, iteration
    return None


def _continuation(height: float, ops: _Operators):
    """Follow the Stokes branch from a linear wave up to k·H = ``height``.

    Returns (y at the nodes, c, Newton iterations in all). Raises
    :class:`SunsetError` when the steps shrink below 1e-5 without converging.
    """
    done: list[tuple[float, np.ndarray, float]] = []
    step = min(STOKES_CONTINUATION_STEP, height)
    reached, iterations = 0.0, 0
    while reached < height:
        target = min(reached + step, height)
        if len(done) >= 2:  # secant predictor along the branch
            (h1, y1, c1), (h2, y2, c2) = done[-2:]
            t = (target - h2) / (h2 - h1)
            y0, c0 = y2 + t * (y2 - y1), c2 + t * (c2 - c1)
        elif done:
            h2, y2, c2 = done[-1]
            y0, c0 = y2 * (target / h2), c2
        else:  # the linear wave: y = (H/2) cos u, c = 1
            y0, c0 = 0.5 * target * np.cos(ops.u), 1.0
        result = _newton(y0, c0, target, ops)
        if result is None:
            step /= 2.0
            if step < 1e-5:
                raise SunsetError(
                    f"steepness {height / (2 * np.pi):.6g}: the exact Stokes "
                    "solver did not converge beyond "
                    f"H/λ = {reached / (2 * np.pi):.6g} "
                    "(too close to the highest wave, "
                    f"H/λ = {STOKES_MAX_STEEPNESS})")
            continue
        y, c, its = result
        iterations += its
        done = done[-1:] + [(target, y, c)]
        reached = target
    return done[-1][1], done[-1][2], iterations


class StokesSurface(NamedTuple):
    """Points on the exact surface over one wavelength, crest in the middle."""

    x: np.ndarray          #: k x, from −π to π
    elevation: np.ndarray  #: k z, elevation about the mean level
    speed: np.ndarray      #: speed of the water along the surface, in the wave's frame, /√(g/k)


@dataclass(frozen=True, eq=False)
class StokesWave:
    """An exact deep-water Stokes wave (from :func:`solve_stokes`).

    All quantities are dimensionless with the wave number k and gravity g.

    Attributes
    ----------
    steepness : float
        H/λ, crest-to-trough height over wavelength.
    height : float
        k·H = 2π H/λ.
    coefficients : ndarray (n_modes,)
        k·a_n, n = 1..n_modes: the Fourier cosine series of the Eulerian
        elevation about the mean level, crest at x = 0 (paper, eq. 2).
    speed : float
        Phase speed c/√(g/k) (relative to the water at great depth).
    alpha : float
        α = k·a₁, the maximum slope of the first harmonic.
    crest_curvature : float
        κ/k, curvature of the surface at the crest (positive: convex).
    trough_curvature : float
        Curvature over k at the trough (positive: concave up). Stokes waves
        have sharp crests and flat troughs: it stays below ``crest_curvature``.
    bernoulli : float
        Bernoulli's constant ½ q² + k z on the surface, in units of g/k,
        with q the water's speed in the wave's frame.
    residual : float
        Largest residual of Babenko's equation at the collocation points.
    tail : float
        Largest conformal Fourier coefficient in the last quarter of the modes:
        an estimate of the truncation error.
    n_modes : int
        Collocation points minus one (Fourier modes resolved).
    map_parameter : float
        L of the auxiliary map u = 2 arctan(L tan(q/2)).
    iterations : int
        Newton iterations along the whole continuation.
    """

    steepness: float
    height: float
    coefficients: np.ndarray = field(repr=False)
    speed: float
    alpha: float
    crest_curvature: float
    trough_curvature: float
    bernoulli: float
    residual: float
    tail: float
    n_modes: int
    map_parameter: float
    iterations: int
    conformal: np.ndarray = field(repr=False)  #: y_n: y(q) = Σ y_n cos n q, n = 0..n_modes
    _table_x: np.ndarray = field(repr=False, compare=False)
    _table_q: np.ndarray = field(repr=False, compare=False)

    @property
    def crest_elevation(self) -> float:
        """k z at the crest (above the mean level)."""
        return float(np.sum(self.conformal))

    @property
    def trough_elevation(self) -> float:
        """k z at the trough (negative: below the mean level)."""
        n = np.arange(len(self.conformal))
        return float(np.sum(self.conformal * (-1.0) ** n))

    def _series(self, q):
        """x(q), y(q), x'(q), y'(q) at arbitrary points q (1-D float64)."""
        n = np.arange(len(self.conformal))
        yn = self.conformal
        u, du = _map(q, self.map_parameter)
        x = np.empty_like(q)
        y = np.empty_like(q)
        xq = np.empty_like(q)
        yq = np.empty_like(q)
        chunk = max(1, 2**20 // len(n))
        for s in range(0, len(q), chunk):
            phase = np.outer(q[s:s + chunk], n)
            cn, sn = np.cos(phase), np.sin(phase)
            x[s:s + chunk] = u[s:s + chunk] + sn @ yn
            y[s:s + chunk] = cn @ yn
            xq[s:s + chunk] = du[s:s + chunk] + cn @ (n * yn)
            yq[s:s + chunk] = -(sn @ (n * yn))
        return x, y, xq, yq

    def profile(self, kx) -> np.ndarray:
        """Exact elevation k z at horizontal positions k x (crest at 0), any shape.

        The surface is known as a curve (x(q), y(q)); this inverts x(q) = k x by
        Newton's method, so it is exact (unlike a truncated Fourier series).
        """
        require_finite("kx", kx)
        X = np.asarray(kx, dtype=float)
        r = np.abs(np.remainder(X.ravel() + np.pi, 2 * np.pi) - np.pi)  # in [0, π]; the wave is even
        q = np.interp(r, self._table_x, self._table_q)
        for _ in range(4):
            x, _, xq, _ = self._series(q)
            q = np.clip(q - (x - r) / xq, 0.0, np.pi)
        return self._series(q)[1].reshape(X.shape)

    def surface(self, n_points: int = 513) -> StokesSurface:
        """The exact surface at ``n_points`` values of q spread over −π..π (3 to STOKES_MAX_SURFACE_POINTS).

        Points crowd at the crest (where the auxiliary map L < 1 puts them).
        Bernoulli's law says ½ speed² + elevation = :attr:`bernoulli` at every
        point: an independent check, since the solver never evaluates it.
        """
        require_int_range("n_points", n_points, 3, STOKES_MAX_SURFACE_POINTS)
        q = np.linspace(-np.pi, np.pi, n_points)
        x, y, xq, yq = self._series(q)
        _, du = _map(q, self.map_parameter)
        speed = self.speed * du / np.hypot(xq, yq)
        return StokesSurface(x, y, speed)

    def series_profile(self, kx, order: int = 4) -> np.ndarray:
        """Elevation of the paper's truncated series with this wave's α, at k x."""
        from .stokes_amplitudes import stokes_coefficients

        require_finite("kx", kx)
        amps = stokes_coefficients(self.alpha, order)
        X = np.remainder(np.asarray(kx, dtype=float), 2.0 * np.pi)   # n k x overflowed for k x near 1e308
        return sum(a * np.cos(n * X) for n, a in enumerate(amps, start=1))


def _default_map(steepness: float) -> float:
    gap = max(STOKES_MAP_STEEPNESS - steepness, 0.0)
    return float(min(1.0, max(0.02, STOKES_MAP_FACTOR * math.sqrt(gap))))


def solve_stokes(steepness: float, n_modes: int | None = None, map_parameter: float | None = None) -> StokesWave:
    """The exact periodic irrotational gravity wave on deep water of steepness H/λ.

    Solves Babenko's equation for the surface in conformal variables by Newton's
    method with continuation in the wave height (see the module docstring), in
    the spirit of Schwartz (1974), who extended Stokes' series by computer, and
    of Rienecker & Fenton (1981), who collocated the exact equations. Results
    are cached: the same arguments return the same object.

    Parameters
    ----------
    steepness : float
        H/λ, a number (not text) from 0 up to :data:`~sunset.constants.STOKES_MAX_STEEPNESS`
        (0.141063, the highest wave). Converged to 1e-12 or better up to 0.135;
        very close to the highest wave the solver may give up, with an error
        (after some seconds: it tries up to 1024 modes).
    n_modes : int, optional
        Collocation points minus one, 16 to :data:`~sunset.constants.STOKES_MAX_MODES`
        (1024: about 7 s; the cost grows as the cube, 2048 took 25 s and 4096 minutes,
        and are refused). Default: chosen by steepness and doubled until the
        spectrum's tail is below 1e-13 (at most 1024).
    map_parameter : float, optional
        L in (0, 1] of the auxiliary map; default
        min(1, 1.5 √(0.1411 − H/λ)), which crowds points at sharp crests.

    Returns
    -------
    StokesWave

    Raises
    ------
    SunsetError
        For a steepness that is NaN, negative or beyond the highest wave, a
        bad ``n_modes`` or ``map_parameter``, or when the solver cannot
        converge (very close to the highest wave).
    """
    s = real_number("steepness", steepness)
    if not 0.0 <= s <= STOKES_MAX_STEEPNESS:
        raise SunsetError(f"steepness must be in 0..{STOKES_MAX_STEEPNESS} (H/λ of the highest Stokes wave on "
                          f"deep water, Williams 1981), got {steepness!r}")
    if n_modes is not None:
        require_int_range("n_modes", n_modes, STOKES_MIN_MODES, STOKES_MAX_MODES)
        n_modes = int(n_modes)
    if map_parameter is not None:
        map_parameter = real_number("map_parameter", map_parameter)
        if not 0.0 < map_parameter <= 1.0:
            raise SunsetError(f"map_parameter must be in (0, 1], got {map_parameter!r}")
    return _solve(s, n_modes, map_parameter)


@functools.lru_cache(maxsize=128)
def _solve(steepness: float, n_modes: int | None, map_parameter: float | None) -> StokesWave:
    L = _default_map(steepness) if map_parameter is None else map_parameter
    if steepness == 0.0:
        return _wave(steepness, np.zeros((n_modes or STOKES_MIN_MODES) + 1), 1.0, L, 0.0, 0)
    height = 2.0 * np.pi * steepness
    # Continuation on a coarse grid, then Newton on finer and finer grids at the final height,
    # each started from the previous solution, until the tail of the spectrum is small.
    N = min(n_modes or STOKES_COARSE_MODES, STOKES_COARSE_MODES)
    ops = _operators(N, L)
    y, c, iterations = _continuation(height, ops)
    while True:
        yn = ops.dct @ y
        tail = float(np.max(np.abs(yn[(3 * N) // 4:])))
        if n_modes is not None and N == n_modes:
            break
        if n_modes is None and tail < STOKES_TAIL_TOLERANCE:
            break
        if n_modes is None and N >= STOKES_MAX_MODES:
            raise SunsetError(
                f"steepness {steepness:.6g}: the exact Stokes solver needs more than {STOKES_MAX_MODES} "
                f"modes this close to the highest wave (H/λ = {STOKES_MAX_STEEPNESS}); "
                f"truncation error {tail:.1e}")
        N = 2 * N if n_modes is None else min(2 * N, n_modes)
        ops = _operators(N, L)
        guess = ops.cos[:, : len(yn)] @ yn if len(yn) <= N + 1 else ops.cos @ yn[: N + 1]
        result = _newton(guess, c, height, ops)
        if result is None:  # fall back on continuation at this resolution
            y, c, its = _continuation(height, ops)
        else:
            y, c, its = result
        iterations += its
    Ky = ops.K @ y
    residual = float(np.max(np.abs(c * c * Ky - y - y * Ky - 0.5 * (ops.K @ (y * y)))))
    return _wave(steepness, yn, float(c), L, residual, iterations)


def _synthesis(yn: np.ndarray, L: float, M: int):
    """q, x(q), y(q), x'(q) at M points q = 2πj/M, by inverse real FFTs."""
    N = len(yn) - 1
    n = np.arange(N + 1)
    q = 2.0 * np.pi * np.arange(M) / M
    u, du = _map(q, L)
    spec = np.zeros(M // 2 + 1, dtype=complex)
    spec[: N + 1] = yn * (M / 2.0)
    spec[0] = yn[0] * M
    y = np.fft.irfft(spec, M)
    spec[: N + 1] = n * yn * (M / 2.0)
    xq = du + np.fft.irfft(spec, M)
    spec[: N + 1] = -1j * yn * (M / 2.0)
    spec[0] = 0.0
    x = u + np.fft.irfft(spec, M)
    return q, x, y, xq


def _wave(steepness: float, yn: np.ndarray, c: float, L: float, residual: float, iterations: int) -> StokesWave:
    """Post-process conformal coefficients into a :class:`StokesWave`."""
    N = len(yn) - 1
    n = np.arange(N + 1)
    # Fine uniform grid in q over a whole period: x(q), y(q), x'(q) by FFT synthesis,
    # fine enough for cos(N x(q)), whose local frequency in q is N x'(q).
    M = max(4096, 1 << int(math.ceil(math.log2(4 * N))))
    for _ in range(2):
        q, x, y, xq = _synthesis(yn, L, M)
        needed = 1 << int(math.ceil(math.log2(4.0 * N * (2.0 + np.max(np.abs(xq))))))
        if needed <= M:
            break
        M = needed
    # Eulerian coefficients a_k = (1/π) ∮ y cos(k x) dx = (2/M) Σ y x'(q) cos(k x(q)), k = 1..N.
    weight = y * xq * (2.0 / M)
    coefficients = np.empty(N)
    block = 32
    for k0 in range(1, N + 1, block):
        ks = np.arange(k0, min(k0 + block, N + 1))
        coefficients[ks - 1] = np.cos(np.outer(ks, x)) @ weight
    # Crest: y'' = −Σ n² y_n, x' = L + Σ n y_n at q = 0. The sums stop where the
    # coefficients reach their round-off plateau, which n² would otherwise amplify.
    tail = float(np.max(np.abs(yn[(3 * N) // 4:])))
    above = np.nonzero(np.abs(yn) > 10.0 * tail)[0]
    top = int(above[-1]) + 1 if len(above) else N + 1
    x_q0 = L + float(np.sum(n[:top] * yn[:top]))
    curvature = float(np.sum(n[:top] ** 2 * yn[:top])) / x_q0**2
    # Trough (q = π, where u' = 1/L): curvature y_xx = y_qq / x_q², positive (concave up).
    sign = (-1.0) ** n[:top]
    x_qpi = 1.0 / L + float(np.sum(sign * n[:top] * yn[:top]))
    trough_curvature = -float(np.sum(sign * n[:top] ** 2 * yn[:top])) / x_qpi**2
    bernoulli = 0.5 * (c * L / x_q0) ** 2 + float(np.sum(yn))
    half = slice(0, M // 2 + 1)  # q from 0 to π: x from 0 to π, increasing
    table_x, table_q = x[half].copy(), q[half].copy()
    table_x[-1] = np.pi
    for arr in (coefficients, yn, table_x, table_q):
        arr.flags.writeable = False
    return StokesWave(
        steepness=steepness, height=2.0 * np.pi * steepness, coefficients=coefficients, speed=c,
        alpha=float(coefficients[0]), crest_curvature=curvature, trough_curvature=trough_curvature,
        bernoulli=bernoulli,
        residual=residual, tail=tail, n_modes=N,
        map_parameter=L, iterations=iterations, conformal=yn, _table_x=table_x, _table_q=table_q)
