"""The physical sky: sunlight, extinction, skylight and the light falling on a surface.

The colours of the film recorder's tables (:mod:`sunset.recorder.colour_tables`)
and of the RGB back end follow from this small physical model, computed
spectrally (380–780 nm) with colour-science; nothing here knows of codes or
pixels, only of directions:

* **Sunlight** outside the atmosphere: a blackbody at the sun's effective
  temperature (:data:`~sunset.constants.SUN_TEMPERATURE`).
* **Extinction**: Rayleigh optical depth of air (Bodhaine et al. 1999,
  ``colour.phenomena.rayleigh_optical_depth``) plus an aerosol optical depth
  τ_a = β (λ/1 µm)^−α (Ångström), both times the air mass, for which the
  direct sun uses the Kasten–Young (1989) formula; ozone's Chappuis band.
* **Sky**: single scattering in a spherical atmosphere with exponential
  molecular and aerosol layers (Rayleigh phase function; Henyey–Greenstein
  for the aerosol), integrated numerically along the view ray, each point lit
  by the sun through its own slant column (:func:`sky_radiance`).
* **Light on a surface**: the direct sun and the skylight from the whole sphere
  around a normal, the sky above and the sea below reflecting it (Fresnel):
  :func:`island_lighting`, :func:`irradiance`, :func:`sky_dome`.
"""

from __future__ import annotations

import functools
import math
from types import SimpleNamespace

import numpy as np

from ..constants import (AEROSOL_ALBEDO, AEROSOL_ANGSTROM_ALPHA, AEROSOL_ANGSTROM_BETA, AEROSOL_ASYMMETRY,
                         AEROSOL_SCALE_HEIGHT, ATMOSPHERE_TOP, DOBSON_UNIT, EARTH_RADIUS, ISLAND_NORMAL_SAMPLES,
                         OZONE_COLUMN_DU, OZONE_CROSS_SECTION, OZONE_CROSS_SECTION_NM, OZONE_HALF_WIDTH,
                         OZONE_LAYER_ALTITUDE, OZONE_PEAK_ALTITUDE, RAYLEIGH_SCALE_HEIGHT, SUN_TEMPERATURE,
                         WATER_REFRACTIVE_INDEX)
from .. import kernels
from ..kernels import twin
from .sun import Sun

__all__ = [
    "spectral_data", "kasten_young_air_mass", "slant_columns", "sky_radiance", "sun_transmittance", "sun_radiance",
    "visible_fraction", "ozone_air_mass", "island_lighting", "direct_irradiance", "fresnel_reflectance",
    "irradiance", "irradiance_weights", "sky_dome", "dome_directions", "island_normals", "elevation",
]


#: Sample counts of the single-scattering integrals (view ray, sun column, hemisphere).
_N_VIEW = 48


_N_SUN = 24


_N_HEMI_MU = 8


_N_HEMI_PHI = 16


@functools.lru_cache(maxsize=None)
def spectral_data() -> SimpleNamespace:
    """Wavelengths and spectra on a 10 nm grid, 380–780 nm, computed once.

    Returns a namespace with ``wavelengths`` (nm), ``cmfs`` (CIE 1931 2°,
    (n, 3)), ``sun`` (blackbody, normalised to mean 1), ``tau`` (3, n): the
    vertical optical depths from sea level of the molecules (Rayleigh), the
    aerosol and the ozone, and ``reflectance`` (a dict: hill, cliff, beach).

    The spectra are colour-science's, imported here (once per process, the
    first time colour is computed): the CIE 1931 CMFs, a blackbody at
    :data:`~sunset.constants.SUN_TEMPERATURE`, the Rayleigh optical depth of
    ``colour.phenomena.rayleigh_optical_depth``, the ColorChecker's foliage
    and dark skin, TCS02.
    """
    import colour
    from colour.quality.datasets import SDS_TCS

    shape = colour.SpectralShape(380, 780, 10)
    lam = np.asarray(shape.wavelengths, dtype=float)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape).values
    sun = colour.sd_blackbody(SUN_TEMPERATURE, shape).values
    checker = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]
    refl = {
        "hill": checker["foliage"].copy().align(shape).values,
        "cliff": checker["dark skin"].copy().align(shape).values,
        "beach": SDS_TCS["CIE 1995"]["TCS02"].copy().align(shape).values,
    }
    tau_r = np.asarray(colour.phenomena.rayleigh_optical_depth(lam * 1e-7), dtype=float)
    tau_a = AEROSOL_ANGSTROM_BETA * (lam / 1000.0) ** (-AEROSOL_ANGSTROM_ALPHA)
    o3 = np.interp(lam, OZONE_CROSS_SECTION_NM, OZONE_CROSS_SECTION)
    tau_o = OZONE_COLUMN_DU * DOBSON_UNIT * o3
    return SimpleNamespace(
        wavelengths=lam,
        cmfs=np.asarray(cmfs, dtype=float),
        sun=np.asarray(sun, dtype=float) / float(np.mean(sun)),
        tau=np.stack([tau_r, tau_a, tau_o]),
        reflectance={k: np.clip(np.asarray(v, dtype=float), 0.0, 1.0) for k, v in refl.items()},
    )


def kasten_young_air_mass(elevation) -> np.ndarray:
    """Relative optical air mass of Kasten & Young (1989).

    m = 1 / (cos z + 0.50572 (96.07995° − z)^−1.6364), z = 90° − elevation
    in degrees; the elevation is clipped to [0°, 90°] (m = 1 at the zenith,
    about 38 at the horizon).

    Parameters
    ----------
    elevation : array_like
        Elevation above the horizon, radians.
    """
    e = np.degrees(np.clip(np.asarray(elevation, dtype=float), 0.0, math.pi / 2))
    z = 90.0 - e
    return 1.0 / (np.cos(np.radians(z)) + 0.50572 * (96.07995 - z) ** -1.6364)


def _ozone_profile(h):
    """Ozone number density relative to its peak: a tent from 10 km up to 25 km and down to 40 km."""
    return np.clip(1.0 - np.abs(h - OZONE_PEAK_ALTITUDE) / OZONE_HALF_WIDTH, 0.0, None)


def _densities(h) -> np.ndarray:
    """Per-metre densities of the three species, normalised so a vertical column from sea level is 1, (..., 3)."""
    return np.stack([np.exp(-h / RAYLEIGH_SCALE_HEIGHT) / RAYLEIGH_SCALE_HEIGHT,
                     np.exp(-h / AEROSOL_SCALE_HEIGHT) / AEROSOL_SCALE_HEIGHT,
                     _ozone_profile(h) / OZONE_HALF_WIDTH], axis=-1)


def slant_columns(altitude, mu, n: int = _N_SUN) -> np.ndarray:
    """Molecular, aerosol and ozone columns from a point to the top of the atmosphere.

    The column of a species along a straight ray is ∫ n(h) ds / ∫₀^∞ n(h) dh,
    so that the ray's optical depth is the vertical optical depth at sea level
    times the column; for a ray from sea level the molecular column is the
    relative air mass. A ray that passes through the solid Earth keeps
    integrating the (clamped, enormous) density there, so its transmittance
    falls smoothly to zero as the sun sets.

    Parameters
    ----------
    altitude : array_like
        Height of the starting point above sea level, metres.
    mu : array_like
        Cosine of the ray's angle from the local vertical.
    n : int
        Samples along the ray (quadratically spaced, denser near the start).

    Returns
    -------
    ndarray (..., 3)
        Columns of the molecules, the aerosol and the ozone, for the broadcast
        shape of the inputs.
    """
    r = EARTH_RADIUS + np.asarray(altitude, dtype=float)
    mu = np.asarray(mu, dtype=float)
    r, mu = np.broadcast_arrays(r, mu)
    top = EARTH_RADIUS + ATMOSPHERE_TOP
    length = -r * mu + np.sqrt(np.maximum(r * r * mu * mu + top * top - r * r, 0.0))
    j = (np.arange(n) + 0.5) / n
    s = length[..., None] * j**2
    ds = length[..., None] * (2.0 * j / n)
    h = np.sqrt(np.maximum(r[..., None] ** 2 + 2.0 * r[..., None] * mu[..., None] * s + s * s, 0.0)) - EARTH_RADIUS
    h = np.maximum(h, -5.0 * RAYLEIGH_SCALE_HEIGHT)
    return np.einsum("...jk,...j->...k", _densities(h), ds)


def _phase_rayleigh(cos_g):
    return 3.0 / (16.0 * math.pi) * (1.0 + cos_g * cos_g)


def _phase_hg(cos_g, g=AEROSOL_ASYMMETRY):
    return (1.0 - g * g) / (4.0 * math.pi * (1.0 + g * g - 2.0 * g * cos_g) ** 1.5)


@twin("sunset.model.sky_numba")
def sky_radiance(directions, sun_dir, n_view: int = _N_VIEW, n_sun: int = _N_SUN,
                 columns=None) -> np.ndarray:
    """Single-scattered sky radiance seen from sea level, per unit solar irradiance.

    L(λ, v) = E₀(λ) ∫ [β_R(λ,h) P_R(γ) + ω β_A(λ,h) P_HG(γ)] T_view T_sun ds,

    along the view ray v to the top of the atmosphere, with β = τ n(h) (the
    vertical optical depth times the normalised density), cos γ = v·P and T
    the transmittances (molecules, aerosol and ozone) along the view ray and
    towards the sun. Directions below the horizon are raised to it.

    Parameters
    ----------
    directions : array_like (K, 3)
        Unit view directions (z up).
    sun_dir : array_like (3,)
        Unit vector P towards the sun.
    columns : callable, optional
        ``columns(altitude, mu)`` → (..., 3), the columns towards the sun from
        each sample point; default :func:`slant_columns` with ``n_sun``
        samples (a tabulated version of it makes many directions cheap,
        :func:`sunset.light.lighting.tabulated_columns`; only the NumPy
        reference takes one: its compiled twin, :mod:`sunset.model.sky_numba`,
        integrates :func:`slant_columns` itself, within a tolerance).

    Returns
    -------
    ndarray (K, n_λ)
        Spectral radiance in units of the top-of-atmosphere solar irradiance
        spectrum (``spectral_data().sun``) per steradian.
    """
    sp = spectral_data()
    v = np.asarray(directions, dtype=float).reshape(-1, 3)
    p = np.asarray(sun_dir, dtype=float)
    mu_v = np.clip(v[:, 2], 0.0, 1.0)
    top = EARTH_RADIUS + ATMOSPHERE_TOP
    R = EARTH_RADIUS
    length = -R * mu_v + np.sqrt(R * R * mu_v * mu_v + top * top - R * R)
    j = (np.arange(n_view) + 0.5) / n_view
    s = length[:, None] * j**2                           # (K, n)
    ds = length[:, None] * (2.0 * j / n_view)
    r = np.sqrt(R * R + 2.0 * R * mu_v[:, None] * s + s * s)
    h = r - R
    dens = _densities(h) * ds[..., None]                 # (K, n, 3)
    view = np.cumsum(dens, axis=1) - 0.5 * dens
    cos_g = np.clip(v @ p, -1.0, 1.0)                   # (K,)
    # the sun's direction cosine at each sample point (the local vertical is the
    # point's radius)
    mu_s = (R * p[2] + s * cos_g[:, None]) / r
    if columns is None:
        col = view + slant_columns(h, mu_s, n_sun)       # (K, n, 3)
    else:
        col = view + columns(h, mu_s)
    trans = np.exp(-(col @ sp.tau))                      # (K, n, λ)
    rayleigh = ((dens[..., 0] * _phase_rayleigh(cos_g)[:, None])[..., None]
                * sp.tau[0])
    aerosol = (dens[..., 1] * AEROSOL_ALBEDO * _phase_hg(cos_g)[:, None])[..., None]
    scat = rayleigh + aerosol * sp.tau[1]
    return sp.sun * np.sum(scat * trans, axis=1)


def visible_fraction(elevation, delta: float) -> np.ndarray:
    """Fraction of the sun's disk (angular radius δ) above the horizon.

    The area of a circular segment: (arccos(−x) + x √(1 − x²)) / π with
    x = elevation/δ clipped to [−1, 1].
    """
    x = np.clip(np.asarray(elevation, dtype=float) / delta, -1.0, 1.0)
    return (np.arccos(-x) + x * np.sqrt(1.0 - x * x)) / math.pi


def ozone_air_mass(elevation) -> np.ndarray:
    """Slant path through a thin ozone layer at 22 km relative to the vertical (Komhyr 1980).

    m = (1 + h/R) / √(cos² z + 2h/R), z the zenith angle (elevation clipped at 0).
    """
    e = np.clip(np.asarray(elevation, dtype=float), 0.0, math.pi / 2)
    k = OZONE_LAYER_ALTITUDE / EARTH_RADIUS
    return (1.0 + k) / np.sqrt(np.sin(e) ** 2 + 2.0 * k)


def sun_transmittance(elevation) -> np.ndarray:
    """Spectral transmittance of the direct sun beam, shape (..., n_λ).

    exp(−(τ_R + τ_A) m_KY − τ_O₃ m_O₃), with the Kasten–Young air mass for the
    molecules and the aerosol and Komhyr's for the ozone layer.
    """
    sp = spectral_data()
    m = kasten_young_air_mass(elevation)[..., None]
    mo = ozone_air_mass(elevation)[..., None]
    return np.exp(-(sp.tau[0] + sp.tau[1]) * m - sp.tau[2] * mo)


def sun_radiance(elevation, delta: float) -> np.ndarray:
    """Spectral radiance of the sun's disk seen through the atmosphere, per unit E₀, (..., n_λ).

    The top-of-atmosphere irradiance spread over the disk's solid angle
    2π(1 − cos δ), times the direct beam's transmittance. With the paper's
    enlarged δ the same sunlight is spread over a larger disk, so the disk is
    less bright than the real sun.
    """
    omega = 2.0 * math.pi * (1.0 - math.cos(delta))
    return spectral_data().sun * sun_transmittance(elevation) / omega


def island_lighting(sun_dir, delta: float) -> tuple[np.ndarray, np.ndarray]:
    """Direct normal irradiance and diffuse horizontal irradiance, spectral, per unit E₀.

    Returns
    -------
    (ndarray (n_λ,), ndarray (n_λ,))
        The direct beam on a surface facing the sun (transmittance × the
        visible fraction of the disk) and the sky's irradiance on a
        horizontal surface, ∫ L cos(zenith) dΩ.
    """
    dirs, d_omega = _sphere()
    up = dirs[: len(dirs) // 2]
    diffuse = (d_omega[: len(up)] * up[:, 2]) @ _upper_sky(sun_dir)
    return direct_irradiance(sun_dir, delta), diffuse


def _upper_sky(sun_dir) -> np.ndarray:
    """:func:`sky_radiance` over the upper half of :func:`_sphere`, read-only.

    :func:`sky_dome` and :func:`island_lighting` both integrate it, often for
    the same sun (a cloudy frame's tables ask for both), so the last few are
    kept, apart for each path of :mod:`sunset.kernels` (they agree within a
    tolerance, not to the bit).
    """
    p = np.asarray(sun_dir, dtype=float)
    if p.shape != (3,):
        dirs = _sphere()[0]
        return sky_radiance(dirs[: len(dirs) // 2], p)
    return _upper_sky_cached(np.ascontiguousarray(p).tobytes(), kernels.enabled())


@functools.lru_cache(maxsize=16)
def _upper_sky_cached(sun_bytes: bytes, compiled: bool) -> np.ndarray:
    dirs = _sphere()[0]
    out = sky_radiance(dirs[: len(dirs) // 2], np.frombuffer(sun_bytes, dtype=float))
    out.setflags(write=False)
    return out


def direct_irradiance(sun_dir, delta: float) -> np.ndarray:
    """The sun's direct beam on a surface facing it, spectral, per unit E₀ (n_λ,).

    Transmittance along the slant path times the fraction of the disk of
    angular radius ``delta`` (radians) above the horizon.
    """
    e = elevation(sun_dir)
    return spectral_data().sun * sun_transmittance(e) * visible_fraction(e, delta)


def elevation(direction) -> float:
    """Elevation of a unit direction above the horizon, radians."""
    return math.asin(max(-1.0, min(1.0, float(direction[2]))))


def fresnel_reflectance(cos_i, n: float = WATER_REFRACTIVE_INDEX) -> np.ndarray:
    """Unpolarised Fresnel reflectance of a flat surface of refractive index n (air → water).

    R = (R_s + R_p)/2 with R_s = ((cos i − n cos t)/(cos i + n cos t))² and
    R_p = ((n cos i − cos t)/(n cos i + cos t))², sin t = sin i / n: about 2%
    at normal incidence, rising to 1 at grazing incidence.

    Parameters
    ----------
    cos_i : array_like
        Cosine of the angle of incidence (clipped to [0, 1]).
    """
    c = np.clip(np.asarray(cos_i, dtype=float), 0.0, 1.0)
    ct = np.sqrt(1.0 - (1.0 - c * c) / (n * n))
    rs = ((c - n * ct) / (c + n * ct)) ** 2
    rp = ((n * c - ct) / (n * c + ct)) ** 2
    return 0.5 * (rs + rp)


@functools.lru_cache(maxsize=None)
def _sphere() -> tuple[np.ndarray, np.ndarray]:
    """Directions and solid angles dΩ covering the whole sphere (midpoint rule in μ = cos(zenith), φ).

    The first half of the rows is the upper hemisphere, the second half its
    mirror image in the horizontal plane, row for row.
    """
    mu = (np.arange(_N_HEMI_MU) + 0.5) / _N_HEMI_MU
    phi = (np.arange(_N_HEMI_PHI) + 0.5) * (2 * math.pi / _N_HEMI_PHI)
    mu, phi = np.meshgrid(mu, phi, indexing="ij")
    sin_t = np.sqrt(1.0 - mu * mu)
    up = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), mu], axis=-1).reshape(-1, 3)
    d_omega = np.full(len(up), (1.0 / _N_HEMI_MU) * (2 * math.pi / _N_HEMI_PHI))
    return np.concatenate([up, up * np.array([1.0, 1.0, -1.0])]), np.concatenate([d_omega, d_omega])


def irradiance(normals, directions, radiance, solid_angles) -> np.ndarray:
    """E(N) = Σ L(ω) max(N·ω, 0) ΔΩ: the irradiance a radiance field gives a surface with normal N.

    Parameters
    ----------
    normals : array_like (..., 3)
        Unit normals.
    directions : array_like (M, 3)
        Unit directions ω the light comes from.
    radiance : array_like (M, n_λ)
        Radiance arriving from each direction.
    solid_angles : array_like (M,)
        ΔΩ of each direction.

    Returns
    -------
    ndarray (..., n_λ)
    """
    return irradiance_weights(normals, directions, solid_angles) @ np.asarray(radiance, dtype=float)


def irradiance_weights(normals, directions, solid_angles) -> np.ndarray:
    """max(N·ω, 0) ΔΩ, (..., M): what :func:`irradiance` multiplies the radiance by.

    It depends on the geometry alone, so a caller that lights the same
    normals under many skies (the colour tables, one per hour) computes it once.
    """
    cos = np.clip(np.asarray(normals, dtype=float) @ np.asarray(directions, dtype=float).T, 0.0, None)
    return cos * np.asarray(solid_angles, dtype=float)


def sky_dome(sun_dir) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The light around an island: the sky above and the sea below, reflecting it.

    Above the horizon the single-scattering sky (:func:`sky_radiance`); below
    it the sea as a calm mirror: the sky seen in the mirror direction times the
    Fresnel reflectance of water (:func:`fresnel_reflectance`).

    Returns
    -------
    (ndarray (M, 3), ndarray (M, n_λ), ndarray (M,))
        Directions, radiance (per unit E₀) and solid angles over the sphere.
    """
    dirs, d_omega = dome_directions()
    half = len(dirs) // 2
    sky = _upper_sky(sun_dir)
    sea = fresnel_reflectance(dirs[:half, 2])[:, None] * sky
    return dirs, np.concatenate([sky, sea]), d_omega


def dome_directions() -> tuple[np.ndarray, np.ndarray]:
    """The directions (M, 3) and solid angles (M,) of :func:`sky_dome`, without its radiance."""
    return _sphere()


def island_normals(sun: Sun, psi, samples: int = ISLAND_NORMAL_SAMPLES
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The normals an island code stands for, and their weights.

    A code keeps only the angle ψ of N's projection on the plane of the
    sun's circle, N = cos β (U cos ψ + V sin ψ) + sin β W. The component
    along W, sin β, is lost: the normals of one code are taken uniformly over
    the sphere (weight cos β) among those that face up (N_z > 0, as every
    point of a height field does).

    Parameters
    ----------
    sun : Sun
    psi : array_like (K,)
        Sun-plane angles, radians.
    samples : int
        Values of β, midpoints of (−π/2, π/2).

    Returns
    -------
    (ndarray (K, samples, 3), ndarray (K, samples))
        Normals and weights that sum to 1 for each ψ.
    """
    psi = np.asarray(psi, dtype=float).reshape(-1)
    beta = ((np.arange(samples) + 0.5) / samples - 0.5) * math.pi
    in_plane = np.cos(psi)[:, None] * sun.U + np.sin(psi)[:, None] * sun.V  # (K, 3)
    n = (np.cos(beta)[None, :, None] * in_plane[:, None, :]
         + np.sin(beta)[None, :, None] * sun.W)
    w = np.where(n[..., 2] > 0.0, np.cos(beta)[None, :], 0.0)
    total = w.sum(axis=1, keepdims=True)
    w = np.where(total > 0, w / np.where(total > 0, total, 1.0), 1.0 / samples)
    return n, w
