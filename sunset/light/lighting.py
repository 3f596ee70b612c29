"""The light of one hour: everything the RGB shader needs that depends on the sun, not on the pixel.

A :class:`Lighting` is to the RGB back end what the colour tables are to the
film recorder: computed once per hour (per sun position), then applied to any
number of stored frames (deferred shading, :mod:`sunset.light.shade`).

* **Sky**: the single-scattering sky model's radiance (the one the colour
  tables use), evaluated per *direction* on a grid over the hemisphere in
  the sun's frame: rows by the elevation e = (π/2) u² (finer near the
  horizon), columns by the azimuth φ from the sun's azimuth as φ = π v²
  (finer near the sun, where the aerosol's forward peak is), u, v in [0, 1];
  the sky is symmetric about the sun's vertical plane. The grid is refined
  (:data:`SKY_REFINE`) by interpolating the logarithm of the radiance, which
  follows the sky's steep exponential fall into the Earth's shadow at
  twilight, and per pixel the refined grid is read bilinearly
  (:meth:`Lighting.sky`); the tests bound the error of that against the model
  evaluated at the pixel's own direction. The sun's columns inside the model are read
  from a table too (:func:`tabulated_columns`).
* **Sun**: the disk of angular radius δ, uniformly bright, its radiance the
  sky model's :func:`~sunset.model.sky.sun_radiance`.
* **Islands**: albedo × (Lambert's direct sun + skylight from the whole
  sphere, sky above and the sky reflected by the sea below), the skylight
  read from a grid of normals (N_x, N_y) per island part.
* **Water**: the XYZ of the single-scattered sunlight and skylight in the
  sea (:mod:`sunset.light.water`), one vector each.

Extra light, later
------------------
``extra_sky`` and ``extra_irradiance`` are lists of callables that later
models (ripples of light, clouds) append to without touching the shader:
``layer(directions, xyz)`` returns the sky radiance after the layer (e.g.
clouds over the sky), ``source(points, normals, part)`` an extra XYZ
irradiance/π on island points (e.g. light reflected by the waves).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from ..constants import ATMOSPHERE_TOP, CLOUD_TABLE_DEPTHS, WATER_REFRACTIVE_INDEX
from ..model.eye import spectrum_to_xyz as _spectrum_to_xyz
from ..model.sky import (direct_irradiance, irradiance, island_lighting, sky_dome, sky_radiance,
                       slant_columns, spectral_data, sun_radiance)
from ..model.sun import require_hours
from . import water
from .fresnel import reflectance
from .tone import exposure

__all__ = ["Lighting", "SKY_ROWS", "SKY_COLUMNS", "NORMAL_GRID", "PARTS"]

#: Rows (√z) and columns (φ = π v²) of the sky grid.
SKY_ROWS = 64
SKY_COLUMNS = 64
#: The shader reads a linear copy of the sky table refined this many times in rows and in columns.
SKY_REFINE = (4, 2)
#: Samples per side of the island normals' grid over (N_x, N_y) in [−1, 1]².
NORMAL_GRID = 33
#: Island parts by Frame.part code (1 beach, 2 cliff, 3 hill) and the reflectance names.
PARTS = {1: "beach", 2: "cliff", 3: "hill"}


#: The tabulated sun columns: altitudes (rows, as √(h/top)) and direction cosines μ in [−1, 1] (columns).
COLUMN_ROWS = 96
COLUMN_MUS = 2049


#: Rows of the column table computed at once: each point's column is computed alone (the same bytes in any
#: block), and a block's samples along the rays (COLUMN_BLOCK × COLUMN_MUS × 24 × 3 float64) stay small,
#: where the whole table's at once are about 370 MB the process then keeps (and, faulted in, pays for).
COLUMN_BLOCK = 4


@functools.lru_cache(maxsize=None)
def _column_table() -> np.ndarray:
    u = np.arange(COLUMN_ROWS) / (COLUMN_ROWS - 1)
    mu = np.linspace(-1.0, 1.0, COLUMN_MUS)
    out = np.empty((COLUMN_ROWS, COLUMN_MUS, 3))
    for a in range(0, COLUMN_ROWS, COLUMN_BLOCK):
        ua = u[a:a + COLUMN_BLOCK]
        out[a:a + COLUMN_BLOCK] = slant_columns((ua * ua * ATMOSPHERE_TOP)[:, None], mu[None, :])
    return out


def tabulated_columns(altitude, mu) -> np.ndarray:
    """The sky model's :func:`~sunset.model.sky.slant_columns`, read bilinearly from a table built once.

    The columns towards the sun from a point depend only on its altitude and
    the sun's direction cosine there, so one table over (√(h/top), μ)
    serves every hour; the tests bound what the reading costs in sky radiance.
    """
    table = _column_table()
    rows = np.sqrt(np.clip(np.asarray(altitude) / ATMOSPHERE_TOP, 0.0, 1.0)) * (COLUMN_ROWS - 1)
    cols = (np.clip(np.asarray(mu), -1.0, 1.0) + 1.0) * (0.5 * (COLUMN_MUS - 1))
    return bilinear(table, rows, cols)


#: Rows of the sky grid whose radiance is computed at once (each direction alone: the same bytes in any block).
SKY_BLOCK = 8


def _sky_radiance_rows(grid: np.ndarray, sun_dir: np.ndarray) -> np.ndarray:
    """:func:`~sunset.model.sky.sky_radiance` (columns from :func:`tabulated_columns`) of the grid's directions,
    (rows × columns, n_λ), SKY_BLOCK rows at a time: the samples along the view rays of all 4096 at once are
    some 270 MB the process would keep (and, faulted in, pay for)."""
    rows = grid.shape[0]
    parts = [sky_radiance(grid[a:a + SKY_BLOCK].reshape(-1, 3), sun_dir, columns=tabulated_columns)
             for a in range(0, rows, SKY_BLOCK)]
    return np.concatenate(parts)


#: Floor of the radiance before its logarithm is tabulated (the sky model's units).
_LOG_FLOOR = 1e-30


def sky_row(z):
    """Fractional grid row of directions with vertical component ``z``: √(e/(π/2)) (SKY_ROWS − 1)."""
    e = np.arcsin(np.clip(z, 0.0, 1.0))
    return np.sqrt(e * (2.0 / math.pi)) * (SKY_ROWS - 1)


def sky_column(azimuth, sun_azimuth):
    """Fractional grid column of directions at ``azimuth``: √(φ/π) (SKY_COLUMNS − 1), φ = |azimuth − sun's| in [0, π]."""
    az = np.asarray(azimuth)
    f = np.float32 if az.dtype == np.float32 else np.float64        # float32 in, float32 out
    phi = np.abs(np.mod(az - f(sun_azimuth) + f(math.pi), f(2 * math.pi)) - f(math.pi))
    return np.sqrt(phi * f(1 / math.pi)) * f(SKY_COLUMNS - 1)


def sky_grid_directions(sun_azimuth: float) -> np.ndarray:
    """The directions (SKY_ROWS, SKY_COLUMNS, 3) of the sky grid, world frame."""
    z = np.sin(0.5 * math.pi * (np.arange(SKY_ROWS) / (SKY_ROWS - 1)) ** 2)
    phi = math.pi * (np.arange(SKY_COLUMNS) / (SKY_COLUMNS - 1)) ** 2 + sun_azimuth
    rho = np.sqrt(1.0 - z * z)[:, None]
    return np.stack(np.broadcast_arrays(rho * np.cos(phi)[None, :], rho * np.sin(phi)[None, :], z[:, None]),
                    axis=-1)


def normal_grid() -> np.ndarray:
    """Unit upward normals (NORMAL_GRID, NORMAL_GRID, 3) at (N_x, N_y) on a grid over [−1, 1]² (rim-clamped)."""
    u = np.linspace(-1.0, 1.0, NORMAL_GRID)
    x, y = np.meshgrid(u, u, indexing="ij")
    r = np.hypot(x, y)
    s = np.where(r > 1.0, 1.0 / np.maximum(r, 1e-12), 1.0)
    x, y = x * s, y * s
    z = np.sqrt(np.clip(1.0 - x * x - y * y, 0.0, 1.0))
    n = np.stack([x, y, z], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


@dataclass
class Lighting:
    """The light for the sun at ``sun_dir`` (unit vector), disk radius ``delta`` (radians).

    Build with :meth:`for_hour` or :meth:`for_direction`.
    """

    sun_dir: np.ndarray
    delta: float
    sun_azimuth: float
    sky_table: np.ndarray          # (SKY_ROWS, SKY_COLUMNS, 3) log XYZ
    sky_linear: np.ndarray         # (refined rows, refined columns, 3) float32 XYZ: what the shader reads
    sun_xyz: np.ndarray            # (3,) radiance of the disk
    island_direct: dict            # part code -> (3,) XYZ of albedo × direct normal irradiance / π
    island_sky: dict               # part code -> (NORMAL_GRID, NORMAL_GRID, 3) XYZ of albedo × skylight / π
    water_sun: np.ndarray          # (3,) XYZ of ω E'_h(sun)
    water_sky: np.ndarray          # (3,) XYZ of ω E'_h(sky)
    beam: np.ndarray               # (3,) the sun's refracted beam in the water (pointing down)
    scale: float                   # the exposure: XYZ divided by this before the response
    n: float = WATER_REFRACTIVE_INDEX
    extra_sky: list = field(default_factory=list)
    extra_irradiance: list = field(default_factory=list)
    cloud_depths: np.ndarray | None = None   # (CLOUD_TABLE_DEPTHS,) depths below the mean cloud level, metres
    cloud_xyz: np.ndarray | None = None      # (CLOUD_TABLE_DEPTHS, 3) float32 XYZ radiance of a cloud there

    # ----------------------------------------------------------------- construction
    @classmethod
    def for_hour(cls, sun, hours: float) -> "Lighting":
        """The light ``hours`` before sunset for a :class:`~sunset.model.sun.Sun`."""
        require_hours("hours", hours)
        return cls.for_direction(sun.position(float(hours)), sun.delta)

    @classmethod
    def for_direction(cls, sun_dir, delta: float, n: float = WATER_REFRACTIVE_INDEX) -> "Lighting":
        p = np.asarray(sun_dir, dtype=float)
        p = p / np.linalg.norm(p)
        sp = spectral_data()
        az = math.atan2(p[1], p[0])
        grid = sky_grid_directions(az)
        sky = _spectrum_to_xyz(_sky_radiance_rows(grid, p)).reshape(grid.shape)
        sky = np.log(np.maximum(sky, _LOG_FLOOR))
        fr, fc = SKY_REFINE
        rows = np.arange((SKY_ROWS - 1) * fr + 1) / fr
        cols = np.arange((SKY_COLUMNS - 1) * fc + 1) / fc
        rr, cc = np.meshgrid(rows, cols, indexing="ij")
        sky_linear = np.exp(bilinear(sky, rr, cc)).astype(np.float32)
        e_sun = math.asin(max(-1.0, min(1.0, p[2])))
        sun_xyz = _spectrum_to_xyz(sun_radiance(e_sun, delta))
        direct = direct_irradiance(p, delta)
        _, diffuse = island_lighting(p, delta)
        dome = sky_dome(p)
        normals = normal_grid()
        e_sky = irradiance(normals.reshape(-1, 3), *dome)                      # (G², n_λ)
        island_direct, island_sky = {}, {}
        for code, name in PARTS.items():
            rho = sp.reflectance[name]
            island_direct[code] = _spectrum_to_xyz(rho * direct / math.pi)
            island_sky[code] = _spectrum_to_xyz(rho * e_sky / math.pi).reshape(NORMAL_GRID, NORMAL_GRID, 3)
        omega = water.single_scattering_albedo(sp.wavelengths)
        mu_s = max(p[2], 0.0)
        water_sun = _spectrum_to_xyz(omega * direct * mu_s * (1.0 - float(reflectance(mu_s, n))))
        water_sky = _spectrum_to_xyz(omega * diffuse * (1.0 - water.diffuse_reflectance(n)))
        mu_t = float(water.refracted_cosine(mu_s, n))
        horiz = np.array([p[0], p[1], 0.0])
        hn = np.linalg.norm(horiz)
        # the light travels away from the sun: down, and horizontally away from the sun's azimuth
        beam = np.array([0.0, 0.0, -1.0]) if hn == 0 else np.append(-horiz[:2] / hn * math.sqrt(1 - mu_t**2), -mu_t)
        return cls(sun_dir=p, delta=float(delta), sun_azimuth=az, sky_table=sky, sky_linear=sky_linear, sun_xyz=sun_xyz,
                   island_direct=island_direct, island_sky=island_sky, water_sun=water_sun, water_sky=water_sky,
                   beam=beam, scale=exposure(p), n=float(n))

    @classmethod
    def for_scene(cls, scene, hours: float) -> "Lighting":
        """The light ``hours`` before sunset for a scene: :meth:`for_hour`, with its clouds if it has any."""
        light = cls.for_hour(scene.sun, hours)
        if scene.clouds is not None:
            light.with_clouds(scene.clouds)
        return light

    def with_clouds(self, clouds) -> "Lighting":
        """Add a cloud layer's light of this hour, by depth below its mean level (in place; returns self).

        :func:`sunset.model.clouds.cloud_radiance` on
        :data:`~sunset.constants.CLOUD_TABLE_DEPTHS` depths from the highest top
        to the deepest bottom, in XYZ: the same light the 8-bit tables give the
        cloud codes, per ray instead of per code.
        """
        from ..model.clouds import cloud_radiance

        d = np.linspace(-clouds.max_top, clouds.max_bottom, CLOUD_TABLE_DEPTHS)
        self.cloud_depths = d
        self.cloud_xyz = _spectrum_to_xyz(cloud_radiance(d, self.sun_dir, clouds, self.delta)).astype(np.float32)
        return self

    def cloud(self, depth) -> np.ndarray:
        """Radiance XYZ (..., 3) float32 of a cloud at ``depth`` below the mean level (linear in the table)."""
        d = np.asarray(depth, dtype=np.float64)
        return np.stack([np.interp(d, self.cloud_depths, self.cloud_xyz[:, c]) for c in range(3)],
                        axis=-1).astype(np.float32)

    # ----------------------------------------------------------------- lookups
    def sky_at(self, rows, cols) -> np.ndarray:
        """Sky radiance XYZ at fractional grid coordinates (:func:`sky_row`, :func:`sky_column`).

        Read linearly from :attr:`sky_linear`, the grid refined :data:`SKY_REFINE`
        times by interpolating the logarithm (so within a refined cell the
        radiance is nearly linear).
        """
        return bilinear(self.sky_linear, np.asarray(rows) * SKY_REFINE[0], np.asarray(cols) * SKY_REFINE[1])

    def island_tables(self) -> tuple[np.ndarray, np.ndarray]:
        """(direct (4, 3), skylight (4, G, G, 3)) float32 by part code (row 0 unused): the shader's island tables."""
        direct = np.zeros((4, 3), np.float32)
        table = np.zeros((4, NORMAL_GRID, NORMAL_GRID, 3), np.float32)
        for code in PARTS:
            direct[code] = self.island_direct[code]
            table[code] = self.island_sky[code]
        return direct, table

    def sky(self, directions) -> np.ndarray:
        """Sky radiance XYZ along unit ``directions`` (..., 3), without the sun's disk or extra layers."""
        d = np.asarray(directions)
        return self.sky_at(sky_row(d[..., 2]), sky_column(np.arctan2(d[..., 1], d[..., 0]), self.sun_azimuth))

    def radiance(self, directions) -> np.ndarray:
        """What a ray leaving into the sky along ``directions`` sees: sky + the sun's disk, then the extra layers."""
        d = np.asarray(directions)
        out = self.sky(d) + self.sun(d)
        for layer in self.extra_sky:
            out = layer(d, out)
        return out

    def sun(self, directions) -> np.ndarray:
        """The sun disk's radiance XYZ where ``directions`` fall inside it (z >= 0), else 0."""
        d = np.asarray(directions)
        inside = (d @ self.sun_dir.astype(d.dtype) > math.cos(self.delta)) & (d[..., 2] >= 0)
        return inside[..., None] * self.sun_xyz.astype(d.dtype)

    def island(self, normals, part, points=None) -> np.ndarray:
        """Island radiance XYZ: albedo × (max(N·P, 0) E_sun + E_sky(N)) / π, per part code (1–3)."""
        nrm = np.asarray(normals)
        part = np.asarray(part)
        cos = np.clip(nrm @ self.sun_dir.astype(nrm.dtype), 0.0, None)
        gx = (np.clip(nrm[..., 0], -1, 1) + 1.0) * (0.5 * (NORMAL_GRID - 1))
        gy = (np.clip(nrm[..., 1], -1, 1) + 1.0) * (0.5 * (NORMAL_GRID - 1))
        out = np.zeros(nrm.shape, nrm.dtype)
        for code in PARTS:
            sel = part == code
            if not np.any(sel):
                continue
            out[sel] = (cos[sel, None] * self.island_direct[code]
                        + bilinear(self.island_sky[code], gx[sel], gy[sel]))
        for source in self.extra_irradiance:
            out = out + source(points, nrm, part)
        return out


def bilinear(table, rows, cols) -> np.ndarray:
    """Bilinear reading of ``table`` (R, C, k) at fractional (rows, cols), clamped to the grid."""
    r_max, c_max = table.shape[0] - 1, table.shape[1] - 1
    rows = np.clip(rows, 0, r_max)
    cols = np.clip(cols, 0, c_max)
    r0 = np.minimum(rows.astype(np.intp), r_max - 1)
    c0 = np.minimum(cols.astype(np.intp), c_max - 1)
    fr = (rows - r0)[..., None]
    fc = (cols - c0)[..., None]
    t = table.astype(np.asarray(rows).dtype, copy=False)
    top = t[r0, c0] * (1 - fc) + t[r0, c0 + 1] * fc
    bottom = t[r0 + 1, c0] * (1 - fc) + t[r0 + 1, c0 + 1] * fc
    return top * (1 - fr) + bottom * fr
