"""Waves on deep water: wave trains, the periodic sea and eq. 1.

A wave train is a long-crested travelling cosine

    z = a cos(ℓx + my − ωt + φ),   ℓ² + m² = k²,   ω = √(g k)

(deep-water dispersion). The sea is their sum about the mean level (eq. 1,
without the −h, which belongs to the camera). A train may carry Stokes
harmonics n = 2..4 (eq. 2): a_n cos n(ℓx + my − ωt + φ), which travel with the
train, so that harmonic n has frequency nω.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from .constants import GRAVITY
from .errors import SunsetError, require_finite, require_int_range, require_nonnegative, require_positive
from .stokes import stokes_coefficients


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
    """

    amplitude: float
    wavelength: float
    direction: float = 90.0
    phase: float = 0.0
    stokes_order: int = 1

    def __post_init__(self):
        require_nonnegative("amplitude", self.amplitude)
        require_positive("wavelength", self.wavelength)
        require_finite("direction", self.direction)
        require_finite("phase", self.phase)
        require_int_range("stokes_order", self.stokes_order, 1, 4)

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
        return math.sqrt(GRAVITY * self.k)

    @property
    def speed(self) -> float:
        """Phase speed c = ω/k = √(g/k), m s⁻¹."""
        return self.omega / self.k

    @property
    def period(self) -> float:
        """Wave period 2π/ω, seconds."""
        return 2.0 * math.pi / self.omega

    @property
    def steepness(self) -> float:
        """α = k·a, the maximum slope of the first harmonic."""
        return self.k * self.amplitude

    def harmonic_amplitudes(self) -> np.ndarray:
        """Amplitudes a_n of harmonics n = 1..stokes_order, metres (eq. 2)."""
        return stokes_coefficients(self.steepness, self.stokes_order) / self.k

    @property
    def max_elevation(self) -> float:
        """Σ_n |a_n|: the most this train can raise or lower the sea, metres."""
        return float(np.sum(np.abs(self.harmonic_amplitudes())))


def _phase(train: WaveTrain, x, y, t):
    l, m = train.wave_vector
    return l * x + m * y - train.omega * t + train.phase


@dataclass(frozen=True)
class Sea:
    """A sum of wave trains about mean sea level (eq. 1 without −h)."""

    trains: tuple[WaveTrain, ...] = field(default_factory=tuple)

    def __post_init__(self):
        object.__setattr__(self, "trains", tuple(self.trains))

    @classmethod
    def periodic(cls, wavelength: float, amplitudes, directions, phases=None, stokes_orders=None,
                 harmonics=None) -> "Sea":
        """A sea whose trains have wavelengths λ/n², so every ω is n ω₁.

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
            n for each train; 1, 2, 3, … by default, giving λ, λ/4, λ/9, ….
        """
        n_trains = len(amplitudes)
        phases = [0.0] * n_trains if phases is None else list(phases)
        stokes_orders = [1] * n_trains if stokes_orders is None else list(stokes_orders)
        harmonics = list(range(1, n_trains + 1)) if harmonics is None else list(harmonics)
        if not (len(directions) == len(phases) == len(stokes_orders) == len(harmonics) == n_trains):
            raise SunsetError("amplitudes, directions, phases, stokes_orders and harmonics must have one entry per train")
        return cls(tuple(
            WaveTrain(a, wavelength / n**2, d, p, s)
            for a, d, p, s, n in zip(amplitudes, directions, phases, stokes_orders, harmonics)
        ))

    @property
    def max_elevation(self) -> float:
        """d = Σ_j Σ_n |a_jn|: the most the sea can depart from its mean level, metres."""
        return float(sum(t.max_elevation for t in self.trains))

    @property
    def period(self) -> float | None:
        """The cycle T after which the whole sea repeats, seconds.

        Every ω_j must be a rational multiple (denominator <= 64) of the
        lowest; then T = 2π q / ω_min. None for a sea that never repeats; 0 for
        still water (every instant is the same).
        """
        moving = [t for t in self.trains if t.amplitude > 0]
        if not moving:
            return 0.0
        w0 = min(t.omega for t in moving)
        q = 1
        for t in moving:
            r = t.omega / w0
            frac = Fraction(r).limit_denominator(64)
            if abs(float(frac) - r) > 1e-9 * r:
                return None
            q = q * frac.denominator // math.gcd(q, frac.denominator)
        return 2.0 * math.pi * q / w0

    def elevation(self, x, y, t=0.0):
        """Sea elevation above mean level, Σ_j Σ_n a_jn cos n θ_j (eq. 1), metres.

        ``x``, ``y`` (metres) and ``t`` (seconds) broadcast against each other;
        the result has their broadcast shape and the dtype of ``x``/``y``
        (float32 in, float32 out).
        """
        x, y, t = _as_arrays(x, y, t)
        out = np.zeros(np.broadcast_shapes(x.shape, y.shape, t.shape), dtype=np.result_type(x, y, t))
        for train in self.trains:
            theta = _phase(train, x, y, t)
            for n, a in enumerate(train.harmonic_amplitudes(), start=1):
                out += a * np.cos(n * theta if n > 1 else theta)
        return out

    def gradient(self, x, y, t=0.0):
        """Analytic (∂f/∂x, ∂f/∂y) of the sea surface (paper, after eq. 1).

        ∂f/∂x = −Σ a_n n ℓ sin nθ, ∂f/∂y = −Σ a_n n m sin nθ. Shapes and
        dtypes as :meth:`elevation`.
        """
        x, y, t = _as_arrays(x, y, t)
        shape = np.broadcast_shapes(x.shape, y.shape, t.shape)
        dtype = np.result_type(x, y, t)
        fx = np.zeros(shape, dtype=dtype)
        fy = np.zeros(shape, dtype=dtype)
        for train in self.trains:
            l, m = train.wave_vector
            theta = _phase(train, x, y, t)
            for n, a in enumerate(train.harmonic_amplitudes(), start=1):
                s = a * n * np.sin(n * theta if n > 1 else theta)
                fx -= l * s
                fy -= m * s
        return fx, fy

    def normal(self, x, y, t=0.0):
        """Unit upward normal (x̄, ȳ, z̄), shape ``broadcast + (3,)`` (paper's normal formula).

        z̄ = 1/√(f_x² + f_y² + 1), x̄ = −z̄ f_x, ȳ = −z̄ f_y.
        """
        fx, fy = self.gradient(x, y, t)
        zb = 1.0 / np.sqrt(fx * fx + fy * fy + 1.0)
        return np.stack([-zb * fx, -zb * fy, zb], axis=-1)


def _as_arrays(x, y, t):
    arrs = []
    for name, v in (("x", x), ("y", y), ("t", t)):
        a = np.asarray(v)
        if a.dtype.kind not in "fc":
            a = a.astype(float)
        arrs.append(a)
    return arrs
