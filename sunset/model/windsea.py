"""A sea given by its wind: the scene's ``[sea.wind]``, its spectrum, its tile and its unresolved slopes.

A scene may give its sea as a wind instead of wave trains::

    [sea.wind]
    speed = 7.0          # m/s, at `height` (10 m unless given)
    direction = 90.0     # degrees the wind blows toward, from +x toward +y (as a train's direction)
    fetch = 50000.0      # metres; inf: fully developed (Pierson–Moskowitz)
    seed = 1             # the random amplitudes
    tile_points = 256    # N: the tile is N × N points ...
    tile_size = 256.0    # ... over L × L metres
    cycle = 64.0         # T, seconds: the sea repeats after T exactly
    # optional: height = 10.0, spreading = "mitsuyasu" or "elfouhaily", choppiness = 0.0

Each lattice component k of the tile gets a complex Gaussian amplitude with
E|h₀(k)|² = ½ Ψ(k) Δk², Ψ = S(k) D(k, φ)/k the directional spectrum
(:mod:`sunset.model.spectrum`, :mod:`sunset.model.spreading`), Δk = 2π/L,
so that the tile's expected height variance is Σ Ψ Δk² over its lattice: the
spectrum's integral over what the tile resolves. The amplitudes are drawn
shell by shell (max(|m|, |n|) = 1, 2, …), so a finer tile of the same L and
seed keeps the same long waves and only adds shorter ones.

What a renderer uses (:mod:`sunset.vector.windsea_scan`, the RGB back end's :mod:`sunset.light.glitter`):

* ``sea.wind.sample(x, y, t)``: (z, ∂z/∂x, ∂z/∂y) at a strip of scene points
  (any shape), bilinear from the tile's FFT grids (errors:
  ``tile.interpolation_error()``); one FFT per new t, then cached;
* ``sea.wind.tile.bound(t)``: max |z| of the sea at t, exact for the
  interpolated sea; ``tile.bound_every_time``: a bound for every t (the
  sea's ``max_elevation``);
* ``tile.size``, ``tile.n``, ``tile.spacing``, ``tile.cycle`` (L, N, L/N, T),
  and ``make_tile(oversample)`` for finer grids;
* ``unresolved_slopes()`` with :func:`sunset.model.coxmunk.facet_density`:
  the facets below the grid, for the RGB back end's glitter.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..constants import GRAVITY, MAX_DEGREES
from ..errors import SunsetError, require_int_range, require_range
from .ocean import MAX_POINTS, MIN_POINTS, OceanTile, lattice, resolved_mask
from .spectrum import MAX_FETCH, MIN_FETCH, WindSpectrum, check_gravity, fetch_text
from .spreading import check_spreading, density, slope_variances
from .wind import MAX_HEIGHT, MAX_WIND, MIN_HEIGHT, MIN_WIND, Wind

#: The smallest tile, in peak wavelengths: a smaller one would miss the waves that hold the energy.
MIN_TILE_PEAKS = 2.0
#: The range of a tile's side L, metres, and of a cycle T, seconds.
MIN_TILE_SIZE, MAX_TILE_SIZE = 1.0, 10000.0
MIN_CYCLE, MAX_CYCLE = 1.0, 3600.0
#: The largest seed.
MAX_SEED = 2 ** 63 - 1
#: What exporting a wind sea to POV-Ray says (its isosurface function is a sum of the trains' cosines).
NOT_EXPORTED = ("sea.wind: a wind sea is not exported to POV-Ray (its function would be a sum of the tile's "
                "components, tens of thousands of cosines): give the sea as [[sea.trains]] to export it")


@dataclass(frozen=True, repr=False)
class WindSea:
    """A wind-driven sea on a periodic FFT tile (see the module's docstring for the fields)."""

    speed: float
    direction: float
    fetch: float
    seed: int
    tile_points: int
    tile_size: float
    cycle: float
    height: float = 10.0
    spreading: str = "mitsuyasu"
    choppiness: float = 0.0
    gravity: float = GRAVITY

    def __post_init__(self):
        require_range("speed", self.speed, MIN_WIND, MAX_WIND, "m/s")
        require_range("height", self.height, MIN_HEIGHT, MAX_HEIGHT, "m")
        require_range("direction", self.direction, -MAX_DEGREES, MAX_DEGREES, "degrees")
        if not (isinstance(self.fetch, (int, float)) and self.fetch == math.inf):
            require_range("fetch", self.fetch, MIN_FETCH, MAX_FETCH, "m (or inf: fully developed)")
        require_int_range("seed", self.seed, 0, MAX_SEED)
        require_int_range("tile_points", self.tile_points, MIN_POINTS, MAX_POINTS)
        if self.tile_points & (self.tile_points - 1):
            raise SunsetError(f"tile_points must be a power of two, got {self.tile_points}")
        require_range("tile_size", self.tile_size, MIN_TILE_SIZE, MAX_TILE_SIZE, "m")
        require_range("cycle", self.cycle, MIN_CYCLE, MAX_CYCLE, "s")
        if not isinstance(self.spreading, str):
            raise SunsetError(f"spreading must be a string, got {self.spreading!r}")
        check_spreading(self.spreading)
        require_range("choppiness", self.choppiness, 0.0, 1.0)
        check_gravity(self.gravity)
        need = MIN_TILE_PEAKS * self.spectrum.peak_wavelength
        if self.tile_size < need:
            raise SunsetError(f"tile_size must be at least {MIN_TILE_PEAKS:g} peak wavelengths ({need:.4g} m) for a "
                              f"{self.speed:g} m/s wind, {fetch_text(self.fetch)}, got {self.tile_size!r}")
        longest = 2.0 * math.pi * math.sqrt(self.tile_size / (2.0 * math.pi * self.gravity))
        if self.cycle < 0.5 * longest:
            raise SunsetError(f"cycle must be at least half the period of the tile's longest wave ({0.5 * longest:.4g} s "
                              f"for a {self.tile_size:g} m tile), got {self.cycle!r}")

    def __repr__(self) -> str:
        s = self.spectrum
        return (f"WindSea({self.speed:g} m/s at {self.height:g} m toward {self.direction:g}°, {fetch_text(self.fetch)} "
                f"({s.kind}), H_s {s.hs:.3g} m, tile {self.tile_points}² over {self.tile_size:g} m, "
                f"cycle {self.cycle:g} s)")

    # -- the wind and its spectrum ------------------------------------------------
    @functools.cached_property
    def wind(self) -> Wind:
        return Wind(self.speed, self.height, self.gravity)

    @functools.cached_property
    def spectrum(self) -> WindSpectrum:
        return WindSpectrum(self.wind, self.fetch)

    def directional(self, k, phi):
        """Ψ(k, φ) = S(k) D(k, φ)/k, m⁴ rad⁻²: per unit area of the wavenumber plane (φ from the wind)."""
        k = np.asarray(k, dtype=float)
        safe = np.where(k > 0, k, 1.0)
        return np.where(k > 0, self.spectrum(safe) * density(self.spreading, self.spectrum, safe, phi) / safe, 0.0)

    # -- the tile ----------------------------------------------------------------------
    @functools.cached_property
    def component_variance(self) -> np.ndarray:
        """Ψ(k) Δk² on the tile's lattice, (N, N) m² (0 off :func:`~sunset.model.ocean.resolved_mask`)."""
        kx, ky = lattice(self.tile_points, self.tile_size)
        phi = np.arctan2(ky, kx) - math.radians(self.direction)
        dk = 2.0 * math.pi / self.tile_size
        var = self.directional(np.hypot(kx, ky), phi) * dk * dk
        return np.where(resolved_mask(self.tile_points), var, 0.0)

    def _draws(self) -> np.ndarray:
        """Standard normal pairs per lattice point, drawn shell by shell (independent of N within a shell)."""
        n = self.tile_points
        m = np.fft.fftfreq(n, d=1.0 / n).astype(np.int64)
        mx, my = np.meshgrid(m, m)
        order = np.lexsort((my.ravel(), mx.ravel(), np.maximum(np.abs(mx), np.abs(my)).ravel()))
        draws = np.random.default_rng(self.seed).standard_normal((n * n, 2))
        out = np.empty((n * n, 2))
        out[order] = draws
        return out.reshape(n, n, 2)

    @functools.cached_property
    def amplitudes(self) -> np.ndarray:
        """h₀(k), (N, N) complex, m: complex Gaussian with E|h₀|² = ½ Ψ Δk²."""
        xi = self._draws()                          # standard normal pairs
        gauss = (xi[..., 0] + 1j * xi[..., 1]) / math.sqrt(2.0)   # E|gauss|² = 1
        return np.sqrt(0.5 * self.component_variance) * gauss

    @functools.cached_property
    def tile(self) -> OceanTile:
        """The periodic FFT tile (built once, then cached)."""
        return self.make_tile()

    def make_tile(self, oversample: int = 1) -> OceanTile:
        """A new tile of this sea with its grids oversampled (1, 2 or 4; see :class:`~sunset.model.ocean.OceanTile`)."""
        return OceanTile(self.amplitudes, self.tile_size, self.cycle, self.choppiness, self.gravity, oversample)

    @property
    def expected_variance(self) -> float:
        """Σ Ψ Δk² over the lattice: the spectrum's integral over what the tile resolves, m²."""
        return float(np.sum(self.component_variance))

    # -- slopes: resolved, unresolved, total --------------------------------------------
    def _along_across(self):
        kx, ky = lattice(self.tile_points, self.tile_size)
        d = math.radians(self.direction)
        return kx * math.cos(d) + ky * math.sin(d), -kx * math.sin(d) + ky * math.cos(d)

    def resolved_slopes(self) -> tuple[float, float]:
        """(σ_u², σ_c²) the tile holds in expectation: Σ k_u² Ψ Δk² and Σ k_c² Ψ Δk² over its lattice."""
        ku, kc = self._along_across()
        v = self.component_variance
        return float(np.sum(ku * ku * v)), float(np.sum(kc * kc * v))

    def total_slopes(self) -> tuple[float, float]:
        """(σ_u², σ_c²) of the wind's whole spectrum, up to the capillary cutoff."""
        return slope_variances(self.spreading, self.spectrum)

    def unresolved_slopes(self) -> tuple[float, float]:
        """(σ_u², σ_c²) the tile cannot resolve: total − resolved, for the back end's facets (≥ 0)."""
        (tu, tc), (ru, rc) = self.total_slopes(), self.resolved_slopes()
        return max(tu - ru, 0.0), max(tc - rc, 0.0)

    def tile_slopes(self, t: float) -> tuple[float, float]:
        """(σ_u², σ_c²) measured on the tile's FFT slopes at time t (spatial mean squares)."""
        f = self.tile.fields(t)
        d = math.radians(self.direction)
        su = f["zx"] * math.cos(d) + f["zy"] * math.sin(d)
        sc = -f["zx"] * math.sin(d) + f["zy"] * math.cos(d)
        return float(np.mean(su * su)), float(np.mean(sc * sc))

    def frequency_power(self) -> tuple[np.ndarray, np.ndarray]:
        """(ω_n, E_n): the tile's variance per lattice frequency n ω₀ (time-mean), rad s⁻¹ and m²."""
        tile = self.tile
        e = np.bincount(tile.harmonic[tile.mask], weights=tile.power[tile.mask])
        return np.arange(e.size) * tile.omega0, e

    def sample(self, x, y, t: float):
        """(z, ∂z/∂x, ∂z/∂y) at scene points (x, y) at time t: see :meth:`sunset.model.ocean.OceanTile.sample`."""
        return self.tile.sample(x, y, t)
