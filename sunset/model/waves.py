"""Waves on deep water: wave trains, the periodic sea and eq. 1.

A wave train is a long-crested travelling cosine

    z = a cos θ,   θ = ℓx + my − ωt + φ,   ℓ² + m² = k²,   ω = √(g k)

(deep-water dispersion: the phase speed is c = ω/k = √(g/k)). The sea's
gravity g is standard gravity unless a scene sets ``[sea] gravity`` (3.71 on
Mars): the sea owns it, and every train of a sea carries the sea's value. The sea is
their sum about the mean level (eq. 1, without the −h, which belongs to the
camera). A train may carry Stokes harmonics n = 2..4 (eq. 2):
a_n cos nθ, which travel with the train, so that harmonic n has frequency nω.

For a film loop (paper, after eq. 1) every ω_j must be a multiple of one
fundamental ω₁; since ω ∝ √k, the wavelengths must be λ, λ/4, λ/9, λ/16, …
(:meth:`Sea.periodic`), and then the sea repeats after T = 2π/ω₁
(:attr:`Sea.period`).

The surface and its gradient are evaluated in float64 whatever the input
dtype (a float32 phase ℓx + my is off by about 1e-7 of its size: 5e-5 rad for
a 2.5 m wave 300 m away, 7e-3 rad 40 km away, near the horizon) and returned
in the inputs' floating dtype. The harmonics cos nθ
and sin nθ come from one cos θ and one sin θ by the angle-addition recurrence,
the paper's remark that the first few terms of eq. 2 can be had "so that the
cosine need only be computed once".
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from fractions import Fraction

import numpy as np

from ..constants import (GRAVITY, MAX_DEGREES, MAX_GRAVITY, MAX_PHASE, MAX_TRAINS, MAX_WAVE_SLOPE, MAX_WAVELENGTH,
                         MIN_GRAVITY, MIN_WAVELENGTH)
from ..errors import (SunsetError, require_finite, require_time, require_int_range, require_items, require_nonnegative,
                      require_positive, require_range, require_scalars, shown)
from .stokes import stokes_coefficients
from .windsea import WindSea

#: Largest denominator accepted when :attr:`Sea.period` looks for the rational
#: ratios ω_j/ω_min of a repeating sea.
PERIOD_MAX_DENOMINATOR = 64


@dataclass(frozen=True)
class WaveTrain:
    """One long-crested train of deep-water gravity waves.

    Parameters
    ----------
    amplitude : float
        a, amplitude of the first harmonic, metres (>= 0).
    wavelength : float
        λ, metres (> 0); wave number k = 2π/λ.
    direction : float
        Direction of travel, degrees, measured from +x toward +y (90° travels
        straight away from the eye, 270° toward it).
    phase : float
        φ, radians, added to the phase ℓx + my − ωt.
    stokes_order : int
        1 for a pure cosine; 2..4 adds the paper's Stokes harmonics up to that
        order (the paper used 2 on its largest wave).
    gravity : float
        g, m s⁻² (> 0), in ω = √(g k); standard gravity by default. A
        :class:`Sea` gives its trains its own gravity.
    """

    amplitude: float
    wavelength: float
    direction: float = 90.0
    phase: float = 0.0
    stokes_order: int = 1
    gravity: float = GRAVITY

    def __post_init__(self):
        require_scalars(self)
        require_nonnegative("amplitude", self.amplitude)
        require_positive("wavelength", self.wavelength)
        if self.wavelength < MIN_WAVELENGTH:
            raise SunsetError(f"wavelength must be at least {MIN_WAVELENGTH:g} m (shorter ripples are "
                              f"capillary waves, outside deep-water gravity dispersion), got {self.wavelength!r}")
        if self.wavelength > MAX_WAVELENGTH:
            raise SunsetError(f"wavelength must be at most {MAX_WAVELENGTH:g} m, got {self.wavelength!r}")
        if self.amplitude * 2.0 * math.pi / self.wavelength > MAX_WAVE_SLOPE:
            raise SunsetError(f"amplitude must be at most wavelength/2π = {self.wavelength / (2 * math.pi):.4g} m "
                              f"(a first-harmonic slope k·a of {MAX_WAVE_SLOPE:g}), got {self.amplitude!r}")
        require_range("direction", self.direction, -MAX_DEGREES, MAX_DEGREES, "degrees")
        require_range("phase", self.phase, -MAX_PHASE, MAX_PHASE, "radians")
        require_int_range("stokes_order", self.stokes_order, 1, 4)
        require_range("gravity", self.gravity, MIN_GRAVITY, MAX_GRAVITY, "m/s²")

    @property
    def k(self) -> float:
        """Wave number k = 2π/λ, rad m⁻¹."""
        return 2.0 * math.pi / self.wavelength

    @property
    def wave_vector(self) -> tuple[float, float]:
        """(ℓ, m) = k (cos direction, sin direction), rad m⁻¹."""
        d = math.radians(self.direction)
        return self.k * math.cos(d), self.k * math.sin(d)

    @property
    def omega(self) -> float:
        """Angular frequency ω = √(g k) (deep-water dispersion), rad s⁻¹."""
        return math.sqrt(self.gravity * self.k)

    @property
    def speed(self) -> float:
        """Phase speed c = ω/k = √(g/k) = √(gλ/2π), m s⁻¹ (linear theory, as in the paper)."""
        return self.omega / self.k

    @property
    def period(self) -> float:
        """Wave period 2π/ω = √(2πλ/g), seconds."""
        return 2.0 * math.pi / self.omega

    @property
    def steepness(self) -> float:
        """α = k·a, the maximum slope of the first harmonic (the paper's α)."""
        return self.k * self.amplitude

    def harmonic_amplitudes(self) -> np.ndarray:
        """Amplitudes a_n of harmonics n = 1..stokes_order, metres (eq. 2).

        a_n = (k a_n)/k with k a_n from :func:`sunset.model.stokes.stokes_coefficients`
        at α = k·a. The returned array is read-only (it is computed once).
        """
        return self._amplitudes

    @functools.cached_property
    def _amplitudes(self) -> np.ndarray:
        amps = stokes_coefficients(self.steepness, self.stokes_order) / self.k
        amps.flags.writeable = False
        return amps

    @property
    def max_elevation(self) -> float:
        """Σ_n |a_n|: the most this train can raise or lower the sea, metres."""
        return float(np.sum(np.abs(self.harmonic_amplitudes())))


def unit_normal(fx, fy) -> np.ndarray:
    """The unit upward normal of a height field z = f(x, y) from its gradient.

    Shape (..., 3).

    The paper's normal formula: z̄ = 1/√(f_x² + f_y² + 1), x̄ = −z̄ f_x,
    ȳ = −z̄ f_y; used for the sea, the islands and the wrinkle normals alike.
    """
    zb = 1.0 / np.sqrt(fx * fx + fy * fy + 1.0)
    return np.stack([-zb * fx, -zb * fy, zb], axis=-1)


def _as_arrays(x, y, t):
    """x, y, t as float64 arrays, and the dtype of the result.

    The result takes the floating dtype of those of ``x`` and ``y`` that are
    NumPy floating arrays or scalars (float32 in, float32 out); Python numbers,
    integers and ``t`` do not count, and float64 is the default.
    """
    arrays, dtypes = [], []
    for i, v in enumerate((x, y, t)):
        a = np.asarray(v)
        if a.dtype.kind not in "iuf":
            raise SunsetError(f"{'xyt'[i]} must be real numbers, got dtype {a.dtype}")
        if i < 2 and isinstance(v, (np.ndarray, np.generic)) and a.dtype.kind == "f":
            dtypes.append(a.dtype)
        if i == 2:                                  # ω t must stay finite (and precise): NaN in, NaN out
            require_time("t", v, nan=True)
        arrays.append(a.astype(np.float64, copy=False))
    return arrays, (np.result_type(*dtypes) if dtypes else np.dtype(np.float64))


def _harmonics(theta: np.ndarray, n_max: int):
    """Yield (n, cos nθ, sin nθ) for n = 1..n_max from one cos θ and one sin θ."""
    c1, s1 = np.cos(theta), np.sin(theta)
    cn, sn = c1, s1
    yield 1, cn, sn
    for n in range(2, n_max + 1):
        cn, sn = cn * c1 - sn * s1, sn * c1 + cn * s1
        yield n, cn, sn


@dataclass(frozen=True, repr=False)
class Sea:
    """A sum of wave trains about mean sea level (eq. 1 without −h).

    Parameters
    ----------
    trains : sequence of WaveTrain
    gravity : float
        g, m s⁻², of the deep-water dispersion ω = √(g k) of every train;
        standard gravity by default. Each train takes it: a train built with
        another non-default gravity is an error.
    wind : WindSea or None
        A sea given by its wind instead of trains (:mod:`sunset.model.windsea`):
        its heights and slopes come from a periodic FFT tile, which the vector
        stage samples (:mod:`sunset.vector.windsea_scan`).
    """

    trains: tuple[WaveTrain, ...] = field(default_factory=tuple)
    gravity: float = GRAVITY
    wind: WindSea | None = None

    def __post_init__(self):
        require_scalars(self)
        require_range("gravity", self.gravity, MIN_GRAVITY, MAX_GRAVITY, "m/s²")
        if self.wind is not None:
            if not isinstance(self.wind, WindSea):
                raise SunsetError(f"wind must be a WindSea, got {shown(self.wind)}")
            if self.trains:
                raise SunsetError("wind: give the sea as trains or as a wind, not both")
            if self.wind.gravity != self.gravity:
                raise SunsetError(f"gravity must be standard gravity ({GRAVITY} m/s²) for a wind sea (its spectra "
                                  f"are fits to Earth's oceans), got {self.gravity!r}")
        trains = require_items("trains", self.trains, WaveTrain, MAX_TRAINS)
        for i, t in enumerate(trains):
            if not isinstance(t, WaveTrain):
                raise SunsetError(f"trains[{i}] must be a WaveTrain, got {t!r}")
            if t.gravity not in (GRAVITY, self.gravity):
                raise SunsetError(f"trains[{i}].gravity is {t.gravity!r} but the sea's gravity is {self.gravity!r}: "
                                  f"set gravity on the sea, which gives it to every train")
        if self.gravity != GRAVITY:
            trains = tuple(t if t.gravity == self.gravity else replace(t, gravity=self.gravity) for t in trains)
        object.__setattr__(self, "trains", trains)

    def __repr__(self) -> str:
        if self.wind is not None:
            return f"Sea({self.wind!r})"
        moving = [t for t in self.trains if t.amplitude > 0]
        if not moving:
            return "Sea(still)"
        lams = [t.wavelength for t in moving]
        period = self.period
        cycle = "never repeats" if period is None else f"period {period:.3g} s"
        g = "" if self.gravity == GRAVITY else f", g = {self.gravity:g} m/s²"
        return (f"Sea({len(self.trains)} train{'s' * (len(self.trains) != 1)}, λ {min(lams):.3g}–{max(lams):.3g} m, "
                f"{cycle}{g})")

    @classmethod
    def periodic(cls, wavelength: float, amplitudes, directions, phases=None,
                 stokes_orders=None, harmonics=None,
                 gravity: float = GRAVITY) -> "Sea":
        """A sea whose trains have wavelengths λ/n², so every ω is n ω₁.

        Since ω = √(g k) and k = 2π n²/λ, train n has ω_n = n ω₁ exactly, and
        the sea repeats after T = 2π/ω₁ = √(2πλ/g) (paper, after eq. 1).

        Parameters
        ----------
        wavelength : float
            λ of the fundamental, metres.
        amplitudes, directions : sequence of float
            One per train: metres, degrees.
        phases : sequence of float, optional
            Radians; zeros by default.
        stokes_orders : sequence of int, optional
            Ones by default.
        harmonics : sequence of int, optional
            n >= 1 for each train; 1, 2, 3, … by default, giving λ, λ/4, λ/9, ….
        gravity : float
            g, m s⁻² (standard gravity by default).
        """
        require_positive("wavelength", wavelength)
        n_trains = len(amplitudes)
        phases = [0.0] * n_trains if phases is None else list(phases)
        if stokes_orders is None:
            stokes_orders = [1] * n_trains
        stokes_orders = list(stokes_orders)
        if harmonics is None:
            harmonics = list(range(1, n_trains + 1))
        harmonics = list(harmonics)
        lengths = (len(directions), len(phases), len(stokes_orders), len(harmonics))
        if any(n != n_trains for n in lengths):
            raise SunsetError("amplitudes, directions, phases, stokes_orders and "
                              "harmonics must have one entry per train")
        for i, n in enumerate(harmonics):
            require_int_range(f"harmonics[{i}]", n, 1)
        return cls(tuple(
            WaveTrain(a, wavelength / n**2, d, p, s, gravity)
            for a, d, p, s, n in zip(amplitudes, directions, phases, stokes_orders,
                                     harmonics)
        ), gravity)

    @property
    def max_elevation(self) -> float:
        """d = Σ_j Σ_n ``|a_jn|``: the most the sea can depart from its mean level, metres.

        A wind sea: its tile's bound over every point and time,
        :attr:`sunset.model.ocean.OceanTile.bound_every_time` (the bound at
        one time t is ``sea.wind.tile.bound(t)``).
        """
        if self.wind is not None:
            return self.wind.tile.bound_every_time
        return float(sum(t.max_elevation for t in self.trains))

    @property
    def period(self) -> float | None:
        """The cycle T after which the whole sea repeats, seconds.

        Every ω_j must be a rational multiple p/q (q <= 64) of the lowest
        ω_min; then T = 2π Q / ω_min with Q the least common multiple of the
        denominators. For the trains of :meth:`periodic`, T = 2π/ω₁. None for
        a sea that never repeats; 0 for still water (every instant is the same).
        A wind sea repeats after its ``cycle``.
        """
        if self.wind is not None:
            return self.wind.cycle
        moving = [t for t in self.trains if t.amplitude > 0]
        if not moving:
            return 0.0
        w0 = min(t.omega for t in moving)
        q = 1
        for t in moving:
            r = t.omega / w0
            frac = Fraction(r).limit_denominator(PERIOD_MAX_DENOMINATOR)
            if abs(float(frac) - r) > 1e-9 * r:
                return None
            q = q * frac.denominator // math.gcd(q, frac.denominator)
        return 2.0 * math.pi * q / w0

    def elevation(self, x, y, t=0.0):
        """Sea elevation above mean level, Σ_j Σ_n a_jn cos n θ_j (eq. 1), metres.

        Parameters
        ----------
        x, y : float or array_like
            Horizontal position, metres (x right, y away from the eye).
        t : float or array_like
            Time, seconds.

        Returns
        -------
        ndarray
            The broadcast shape of ``x``, ``y`` and ``t``, in the floating dtype
            of ``x`` and ``y`` (float32 in, float32 out). NaN in, NaN out.
        """
        (x, y, t), dtype = _as_arrays(x, y, t)
        if self.wind is not None:
            return self._wind_sample(x, y, t, dtype)[0]
        out = np.zeros(np.broadcast_shapes(x.shape, y.shape, t.shape))
        for train in self.trains:
            l, m = train.wave_vector
            theta = l * x + m * y - train.omega * t + train.phase
            amps = train.harmonic_amplitudes()
            for n, cn, _ in _harmonics(theta, len(amps)):
                out += amps[n - 1] * cn
        return out.astype(dtype, copy=False)

    def gradient(self, x, y, t=0.0):
        """Analytic (∂f/∂x, ∂f/∂y) of the sea surface (paper, after eq. 1).

        ∂f/∂x = −Σ a_n n ℓ sin nθ, ∂f/∂y = −Σ a_n n m sin nθ, dimensionless.
        Shapes and dtypes as :meth:`elevation`.
        """
        (x, y, t), dtype = _as_arrays(x, y, t)
        if self.wind is not None:
            return self._wind_sample(x, y, t, dtype)[1:]
        shape = np.broadcast_shapes(x.shape, y.shape, t.shape)
        fx = np.zeros(shape)
        fy = np.zeros(shape)
        for train in self.trains:
            l, m = train.wave_vector
            theta = l * x + m * y - train.omega * t + train.phase
            amps = train.harmonic_amplitudes()
            slope = np.zeros(theta.shape)
            for n, _, sn in _harmonics(theta, len(amps)):
                slope -= (amps[n - 1] * n) * sn
            fx += l * slope
            fy += m * slope
        return fx.astype(dtype, copy=False), fy.astype(dtype, copy=False)

    def _wind_sample(self, x, y, t, dtype):
        """(z, z_x, z_y) of the wind sea's tile, one FFT per distinct time."""
        shape = np.broadcast_shapes(x.shape, y.shape, t.shape)
        x, y, t = (np.broadcast_to(a, shape) for a in (x, y, t))
        out = [np.empty(shape), np.empty(shape), np.empty(shape)]
        for tt in np.unique(t[np.isfinite(t)]) if t.size else ():
            sel = t == tt
            for o, v in zip(out, self.wind.sample(x[sel], y[sel], float(tt))):
                o[sel] = v
        for o in out:
            o[~np.isfinite(t)] = np.nan
        return tuple(o.astype(dtype, copy=False) for o in out)

    def normal(self, x, y, t=0.0):
        """Unit upward normal (x̄, ȳ, z̄), shape ``broadcast + (3,)``.

        The paper's normal formula: z̄ = 1/√(f_x² + f_y² + 1), x̄ = −z̄ f_x,
        ȳ = −z̄ f_y; dtype as :meth:`elevation`.
        """
        return unit_normal(*self.gradient(x, y, t))
