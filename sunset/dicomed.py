"""The film recorder stage: colour translation tables and three colour passes.

The Dicomed D-48 saw the tape three times, once through each of its red,
green and blue filters, each time through a 256-entry translation table. It
knew nothing of the scene: only the code of each pixel, its raster position
and, through the tables, the sun's position P(θ) = U cos θ + V sin θ with
θ = 15° per hour before sunset. This module is that machine. It reads codes
(:mod:`sunset.codes`), the scene's camera (raster position → direction) and
its sun, and never a :class:`~sunset.frame.Frame`.

Where the colours come from
---------------------------
Nothing is picked by hand; the colours follow from a small physical model,
computed spectrally (380–780 nm) with colour-science:

* **Sunlight** outside the atmosphere: a blackbody at the sun's effective
  temperature (:data:`~sunset.constants.SUN_TEMPERATURE`).
* **Extinction**: Rayleigh optical depth of air (Bodhaine et al. 1999,
  ``colour.phenomena.rayleigh_optical_depth``) plus an aerosol optical depth
  τ_a = β (λ/1 µm)^−α (Ångström), both times the air mass, for which the
  direct sun uses the Kasten–Young (1989) formula.
* **Sky**: single scattering in a spherical atmosphere with exponential
  molecular and aerosol layers (Rayleigh phase function; Henyey–Greenstein
  for the aerosol), integrated numerically along the view ray, each point lit
  by the sun through its own slant column. Sky codes are evaluated looking
  along the camera's axis (+y) at the code's elevation; track and halo codes
  take the same sky value, brightening towards the sun's colour when the sun
  passes their elevation.
* **Islands**: measured reflectance spectra (ColorChecker "foliage" for the
  hill, "dark skin" for the brown cliff, CIE test colour sample 2 for the tan
  beach) under the direct sun × the code's cosine factor, plus the skylight:
  the irradiance from the whole sphere around the normal, the sky above and
  the sea below reflecting it (Fresnel), averaged over the normals a code
  stands for (:func:`island_normals`). Skylight is what keeps the islands'
  shadowed sides from going black.
* **Exposure and response**: CIE 1931 XYZ relative to a white horizontal card
  in full sun at 30° (and to an exposure key that follows the light as it
  fades), a compressive response of the eye to luminance (Naka–Rushton,
  :func:`eye_response`) that keeps each colour's chromaticity, bleaching
  towards white only what would pass full scale, then linear sRGB and its
  encoding.

The sun-disk rule
-----------------
A pixel above the horizon, wholly inside the sun's disk, whose code is a sky
code, is exposed in the sun's colour (the paper, *Color Specification for the
Sky*, paraphrased); near the rim, a mix weighted by the fraction of the pixel
(above the horizon) covered by the disk, found by sub-sampling the pixel's
footprint.
"""

from __future__ import annotations

import functools
import math
from types import SimpleNamespace

import numpy as np

from .codes import (CODE_MAP, island_code_rho, sky_code_z, sun_plane_angle, track_code_elevations,
                    track_elevation_max)
from .constants import (AEROSOL_ALBEDO, AEROSOL_ANGSTROM_ALPHA, AEROSOL_ANGSTROM_BETA, AEROSOL_ASYMMETRY,
                        AEROSOL_SCALE_HEIGHT, ATMOSPHERE_TOP, DOBSON_UNIT, EARTH_RADIUS, EXPOSURE_SUN_ELEVATION, EYE_RESPONSE_EXPONENT,
                        EYE_SEMI_SATURATION, ISLAND_NORMAL_SAMPLES, WATER_REFRACTIVE_INDEX,
                        EXPOSURE_FOLLOW, HALO_FACTOR, HALO_STRENGTH, OZONE_COLUMN_DU, OZONE_CROSS_SECTION,
                        OZONE_CROSS_SECTION_NM, OZONE_HALF_WIDTH, OZONE_LAYER_ALTITUDE, OZONE_PEAK_ALTITUDE,
                        RAYLEIGH_SCALE_HEIGHT, SUN_SUPERSAMPLE,
                        SUN_TEMPERATURE, SUN_TRUE_RADIUS)
from .errors import SunsetError, require_finite
from .sun import Sun

__all__ = [
    "spectral_data", "tables_linear", "kasten_young_air_mass", "slant_columns", "sky_radiance", "sun_transmittance", "sun_radiance", "sun_colour",
    "visible_fraction", "ozone_air_mass", "island_lighting", "direct_irradiance", "tables", "sun_coverage", "expose", "PASSES",
    "eye_response", "fresnel_reflectance", "irradiance", "sky_dome", "island_normals",
]

#: The three passes of the film recorder, in order.
PASSES = ("red", "green", "blue")

#: Sample counts of the single-scattering integrals (view ray, sun column, hemisphere).
_N_VIEW = 48
_N_SUN = 24
_N_HEMI_MU = 8
_N_HEMI_PHI = 16
#: Sub-samples of each island code's dither interval.
_N_SUBCODE = 16


# --------------------------------------------------------------------------- spectral data
@functools.lru_cache(maxsize=None)
def spectral_data() -> SimpleNamespace:
    """Wavelengths and spectra on a 10 nm grid, 380–780 nm, computed once.

    Returns a namespace with ``wavelengths`` (nm), ``cmfs`` (CIE 1931 2°,
    (n, 3)), ``sun`` (blackbody, normalised to mean 1), ``tau`` (3, n): the
    vertical optical depths from sea level of the molecules (Rayleigh), the
    aerosol and the ozone, and ``reflectance`` (a dict: hill, cliff, beach).
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


def _xyz_to_linear_srgb(xyz: np.ndarray) -> np.ndarray:
    """CIE XYZ → linear sRGB, adapted (CAT02) from the film's white (:func:`film_white`) to D65."""
    import colour

    return colour.XYZ_to_sRGB(xyz, illuminant=film_white(), chromatic_adaptation_transform="CAT02",
                              apply_cctf_encoding=False)


def _spectrum_to_xyz(spec: np.ndarray) -> np.ndarray:
    """Integrate spectra (..., n) against the CMFs: XYZ (..., 3), 10 nm steps."""
    return spec @ spectral_data().cmfs * 10.0


def _encode(lin: np.ndarray) -> np.ndarray:
    """Linear [0, 1] → sRGB-encoded [0, 1] (IEC 61966-2-1)."""
    lin = np.clip(lin, 0.0, 1.0)
    return np.where(lin <= 0.0031308, 12.92 * lin, 1.055 * np.power(lin, 1 / 2.4) - 0.055)


def _decode(enc: np.ndarray) -> np.ndarray:
    """sRGB-encoded [0, 1] → linear [0, 1]."""
    enc = np.clip(enc, 0.0, 1.0)
    return np.where(enc <= 0.04045, enc / 12.92, np.power((enc + 0.055) / 1.055, 2.4))


def _to_uint8(enc: np.ndarray) -> np.ndarray:
    return np.clip(np.rint(enc * 255.0), 0, 255).astype(np.uint8)


#: sRGB byte → linear value, for mixing in linear light.
_DECODE_LUT = _decode(np.arange(256) / 255.0)


# --------------------------------------------------------------------------- air mass and columns
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


def sky_radiance(directions, sun_dir, n_view: int = _N_VIEW, n_sun: int = _N_SUN) -> np.ndarray:
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
    # the sun's direction cosine at each sample point (the local vertical is the point's radius)
    mu_s = (R * p[2] + s * cos_g[:, None]) / r
    col = view + slant_columns(h, mu_s, n_sun)           # (K, n, 3)
    trans = np.exp(-(col @ sp.tau))                      # (K, n, λ)
    scat = (dens[..., 0] * _phase_rayleigh(cos_g)[:, None])[..., None] * sp.tau[0] \
        + (dens[..., 1] * AEROSOL_ALBEDO * _phase_hg(cos_g)[:, None])[..., None] * sp.tau[1]
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
    diffuse = (d_omega[: len(up)] * up[:, 2]) @ sky_radiance(up, sun_dir)
    return direct_irradiance(sun_dir, delta), diffuse


def direct_irradiance(sun_dir, delta: float) -> np.ndarray:
    """The sun's direct beam on a surface facing it, spectral, per unit E₀ (n_λ,).

    Transmittance along the slant path times the fraction of the disk of
    angular radius ``delta`` (radians) above the horizon.
    """
    e = _elevation(sun_dir)
    return spectral_data().sun * sun_transmittance(e) * visible_fraction(e, delta)


def _elevation(direction) -> float:
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
    cos = np.clip(np.asarray(normals, dtype=float) @ np.asarray(directions, dtype=float).T, 0.0, None)
    return (cos * np.asarray(solid_angles, dtype=float)) @ np.asarray(radiance, dtype=float)


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
    dirs, d_omega = _sphere()
    half = len(dirs) // 2
    sky = sky_radiance(dirs[:half], sun_dir)
    sea = fresnel_reflectance(dirs[:half, 2])[:, None] * sky
    return dirs, np.concatenate([sky, sea]), d_omega


def island_normals(sun: Sun, psi, samples: int = ISLAND_NORMAL_SAMPLES) -> tuple[np.ndarray, np.ndarray]:
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
    in_plane = np.cos(psi)[:, None] * sun.U + np.sin(psi)[:, None] * sun.V            # (K, 3)
    n = np.cos(beta)[None, :, None] * in_plane[:, None, :] + np.sin(beta)[None, :, None] * sun.W
    w = np.where(n[..., 2] > 0.0, np.cos(beta)[None, :], 0.0)
    total = w.sum(axis=1, keepdims=True)
    w = np.where(total > 0, w / np.where(total > 0, total, 1.0), 1.0 / samples)
    return n, w


@functools.lru_cache(maxsize=None)
def _reference_white() -> np.ndarray:
    """XYZ of a white horizontal card in full sun at the reference elevation (sun + sky)."""
    e = math.radians(EXPOSURE_SUN_ELEVATION)
    p = np.array([0.0, math.cos(e), math.sin(e)])
    direct, diffuse = island_lighting(p, SUN_TRUE_RADIUS)
    return _spectrum_to_xyz((direct * math.sin(e) + diffuse) / math.pi)


@functools.lru_cache(maxsize=None)
def film_white() -> tuple[float, float]:
    """CIE xy chromaticity the film is balanced for: daylight on a white card (sun at 30° plus sky)."""
    xyz = _reference_white()
    return (float(xyz[0] / xyz.sum()), float(xyz[1] / xyz.sum()))


def exposure_key(sun_dir) -> float:
    """The luminance the film is exposed for, relative to the white card.

    (L_key)^k with L_key the sky's luminance 5° above the horizon along the
    camera's axis, relative to the reference white card, and
    k = :data:`~sunset.constants.EXPOSURE_FOLLOW`: the camera opens up as the
    light fades, but not all the way, so the sunset still darkens.
    """
    e = math.radians(5.0)
    key = float(_spectrum_to_xyz(sky_radiance(np.array([[0.0, math.cos(e), math.sin(e)]]), sun_dir))[0, 1])
    key = max(key / float(_reference_white()[1]), 1e-6)
    return key ** EXPOSURE_FOLLOW


def eye_response(x) -> np.ndarray:
    """The display's response to relative luminance x >= 0: a Naka–Rushton curve, in [0, 1).

    y = xⁿ / (xⁿ + σⁿ) with n = :data:`~sunset.constants.EYE_RESPONSE_EXPONENT`
    and σ = :data:`~sunset.constants.EYE_SEMI_SATURATION` (Naka & Rushton 1966):
    the photoreceptors' compressive response, which is why the eye, adapted to a
    sunset sky, still sees the islands in their shadow that a photograph
    exposed for the same sky shows black. Below σ it is nearly the power law
    (x/σ)ⁿ, so a ratio of 300 in luminance becomes a ratio of at most
    300ⁿ ≈ 31.
    """
    a = np.power(np.clip(np.asarray(x, dtype=float), 0.0, None), EYE_RESPONSE_EXPONENT)
    return a / (a + EYE_SEMI_SATURATION ** EYE_RESPONSE_EXPONENT)


def _film(radiance: np.ndarray, key: float) -> np.ndarray:
    """Spectral radiance (..., n_λ) → the linear display value in each pass (..., 3).

    XYZ relative to the white card and the exposure key, the eye's response
    (:func:`eye_response`) applied to the luminance Y, and linear sRGB scaled
    by y/Y, so the compression keeps each colour's chromaticity. A colour
    that would pass 1 in some pass is mixed towards the grey of the same
    luminance until it fits: very bright light (the sun, its glitter) bleaches
    towards white, as it does on film and in the eye.
    """
    xyz = _spectrum_to_xyz(radiance) / (float(_reference_white()[1]) * key)
    lin = np.clip(_xyz_to_linear_srgb(xyz), 0.0, None)
    y = np.clip(xyz[..., 1], 0.0, None)
    resp = eye_response(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(y > 1e-12, resp / np.where(y > 1e-12, y, 1.0), 0.0)
    rgb = lin * scale[..., None]
    top = rgb.max(axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(top > 1.0, (top - 1.0) / np.where(top > 1.0, top - resp, 1.0), 0.0)
    rgb = (1.0 - t[..., None]) * rgb + t[..., None] * resp[..., None]
    return np.clip(rgb, 0.0, 1.0)


# --------------------------------------------------------------------------- the tables
def _axis_direction(elevation: np.ndarray) -> np.ndarray:
    """The direction along the camera's axis (+y) at each elevation."""
    e = np.asarray(elevation, dtype=float)
    return np.stack([np.zeros_like(e), np.cos(e), np.sin(e)], axis=-1)


def _tent(centres: np.ndarray, at: float, radius: float, width: float) -> np.ndarray:
    """1 within radius − width/2 of ``at``, falling linearly to 0 at radius + width/2."""
    return np.clip((radius + 0.5 * width - np.abs(centres - at)) / width, 0.0, 1.0)


def _island_factors(theta: float, size: int) -> np.ndarray:
    """Mean of max(cos(θ − ψ), 0) over the dither interval of each island offset (triangle weights)."""
    rh0 = island_code_rho(size)
    step = 4.0 / size
    t = (np.arange(_N_SUBCODE) + 0.5) / _N_SUBCODE * 2.0 - 1.0      # in (−1, 1)
    w = 1.0 - np.abs(t)
    rh = rh0[:, None] + t[None, :] * step
    psi = sun_plane_angle(rh)
    f = np.maximum(np.cos(theta - psi), 0.0)
    return (f * w).sum(axis=1) / w.sum()


def _tables_linear(sun: Sun, hours: float) -> tuple[np.ndarray, np.ndarray]:
    """The three passes' tables as linear film response, shape (256, 3), and the sun's colour (3,)."""
    cmap = CODE_MAP
    theta = float(Sun.theta(hours))
    p = sun.position(hours)
    e_sun = _elevation(p)
    out = np.zeros((256, 3))

    # sky: look along the camera's axis at the code's elevation
    z = sky_code_z(cmap.sky.size)
    e_sky = np.arcsin(z)
    sky_dirs = np.stack([np.zeros_like(z), np.cos(e_sky), z], axis=-1)
    # track and halo: away from the sun's height they are the sky "as before" (the
    # sky at the same elevation), so the track shows no seam where it is not glittering
    e_track = track_code_elevations(cmap.track.size, sun)
    e_halo = track_code_elevations(cmap.halo.size, sun)
    dirs = np.concatenate([sky_dirs, _axis_direction(e_track), _axis_direction(e_halo)])
    key = exposure_key(p)
    sky = _film(sky_radiance(dirs, p), key)
    n1, n2 = cmap.sky.size, cmap.sky.size + cmap.track.size
    sky_lin, track_sky, halo_sky = sky[:n1], sky[n1:n2], sky[n2:]

    delta = sun.delta
    sun_lin = _film(sun_radiance(e_sun, delta), key)
    w_track = track_elevation_max(sun) / cmap.track.size       # elevation step of one code
    w_halo = track_elevation_max(sun) / cmap.halo.size
    a = _tent(e_track, e_sun, max(delta, w_track), w_track)[:, None]
    b = HALO_STRENGTH * _tent(e_halo, e_sun, max(HALO_FACTOR * delta, w_halo), w_halo)[:, None]
    out[cmap.sky.start:cmap.sky.stop] = sky_lin
    out[cmap.track.start:cmap.track.stop] = (1 - a) * track_sky + a * sun_lin
    out[cmap.halo.start:cmap.halo.stop] = (1 - b) * halo_sky + b * sun_lin

    # islands: reflectance × (direct × cosine factor + diffuse sky)
    direct = direct_irradiance(p, delta)
    dome = sky_dome(p)
    sp = spectral_data()
    for rng, name in zip(cmap.islands, ("hill", "cliff", "beach")):
        f = _island_factors(theta, rng.size)[:, None]
        normals, w = island_normals(sun, sun_plane_angle(island_code_rho(rng.size)))
        cos_beta = (w * np.hypot(normals @ sun.U, normals @ sun.V)).sum(axis=1)[:, None]  # mean |N_UV|
        skylight = np.einsum("kj,kjl->kl", w, irradiance(normals, *dome))
        radiance = sp.reflectance[name] * (direct * cos_beta * f + skylight) / math.pi
        out[rng.start:rng.stop] = _film(radiance, key)
    return out, sun_lin


@functools.lru_cache(maxsize=4096)
def _tables_cached(sun: Sun, hours: float) -> tuple[np.ndarray, np.ndarray]:
    lin, sun_lin = _tables_linear(sun, hours)
    t = np.ascontiguousarray(_to_uint8(_encode(lin)).T)
    t.setflags(write=False)
    sun_lin.setflags(write=False)
    return t, sun_lin


def tables(sun: Sun, hours: float) -> np.ndarray:
    """The film recorder's translation tables for the sun ``hours`` before sunset.

    Parameters
    ----------
    sun : Sun
        The sun's circle (U, V, W) and radius δ.
    hours : float
        Hours before sunset (θ = 15°/h); negative after sunset.

    Returns
    -------
    ndarray (3, 256) uint8, read-only
        One 256-entry table for each pass: red, green, blue.
    """
    require_finite("hours", hours)
    return _tables_cached(sun, float(hours))[0]


def tables_linear(sun: Sun, hours: float) -> np.ndarray:
    """The same tables before the sRGB encoding and rounding: linear film response, (3, 256) float."""
    require_finite("hours", hours)
    return _tables_linear(sun, float(hours))[0].T


def sun_colour(sun: Sun, hours: float) -> np.ndarray:
    """The film's linear response (3,) to the sun's disk ``hours`` before sunset (the "sun colour")."""
    require_finite("hours", hours)
    return _tables_cached(sun, float(hours))[1]


# --------------------------------------------------------------------------- the sun disk
def _dirs(s, z) -> np.ndarray:
    d = np.stack(np.broadcast_arrays(s, np.ones_like(s * z), z), axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def sun_coverage(camera, sun: Sun, hours: float, supersample: int = SUN_SUPERSAMPLE):
    """Fraction of each pixel covered by the sun's disk above the horizon.

    Only pixels near the sun are examined. A pixel whose four corners lie
    inside the disk (a convex spherical cap, so the whole pixel does) and
    whose lower edge is above the horizon ζ = 0 is covered fully; a pixel
    whose centre is farther than δ plus its half-diagonal from the sun's
    centre, or that lies below the horizon, not at all; the rest are
    sub-sampled on a ``supersample`` × ``supersample`` grid.

    Returns
    -------
    (slice, slice, ndarray)
        The rows and columns of the examined box and the coverage in [0, 1]
        of each pixel in it (an empty box when the sun is out of view).
    """
    empty = (slice(0, 0), slice(0, 0), np.zeros((0, 0)))
    p = sun.position(hours)
    delta = sun.delta
    if p[1] <= math.sin(delta):
        return empty
    s_c, z_c = p[0] / p[1], p[2] / p[1]
    ds, dz = camera.pixel_pitch
    reach = 1.1 * math.tan(delta) * (1.0 + s_c * s_c + z_c * z_c) + ds + dz
    c0 = max(0, int(math.floor((s_c - reach - camera.s_min) / ds)))
    c1 = min(camera.width, int(math.ceil((s_c + reach - camera.s_min) / ds)) + 1)
    r0 = max(0, int(math.floor((camera.zy_max - (z_c + reach)) / dz)))
    r1 = min(camera.height, int(math.ceil((camera.zy_max - (z_c - reach)) / dz)) + 1)
    if c0 >= c1 or r0 >= r1 or z_c + reach <= 0.0:
        return empty
    s = camera.s_centres()[c0:c1][None, :]
    z = camera.zy_centres()[r0:r1][:, None]
    cos_d = math.cos(delta)
    centre = _dirs(s, z)
    ang = np.arccos(np.clip(centre @ p, -1.0, 1.0))
    corners_in = np.ones(ang.shape, bool)
    half_diag = np.zeros(ang.shape)
    for fs in (-0.5, 0.5):
        for fz in (-0.5, 0.5):
            corner = _dirs(s + fs * ds, z + fz * dz)
            corners_in &= corner @ p > cos_d
            half_diag = np.maximum(half_diag, np.arccos(np.clip(np.sum(corner * centre, -1), -1.0, 1.0)))
    above = (z - 0.5 * dz) >= 0.0
    below = (z + 0.5 * dz) <= 0.0
    cov = np.where(corners_in & above, 1.0, 0.0)
    rim = ~(corners_in & above) & ~below & (ang - half_diag < delta)
    if np.any(rim):
        rows, cols = np.nonzero(rim)
        n = supersample
        f = (np.arange(n) + 0.5) / n - 0.5
        ss = (s[0, cols][:, None, None] + f[None, None, :] * ds)
        zz = (z[rows, 0][:, None, None] + f[None, :, None] * dz)
        sub = _dirs(ss, zz)
        inside = (sub @ p > cos_d) & (zz > 0.0)
        cov[rows, cols] = inside.reshape(len(rows), -1).mean(axis=1)
    return slice(r0, r1), slice(c0, c1), cov


# --------------------------------------------------------------------------- exposing
def expose(scene, codes, hours: float) -> np.ndarray:
    """Expose one frame of codes: three passes through the tables, then the sun's disk.

    Parameters
    ----------
    scene : Scene
        Only its camera (raster position → direction) and its sun are used.
    codes : ndarray (H, W) uint8
        One frame of the tape.
    hours : float
        Hours before sunset.

    Returns
    -------
    ndarray (H, W, 3) uint8
        sRGB image.
    """
    require_finite("hours", hours)
    codes = np.asarray(codes)
    cam = scene.camera
    if codes.dtype != np.uint8:
        raise SunsetError(f"codes must be uint8, got {codes.dtype}")
    if codes.shape != (cam.height, cam.width):
        raise SunsetError(f"codes must have the camera's shape {(cam.height, cam.width)}, got {codes.shape}")
    tab = tables(scene.sun, hours)
    rgb = np.empty(codes.shape + (3,), np.uint8)
    for k, _colour in enumerate(PASSES):        # one exposure through each filter
        rgb[..., k] = tab[k][codes]
    rows, cols, cov = sun_coverage(cam, scene.sun, hours)
    if cov.size:
        weight = np.where(CODE_MAP.reaches_sky(codes[rows, cols]), cov, 0.0)[..., None]
        if np.any(weight > 0):
            sun_lin = sun_colour(scene.sun, hours)
            box = _DECODE_LUT[rgb[rows, cols]]
            mixed = (1.0 - weight) * box + weight * sun_lin
            rgb[rows, cols] = np.where(weight > 0, _to_uint8(_encode(mixed)), rgb[rows, cols])
    return rgb
