"""The film recorder's colour translation tables: 256 entries for each of three passes.

For each hour before sunset, every code of the tape (:mod:`sunset.tape.codemap`)
gets a colour from the physical sky (:mod:`sunset.model.sky`) seen through the
film and the eye (:mod:`sunset.model.eye`):

* **Sky codes** look along the camera's axis at the code's elevation; track and
  halo codes take the same sky value, brightening towards the sun's colour when
  the sun passes their elevation.
* **Islands**: measured reflectance spectra (ColorChecker "foliage" for the
  hill, "dark skin" for the brown cliff, CIE test colour sample 2 for the tan
  beach) under the direct sun × the code's cosine factor, plus the skylight
  averaged over the normals a code stands for
  (:func:`sunset.model.sky.island_normals`). Skylight is what keeps the
  islands' shadowed sides from going black.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .. import kernels
from ..constants import HALO_STRENGTH
from ..errors import SunsetError, require_finite
from ..model.eye import exposure_key, film_response, srgb_encode, to_uint8
from ..model.sky import (direct_irradiance, dome_directions, elevation, irradiance_weights, island_normals, sky_dome,
                         sky_radiance, spectral_data, sun_radiance)
from ..model.clouds import Clouds, cloud_radiance
from ..model.sun import Sun, require_hours
from ..tape.codemap import (CLOUDY_CODE_MAP, CODE_MAP, cloud_code_depths, island_code_rho, sky_code_z, sun_plane_angle, track_code_elevations,
                          track_elevation_max)

__all__ = ["tables", "tables_linear", "sun_colour", "glitter_weights"]

#: Sub-samples of each island code's dither interval.
_N_SUBCODE = 16


def _axis_direction(elevation: np.ndarray) -> np.ndarray:
    """The direction along the camera's axis (+y) at each elevation."""
    e = np.asarray(elevation, dtype=float)
    return np.stack([np.zeros_like(e), np.cos(e), np.sin(e)], axis=-1)


def _tent(centres: np.ndarray, at: float, radius: float, width: float) -> np.ndarray:
    """1 within radius − width/2 of ``at``, falling linearly to 0 at radius + width/2."""
    return np.clip((radius + 0.5 * width - np.abs(centres - at)) / width, 0.0, 1.0)


def glitter_weights(sun: Sun, hours: float, halo_radius: float | None = None) -> np.ndarray:
    """How far each code's table entry is turned from sky colour to sun colour, shape (256,).

    A track code stands for a reflected ray within δ of the sun's plane at the
    elevation the code is centred on; its entry is the sun's colour (weight 1)
    while the sun stands within max(δ, one code's step) of that elevation,
    falling linearly to sky colour over one code's step either side, so that
    at least one entry is sun colour at any time and its neighbours are
    intermediate (the paper, *Color Specification for the Sky*). A halo code
    stands for a ray that deviates *horizontally* from the sun's position, by
    δ to 3δ: its entry goes part of the way (``HALO_STRENGTH``) over the same
    elevations as the track's, so that the glitter widens sideways but not
    lengthwise. (Lighting the halo over 3δ of elevation, as the tables did
    before, made the halo three times taller than the track: on still water,
    two long side streaks joined by a short bright middle, the "N" that
    Figure 4 showed; book, chapter 9.) Every other code gets 0.

    Parameters
    ----------
    sun : Sun
    hours : float
        Hours before sunset.
    halo_radius : float, optional
        The halo's reach in elevation, radians; by default the track's,
        max(δ, one track code's step). Only for showing what another reach
        does (the book passes 3δ to redraw the old "N").
    """
    require_hours("hours", hours)
    cmap = CODE_MAP
    e_sun = elevation(sun.position(hours))
    e_max = track_elevation_max(sun)
    w_track = e_max / cmap.track.size           # elevation step of one track code
    w_halo = e_max / cmap.halo.size
    radius = max(sun.delta, w_track)            # the sun's reach in elevation, as the track sees it
    if halo_radius is None:
        halo_radius = max(radius, 0.5 * w_halo)
    else:
        require_finite("halo_radius", halo_radius)
        if halo_radius <= 0:
            raise SunsetError(f"halo_radius must be positive, got {halo_radius!r}")
    out = np.zeros(256)
    out[cmap.track.start:cmap.track.stop] = _tent(track_code_elevations(cmap.track.size, sun), e_sun, radius,
                                                  w_track)
    out[cmap.halo.start:cmap.halo.stop] = HALO_STRENGTH * _tent(track_code_elevations(cmap.halo.size, sun), e_sun,
                                                                float(halo_radius), w_halo)
    return out


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


@functools.lru_cache(maxsize=64)
def _sky_directions(sun: Sun, cmap) -> tuple[np.ndarray, np.ndarray]:
    """The sky, track and halo codes' view directions, each distinct one once, and where each code's is.

    They depend on the sun's circle alone, not on the hour. The track's and
    the halo's elevations are the same when they have as many codes, and
    each direction's sky is integrated once (row by row, the same bits).
    """
    # sky: look along the camera's axis at the code's elevation
    z = sky_code_z(cmap.sky.size)
    e_sky = np.arcsin(z)
    sky_dirs = np.stack([np.zeros_like(z), np.cos(e_sky), z], axis=-1)
    # track and halo: away from the sun's height they are the sky "as before" (the
    # sky at the same elevation), so the track shows no seam where it is not glittering
    e_track = track_code_elevations(cmap.track.size, sun)
    e_halo = track_code_elevations(cmap.halo.size, sun)
    dirs = np.ascontiguousarray(np.concatenate([sky_dirs, _axis_direction(e_track), _axis_direction(e_halo)]))
    _, first, where = np.unique(dirs.view(np.dtype((np.void, 3 * dirs.itemsize))).ravel(), return_index=True,
                                return_inverse=True)
    distinct = dirs[first]
    for a in (distinct, where):
        a.setflags(write=False)
    return distinct, where.ravel()


@functools.lru_cache(maxsize=64)
def _island_geometry(sun: Sun, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An island's codes' normal weights (K, S), mean |N_UV| (K, 1) and skylight weights (K, S, M): not hourly."""
    normals, w = island_normals(sun, sun_plane_angle(island_code_rho(size)))
    cos_beta = (w * np.hypot(normals @ sun.U, normals @ sun.V)).sum(axis=1)[:, None]  # mean |N_UV|
    dirs, d_omega = dome_directions()
    weights = irradiance_weights(normals, dirs, d_omega)
    for a in (w, cos_beta, weights):
        a.setflags(write=False)
    return w, cos_beta, weights


def _tables_linear(sun: Sun, hours: float, clouds: Clouds | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The three passes' tables as linear film response, shape (256, 3), and the sun's colour (3,).

    Every code's spectral radiance first, then the film's response to all of
    them at once (row by row, the same bits as one code range at a time).
    """
    cmap = CLOUDY_CODE_MAP if clouds is not None else CODE_MAP
    theta = float(Sun.theta(hours))
    p = sun.position(hours)
    e_sun = elevation(p)
    out = np.zeros((256, 3))
    key = exposure_key(p)
    delta = sun.delta
    sun_lin = film_response(sun_radiance(e_sun, delta), key)

    # sky, track and halo codes: the sky along the camera's axis (track and halo below)
    distinct, where = _sky_directions(sun, cmap)
    ranges = [cmap.sky, cmap.track, cmap.halo]
    radiance = [sky_radiance(distinct, p)[where]]

    # islands: reflectance × (direct × cosine factor + diffuse sky)
    direct = direct_irradiance(p, delta)
    dome = sky_dome(p)
    sp = spectral_data()
    for rng, name in zip(cmap.islands, ("hill", "cliff", "beach")):
        f = _island_factors(theta, rng.size)[:, None]
        w, cos_beta, weights = _island_geometry(sun, rng.size)
        skylight = np.einsum("kj,kjl->kl", w, weights @ dome[1])
        radiance.append(sp.reflectance[name] * (direct * cos_beta * f + skylight) / math.pi)
        ranges.append(rng)

    # clouds: lit by the sun at their own altitude, shaded by depth below the mean level
    if clouds is not None:
        depth = cloud_code_depths(cmap.cloud.size, clouds.max_top, clouds.max_bottom)
        radiance.append(cloud_radiance(depth, p, clouds, delta))
        ranges.append(cmap.cloud)

    lin = film_response(np.concatenate(radiance), key)
    at = np.cumsum([0] + [rng.size for rng in ranges])
    parts = {rng.name: lin[a:b] for rng, a, b in zip(ranges, at[:-1], at[1:])}
    weights = glitter_weights(sun, hours)
    a = weights[cmap.track.start:cmap.track.stop, None]
    b = weights[cmap.halo.start:cmap.halo.stop, None]
    for rng in ranges:
        out[rng.start:rng.stop] = parts[rng.name]
    out[cmap.track.start:cmap.track.stop] = (1 - a) * parts["track"] + a * sun_lin
    out[cmap.halo.start:cmap.halo.stop] = (1 - b) * parts["halo"] + b * sun_lin
    return out, sun_lin


def _tables_cached(sun: Sun, hours: float, clouds: Clouds | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The 8-bit tables (3, 256) and the sun's colour, kept per path of :mod:`sunset.kernels` (which agree
    within a tolerance, not to the bit)."""
    return _tables_kept(sun, hours, clouds, kernels.enabled())


@functools.lru_cache(maxsize=4096)
def _tables_kept(sun: Sun, hours: float, clouds: Clouds | None, compiled: bool) -> tuple[np.ndarray, np.ndarray]:
    lin, sun_lin = _tables_linear(sun, hours, clouds)
    t = np.ascontiguousarray(to_uint8(srgb_encode(lin)).T)
    t.setflags(write=False)
    sun_lin.setflags(write=False)
    return t, sun_lin


def tables(sun: Sun, hours: float, clouds: Clouds | None = None) -> np.ndarray:
    """The film recorder's translation tables for the sun ``hours`` before sunset.

    Parameters
    ----------
    sun : Sun
        The sun's circle (U, V, W) and radius δ.
    hours : float
        Hours before sunset (θ = 15°/h); negative after sunset.
    clouds : Clouds, optional
        The scene's cloud layer: the tables then follow
        :data:`~sunset.tape.codemap.CLOUDY_CODE_MAP`.

    Returns
    -------
    ndarray (3, 256) uint8, read-only
        One 256-entry table for each pass: red, green, blue.
    """
    require_hours("hours", hours)
    return _tables_cached(sun, float(hours), clouds)[0]


def tables_linear(sun: Sun, hours: float, clouds: Clouds | None = None) -> np.ndarray:
    """The same tables before the sRGB encoding and rounding: linear film response, (3, 256) float."""
    require_hours("hours", hours)
    return _tables_linear(sun, float(hours), clouds)[0].T


def sun_colour(sun: Sun, hours: float, clouds: Clouds | None = None) -> np.ndarray:
    """The film's linear response (3,) to the sun's disk ``hours`` before sunset (the "sun colour")."""
    require_hours("hours", hours)
    return _tables_cached(sun, float(hours), clouds)[1]
