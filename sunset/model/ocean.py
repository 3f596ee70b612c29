"""A periodic tile of sea on Max's lattice, synthesised by FFT (Tessendorf's recipe, Max's loop).

The tile is an N × N grid over L × L metres, repeated to cover the plane. Its
height is a finite Fourier series over the lattice k = (2π/L)(m, n),
−N/2 < m, n < N/2 (the Nyquist row and column, and k = 0, are left empty):

    z(x, t) = Σ_k ẑ(k, t) e^{i k·x},   ẑ(k, t) = h₀(k) e^{−iω(k)t} + conj(h₀(−k)) e^{iω(k)t},

(Tessendorf 2001, with e^{−iωt} so that h₀(k) runs along k). ẑ(−k) = conj(ẑ(k)),
so z is real; one inverse real FFT makes the whole grid at one instant.

Max's loop. Every ω is put on the lattice of multiples of ω₀ = 2π/T,

    ω(k) = n(k) ω₀,   n(k) = max(1, round(√(g|k|)/ω₀)),

so that the tile repeats after the cycle T exactly, as Max's λ/n² ladder made
his trains repeat. The dispersion relation is bent by at most ω₀/2 (a
relative error ω₀/(2ω), largest for the longest waves; see
:meth:`OceanTile.dispersion_error`). Time enters only as the phase n ω₀ (t mod T).

Slopes come from the same FFT, ∂z/∂x ↔ i k_x ẑ, not from differences. The
optional choppy displacement (Tessendorf's λ D, here with D̂ = i (k/|k|) ẑ so
that λ = 1 turns one component into Gerstner's trochoid) moves the grid's
points to x + λ D(x); its Jacobian J = (1 + λ D_xx)(1 + λ D_yy) − λ² D_xy²
falls to 0 where the surface folds.

Between grid points the fields are interpolated bilinearly. The interpolant
of a grid is a convex combination of four grid values, so the grid's largest
|z| bounds the interpolated sea exactly (:meth:`OceanTile.bound`); the
interpolation's error is stated per tile (:meth:`OceanTile.interpolation_error`).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..constants import GRAVITY
from ..errors import SunsetError, require_int_range, require_range

#: Fixed-point iterations that invert the choppy map x ↦ x + λ D(x) for an Eulerian height.
CHOPPY_ITERATIONS = 12
#: The smallest and largest N of a tile (a power of two).
MIN_POINTS, MAX_POINTS = 8, 1024
#: The oversampling factors a tile's grids may have.
OVERSAMPLES = (1, 2, 4)


def lattice(n: int, size: float) -> tuple[np.ndarray, np.ndarray]:
    """(k_x, k_y) of an n × n tile of side ``size``, each (n, n), rad m⁻¹ (FFT order; [i, j] ↔ y_i, x_j)."""
    k = 2.0 * math.pi * np.fft.fftfreq(n, d=size / n)
    return np.meshgrid(k, k)


def resolved_mask(n: int) -> np.ndarray:
    """True on the lattice points the tile holds: not k = 0, not the Nyquist row or column."""
    m = np.fft.fftfreq(n, d=1.0 / n)
    ok = np.abs(m) < n // 2
    mask = ok[None, :] & ok[:, None]
    mask[0, 0] = False
    return mask


class OceanTile:
    """A periodic, time-periodic height field from complex amplitudes h₀(k).

    Parameters
    ----------
    h0 : ndarray, complex, (N, N)
        h₀(k) in FFT order ([i, j] ↔ k_y = 2π i'/L, k_x = 2π j'/L); entries off
        :func:`resolved_mask` are ignored.
    size : float
        L, metres (> 0).
    cycle : float
        T, seconds (> 0): every ω is a multiple of 2π/T.
    choppiness : float
        λ in [0, 1]; 0 for a pure height field.
    gravity : float
        g, m s⁻², of ω = √(g k) before it is bent.
    oversample : int
        1, 2 or 4: the grids are synthesised at oversample·N points a side
        (the same components, zero-padded), so that bilinear interpolation
        meets no component above a quarter (2) or an eighth (4) of the grid's
        sampling rate. Memory and FFT time grow as its square.
    """

    def __init__(self, h0, size: float, cycle: float, choppiness: float = 0.0, gravity: float = GRAVITY,
                 oversample: int = 1):
        h0 = np.asarray(h0)
        if h0.ndim != 2 or h0.shape[0] != h0.shape[1] or not np.iscomplexobj(h0):
            raise SunsetError(f"h0 must be a square complex array, got shape {h0.shape} of {h0.dtype}")
        n = h0.shape[0]
        require_int_range("points", n, MIN_POINTS, MAX_POINTS)
        if n & (n - 1):
            raise SunsetError(f"points must be a power of two, got {n}")
        require_range("size", size, 0.0, 1e5, "m", lo_open=True)
        require_range("cycle", cycle, 0.0, 1e5, "s", lo_open=True)
        require_range("choppiness", choppiness, 0.0, 1.0)
        require_range("gravity", gravity, 0.0, 100.0, "m/s²", lo_open=True)
        if isinstance(oversample, bool) or oversample not in OVERSAMPLES:
            raise SunsetError(f"oversample must be one of {', '.join(map(str, OVERSAMPLES))}, got {oversample!r}")
        if not np.all(np.isfinite(h0)):
            raise SunsetError("h0 must be finite")
        self.n, self.size, self.cycle = n, float(size), float(cycle)
        self.choppiness, self.gravity = float(choppiness), float(gravity)
        self.oversample = int(oversample)
        self.grid_points = n * self.oversample
        self.spacing = self.size / self.grid_points
        self.omega0 = 2.0 * math.pi / self.cycle
        self.kx, self.ky = lattice(n, self.size)
        self.k = np.hypot(self.kx, self.ky)
        self.mask = resolved_mask(n)
        self.h0 = np.where(self.mask, h0, 0.0).astype(complex)
        self.h0_minus = np.conj(np.roll(self.h0[::-1, ::-1], 1, axis=(0, 1)))     # conj(h₀(−k))
        # max-lattice-begin: ω bent onto the multiples n ω₀ of ω₀ = 2π/T
        self.true_omega = np.sqrt(self.gravity * self.k)
        n = np.maximum(1, np.rint(self.true_omega / self.omega0))
        self.harmonic = np.where(self.mask, n, 0).astype(np.int64)
        self.omega = self.harmonic * self.omega0
        # max-lattice-end
        self._cache: tuple[float, dict] | None = None

    # -- the spectrum in time -------------------------------------------------------
    def phase(self, t: float) -> np.ndarray:
        """ω(k) (t mod T), radians: how time enters (so z(t + T) = z(t))."""
        tau = math.fmod(float(t), self.cycle)
        return self.omega * tau

    def amplitudes(self, t: float) -> np.ndarray:
        """ẑ(k, t) = h₀(k) e^{−iωt} + conj(h₀(−k)) e^{iωt}, (N, N), Hermitian."""
        if not math.isfinite(float(t)):
            raise SunsetError(f"t must be a finite time in seconds, got {t!r}")
        p = self.phase(t)
        c, s = np.cos(p), np.sin(p)
        return self.h0 * (c - 1j * s) + self.h0_minus * (c + 1j * s)

    @property
    def power(self) -> np.ndarray:
        """|h₀(k)|² + |h₀(−k)|²: the time-mean of |ẑ(k, t)|², m²."""
        return np.abs(self.h0) ** 2 + np.abs(self.h0_minus) ** 2

    def _synth(self, spec: np.ndarray) -> np.ndarray:
        n, m = self.n, self.grid_points
        half = spec[:, : n // 2 + 1] * (m * m)
        if m != n:                                   # zero-pad: rows by signed index, columns 0..N/2
            padded = np.zeros((m, m // 2 + 1), dtype=complex)
            rows = np.fft.fftfreq(n, d=1.0 / n).astype(np.intp) % m
            padded[rows, : n // 2 + 1] = half
            half = padded
        return np.fft.irfft2(half, s=(m, m))

    def fields(self, t: float) -> dict[str, np.ndarray]:
        """The grid at time t: ``z``, ``zx``, ``zy`` (and ``dx``, ``dy``, ``dxx``, ``dxy``, ``dyy`` if choppy).

        Each (M, M) float64 with M = oversample·N, [i, j] at (x, y) = (j, i) L/M.
        The last time's fields are kept (replaced whole, so threads that sample
        strips at one t share them safely), so a strip after a strip at one t
        costs no FFT.
        """
        t = float(t)
        if self._cache is not None and self._cache[0] == t:
            return self._cache[1]
        spec = self.amplitudes(t)
        out = {"z": self._synth(spec), "zx": self._synth(1j * self.kx * spec), "zy": self._synth(1j * self.ky * spec)}
        if self.choppiness > 0:
            with np.errstate(invalid="ignore", divide="ignore"):
                ux, uy = np.where(self.mask, self.kx / self.k, 0.0), np.where(self.mask, self.ky / self.k, 0.0)
            out["dx"], out["dy"] = self._synth(1j * ux * spec), self._synth(1j * uy * spec)
            out["dxx"] = self._synth(-self.kx * ux * spec)
            out["dxy"] = self._synth(-self.kx * uy * spec)
            out["dyy"] = self._synth(-self.ky * uy * spec)
        self._cache = (t, out)
        return out

    def jacobian(self, t: float) -> np.ndarray:
        """J = (1 + λD_xx)(1 + λD_yy) − λ²D_xy² on the grid (1 everywhere when λ = 0)."""
        if self.choppiness == 0:
            return np.ones((self.grid_points, self.grid_points))
        f, lam = self.fields(t), self.choppiness
        return (1.0 + lam * f["dxx"]) * (1.0 + lam * f["dyy"]) - lam * lam * f["dxy"] ** 2

    def folded_fraction(self, t: float) -> float:
        """The share of grid points where the choppy surface folds over (J ≤ 0)."""
        return float(np.mean(self.jacobian(t) <= 0.0))

    # -- evaluation anywhere --------------------------------------------------------
    def _bilinear(self, grids, x, y):
        """Each of ``grids`` interpolated bilinearly, periodically, at (x, y)."""
        u = np.asarray(x, dtype=float) / self.spacing
        v = np.asarray(y, dtype=float) / self.spacing
        u, v = np.broadcast_arrays(u, v)
        i0, j0 = np.floor(v), np.floor(u)
        fv, fu = v - i0, u - j0
        m = self.grid_points
        i0 = np.mod(i0, m).astype(np.intp)
        j0 = np.mod(j0, m).astype(np.intp)
        i1, j1 = (i0 + 1) % m, (j0 + 1) % m
        w00, w01 = (1 - fv) * (1 - fu), (1 - fv) * fu
        w10, w11 = fv * (1 - fu), fv * fu
        return [w00 * g[i0, j0] + w01 * g[i0, j1]
                + w10 * g[i1, j0] + w11 * g[i1, j1] for g in grids]

    def sample(self, x, y, t: float):
        """(z, ∂z/∂x, ∂z/∂y) at points (x, y) (metres, any broadcast shape) at time t.

        Bilinear interpolation of the FFT grids of z and its gradient (the
        gradient is the interpolated FFT gradient, not the slope of the
        interpolated z). With choppiness λ > 0 the point x is first carried
        back through the choppy map, x₀ = x − λ D(x₀) (CHOPPY_ITERATIONS fixed-point
        steps, a contraction wherever λ|∇D| < 1), and the slope is
        (I + λ∇D)⁻ᵀ ∇z at x₀. NaN in, NaN out.
        """
        f = self.fields(t)
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        bad = ~(np.isfinite(x) & np.isfinite(y))
        x, y = np.where(bad, 0.0, x), np.where(bad, 0.0, y)
        if self.choppiness == 0:
            z, zx, zy = self._bilinear((f["z"], f["zx"], f["zy"]), x, y)
        else:
            lam, x0, y0 = self.choppiness, x, y
            for _ in range(CHOPPY_ITERATIONS):
                dx, dy = self._bilinear((f["dx"], f["dy"]), x0, y0)
                x0, y0 = x - lam * dx, y - lam * dy
            z, gx, gy, axx, axy, ayy = self._bilinear((f["z"], f["zx"], f["zy"], f["dxx"], f["dxy"], f["dyy"]), x0, y0)
            a, b, d = 1.0 + lam * axx, lam * axy, 1.0 + lam * ayy                # M = [[a, b], [b, d]]
            det = a * d - b * b
            with np.errstate(divide="ignore", invalid="ignore"):
                zx, zy = (d * gx - b * gy) / det, (a * gy - b * gx) / det
        nan = np.where(bad, np.nan, 0.0)
        return z + nan, zx + nan, zy + nan

    def heights(self, x, y, t: float):
        """z alone at points (x, y) at time t, as :meth:`sample`'s first field (bilinear; choppy: :meth:`sample`)."""
        if self.choppiness > 0:
            return self.sample(x, y, t)[0]
        f = self.fields(t)
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        bad = ~(np.isfinite(x) & np.isfinite(y))
        z = self._bilinear((f["z"],), np.where(bad, 0.0, x), np.where(bad, 0.0, y))[0]
        return np.where(bad, np.nan, z)

    def exact(self, x, y, t: float):
        """(z, ∂z/∂x, ∂z/∂y) by the direct sum of the Fourier series (no interpolation, no choppiness).

        O(points × N²): a reference for tests and small tiles, not for frames.
        """
        spec = self.amplitudes(t)[self.mask]
        kx, ky = self.kx[self.mask], self.ky[self.mask]
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        x, y = np.broadcast_arrays(x, y)
        e = np.exp(1j * (np.multiply.outer(x, kx) + np.multiply.outer(y, ky))) * spec
        return e.sum(-1).real, (e * (1j * kx)).sum(-1).real, (e * (1j * ky)).sum(-1).real

    # -- bounds and errors ----------------------------------------------------------
    def bound(self, t: float) -> float:
        """max |z| over the grid at t: bounds the interpolated (and choppy) sea at t exactly, metres."""
        return float(np.max(np.abs(self.fields(t)["z"])))

    @functools.cached_property
    def bound_every_time(self) -> float:
        """A bound on |z| of the interpolated (and choppy) sea at every point and every time, metres (tight).

        Time enters only as the harmonics n ω₀ of the lattice, so at a grid
        point x the height is Σ_n (A_n(x) e^{−inω₀t} + B_n(x) e^{inω₀t}), A_n
        and B_n the inverse FFTs of h₀ and conj(h₀(−k)) over the components
        of harmonic n; hence |z(x, t)| ≤ Σ_n (|A_n(x)| + |B_n(x)|) for every
        t. Its largest value over the grid bounds the interpolant (a convex
        combination of grid values) and the choppy sea (the heights of moved
        points). One pair of FFTs per harmonic, computed once; within a
        factor of about two of the largest height a cycle reaches (chapter 14),
        where :attr:`bound_all_times` is ten times looser.
        """
        m = self.grid_points
        rows = np.fft.fftfreq(self.n, d=1.0 / self.n).astype(np.intp) % m
        total = np.zeros((m, m))
        for n in np.unique(self.harmonic[self.mask]):
            sel = self.mask & (self.harmonic == n)
            for amp in (self.h0, self.h0_minus):
                full = np.zeros((m, m), dtype=complex)
                full[np.ix_(rows, rows)] = np.where(sel, amp, 0.0)
                total += np.abs(np.fft.ifft2(full)) * (m * m)
        return float(total.max())

    @property
    def bound_all_times(self) -> float:
        """Σ_k (|h₀(k)| + |h₀(−k)|): a bound on |z| at every point and every time, metres (loose)."""
        return float(np.sum(np.abs(self.h0)) + np.sum(np.abs(self.h0_minus)))

    def interpolation_error(self) -> dict[str, float]:
        """What bilinear interpolation costs this tile, over uniformly random points and times.

        For one component e^{iθu} sampled at integer u (θ = k_x Δ), the
        interpolant on [0, 1] is (1 − u) + u e^{iθ}; its mean square
        A = (2 + cos θ)/3 and its mean product with the truth B = 2(1 − cos θ)/θ²
        give the mean-square error A_x A_y − 2 B_x B_y + 1 of the tensor
        product. Summed with the tile's powers |h₀(k)|² + |h₀(−k)|²:

        ``rms_z``, ``rms_zx``, ``rms_zy``: the rms errors of z (metres) and of
        the slopes; ``max_z``: a bound on |error of z| anywhere, any time,
        Σ (|h₀(k)| + |h₀(−k)|)(ε(θ_x) + ε(θ_y)), ε(θ) = max_u |(1 − u) + u e^{iθ} − e^{iθu}|.
        """
        tx, ty = self.kx * self.spacing, self.ky * self.spacing

        def ab(theta):
            with np.errstate(invalid="ignore", divide="ignore"):
                b = np.where(theta == 0, 1.0, 2.0 * (1.0 - np.cos(theta)) / np.where(theta == 0, 1.0, theta) ** 2)
            return (2.0 + np.cos(theta)) / 3.0, b

        (ax, bx), (ay, by) = ab(tx), ab(ty)
        ms = np.maximum(ax * ay - 2.0 * bx * by + 1.0, 0.0)
        p = np.where(self.mask, self.power, 0.0)
        u = np.linspace(0.0, 1.0, 257)
        theta = 2.0 * math.pi * np.fft.fftfreq(self.n) / self.oversample
        eps_1d = np.abs((1 - u)[None, :] + u[None, :] * np.exp(1j * theta)[:, None]
                        - np.exp(1j * np.outer(theta, u))).max(axis=1)
        eps = eps_1d[None, :] + eps_1d[:, None]                          # [i, j]: ε(θ_y,i) + ε(θ_x,j)
        amp = np.abs(self.h0) + np.abs(self.h0_minus)
        return {"rms_z": math.sqrt(float(np.sum(p * ms))), "rms_zx": math.sqrt(float(np.sum(self.kx ** 2 * p * ms))),
                "rms_zy": math.sqrt(float(np.sum(self.ky ** 2 * p * ms))), "max_z": float(np.sum(amp * eps))}

    def dispersion_error(self, weights=None, share: float = 0.99) -> dict[str, float]:
        """How far Max's lattice bends ω = √(g k) on this tile.

        The relative error (ω_lattice − ω)/ω, which is also the phase speed's,
        over the components that hold ``share`` of the tile's variance
        (``weights``: the variance per component; the tile's powers by
        default): ``max`` (largest |error|), ``rms`` (variance-weighted), and
        ``k_min`` (rad m⁻¹), the longest wave counted.
        """
        w = np.where(self.mask, self.power if weights is None else weights, 0.0).ravel()
        rel = (np.where(self.mask, self.omega / np.where(self.mask, self.true_omega, 1.0), 1.0) - 1.0).ravel()
        order = np.argsort(w)[::-1]
        cum = np.cumsum(w[order])
        keep = order[: int(np.searchsorted(cum, share * cum[-1])) + 1]
        ww = w[keep] / w[keep].sum()
        return {"max": float(np.max(np.abs(rel[keep]))), "rms": float(np.sqrt(np.sum(ww * rel[keep] ** 2))),
                "k_min": float(self.k.ravel()[keep].min())}
