"""What each of the 256 codes of the tape means: the code map, and the rules from a ray to its code.

The Cray wrote one byte per pixel; the film recorder turned bytes into colours
through translation tables (:mod:`sunset.recorder.dicomed`). The 256 codes are divided
into groups, "paint by numbers" (paper, *Color Table Animation*), and within
a group the number carries the illumination information that, together with
the sun's position, decides the colour.

The code map
------------
=========  =====================================================================
group      what the number inside the group says
=========  =====================================================================
hill       green island hill: the sun-plane angle of N, as ρ̂(N) (below)
cliff      brown island cliff: the same
beach      tan beach: the same
sky        a ray that reaches the sky: its z component (√z, finer near the horizon)
track      a reflected ray along the sun's track, |W·R| < sin δ: its elevation
halo       a reflected ray beside the track, sin δ <= |W·R| < sin 3δ: its elevation
=========  =====================================================================

Islands (*Color Specification for Diffuse Reflection*)
------------------------------------------------------
With the sun at P(θ) = U cos θ + V sin θ and a = N·U, b = N·V,
N·P = a cos θ + b sin θ. For θ in [−π/2, π/2] and b > 0 this is positive
exactly when sin θ > ρ(N), with

    ρ(N) = −(N·U) / √((N·U)² + (N·V)²),

the paper's formula with its sign and square roots restored. For b < 0 the
inequality turns round: N·P > 0 exactly when sin θ < −ρ(N). The extended

    ρ̂(N) = ρ(N) if N·V > 0,   2 − ρ(N) otherwise,   in [−1, 3),

is a monotone function of the angle ψ = atan2(N·V, N·U) of N's projection on
the plane of the sun's circle (ρ̂ = −cos ψ on 0 <= ψ <= π, 2 + cos ψ on
π <= ψ < 2π), and for θ in [−π/2, π/2] the shadowed normals are exactly those
with sin θ <= ρ̂(N) <= 2 + sin θ: one band of codes that slides down as the sun
sets. On the half N·V > 0, which the paper considered, that is its rule "the
numbers greater than A + B sin θ are shadows". The code is
A + ⌊B (ρ̂ + 1) + u⌋ taken modulo 4B (ρ̂ = 3 is ρ̂ = −1: the angle ψ wraps),
with u a random number in [0, 1).

Sky and glitter (*Color Specification for the Sky*)
---------------------------------------------------
A ray that ends in the sky is coded by the z component of its final direction.
A reflected ray can meet the sun's disk only if it lies within δ of the plane
of C, i.e. |W·R| < sin δ (the printed "cos δ" cannot be literal: W is the
plane's normal, so rays in the plane have W·R = 0). Such rays get the *track*
codes, indexed by their elevation, which says at which time of day they would
see the sun; rays with sin δ <= |W·R| < sin 3δ get the *halo* codes. A scaled
random number is added to |W·R| and to the index before they are thresholded,
and the random generator is reset with the same seed for every frame, so the
texture does not jitter from frame to frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import (CLOUDY_CODES_BEACH, CLOUDY_CODES_CLIFF, CLOUDY_CODES_CLOUD, CLOUDY_CODES_HILL,
                         CLOUDY_CODES_SKY, CODES_BEACH, CODES_CLIFF, CODES_HALO, CODES_HILL, CODES_SKY, CODES_TRACK,
                         HALO_FACTOR, N_CODES, PART_BEACH, PART_CLIFF, PART_HILL)
from ..model.sun import Sun

__all__ = [
    "CodeRange", "CodeMap", "CODE_MAP", "CLOUDY_CODE_MAP", "code_map", "cloud_index", "cloud_code_depths", "rho",
    "rho_hat", "sun_plane_angle", "island_offsets", "sky_index", "track_elevation_max", "elevation_index",
    "island_code_rho", "sky_code_z", "track_code_elevations",
]


# --------------------------------------------------------------------------- the code map
@dataclass(frozen=True)
class CodeRange:
    """A run of consecutive codes ``start .. start + size − 1`` with one meaning."""

    name: str
    start: int
    size: int
    description: str

    @property
    def stop(self) -> int:
        """One past the last code of the range."""
        return self.start + self.size

    def codes(self) -> np.ndarray:
        """The range's codes, ascending, as uint8."""
        return np.arange(self.start, self.stop, dtype=np.uint8)

    def contains(self, codes) -> np.ndarray:
        """Boolean mask: which of ``codes`` lie in this range."""
        c = np.asarray(codes)
        return (c >= self.start) & (c < self.stop)


@dataclass(frozen=True)
class CodeMap:
    """The groups of the 256 codes, in code order.

    Every code 0..255 belongs to exactly one range (checked on creation).
    """

    hill: CodeRange
    cliff: CodeRange
    beach: CodeRange
    sky: CodeRange
    track: CodeRange
    halo: CodeRange
    cloud: CodeRange | None = None

    def __post_init__(self):
        pos = 0
        for r in self.ranges:
            if r.start != pos or r.size <= 0:
                raise ValueError(f"code range {r.name} must start at {pos} and be non-empty")
            pos = r.stop
        if pos != N_CODES:
            raise ValueError(f"the code ranges cover 0..{pos - 1}, not 0..{N_CODES - 1}")

    @property
    def ranges(self) -> tuple[CodeRange, ...]:
        """All ranges, in code order."""
        clouds = (self.cloud,) if self.cloud is not None else ()
        return (self.hill, self.cliff, self.beach) + clouds + (self.sky, self.track, self.halo)

    @property
    def islands(self) -> tuple[CodeRange, ...]:
        """The island ranges (hill, cliff, beach)."""
        return (self.hill, self.cliff, self.beach)

    def for_part(self, part: int) -> CodeRange:
        """The island range of an island part (``PART_HILL``, ``PART_CLIFF``, ``PART_BEACH``)."""
        return {PART_HILL: self.hill, PART_CLIFF: self.cliff, PART_BEACH: self.beach}[int(part)]

    def group(self, codes) -> np.ndarray:
        """Index into :attr:`ranges` of each code's group (int array, the shape of ``codes``)."""
        c = np.asarray(codes)
        starts = np.array([r.start for r in self.ranges])
        return np.searchsorted(starts, c, side="right") - 1

    def reaches_sky(self, codes) -> np.ndarray:
        """Mask of codes whose ray ends in the sky (sky, track or halo ranges)."""
        return np.asarray(codes) >= self.sky.start

    def table(self) -> list[tuple[str, int, int, str]]:
        """(name, first, last, description) for every range: the map as a table."""
        return [(r.name, r.start, r.stop - 1, r.description) for r in self.ranges]


def _make_map(hill: int = CODES_HILL, cliff: int = CODES_CLIFF, beach: int = CODES_BEACH, cloud: int = 0,
              sky: int = CODES_SKY) -> CodeMap:
    sizes = [("hill", hill, "green hill: A + ⌊B(ρ̂(N) + 1) + u⌋ mod 4B"),
             ("cliff", cliff, "brown cliff: A + ⌊B(ρ̂(N) + 1) + u⌋ mod 4B"),
             ("beach", beach, "tan beach: A + ⌊B(ρ̂(N) + 1) + u⌋ mod 4B"),
             ("cloud", cloud, "cloud, by depth d below the mean level: ⌊n (d + T)/(T + B) + u⌋"),
             ("sky", sky, "ray to the sky: ⌊n √R_z + u⌋"),
             ("track", CODES_TRACK, "reflected ray, |W·R| < sin δ: ⌊n e/e_max + u⌋, e = asin R_z"),
             ("halo", CODES_HALO, "reflected ray, sin δ <= |W·R| < sin 3δ: ⌊n e/e_max + u⌋")]
    ranges, pos = {}, 0
    for name, size, doc in sizes:
        if size:
            ranges[name] = CodeRange(name, pos, size, doc)
            pos += size
    return CodeMap(**ranges)


#: The code map used by the vector stage and the film recorder alike.
CODE_MAP = _make_map()

#: The code map of a scene with clouds: a cloud range between the islands and the sky.
CLOUDY_CODE_MAP = _make_map(CLOUDY_CODES_HILL, CLOUDY_CODES_CLIFF, CLOUDY_CODES_BEACH, CLOUDY_CODES_CLOUD,
                            CLOUDY_CODES_SKY)


def code_map(scene) -> CodeMap:
    """The code map of a scene: :data:`CODE_MAP`, or :data:`CLOUDY_CODE_MAP` when it has clouds."""
    return CLOUDY_CODE_MAP if getattr(scene, "clouds", None) is not None else CODE_MAP


# --------------------------------------------------------------------------- clouds: depth
def cloud_index(depth, size: int, top: float, bottom: float, u) -> np.ndarray:
    """Index in the cloud range: ⌊n (d + T)/(T + B) + u⌋ clipped to 0..n−1, T and B the layer's greatest top and bottom."""
    x = (np.asarray(depth, dtype=float) + top) * (size / (top + bottom))
    return np.clip(np.floor(x + u).astype(np.int64), 0, size - 1)


def cloud_code_depths(size: int, top: float, bottom: float) -> np.ndarray:
    """The depth below the mean level (metres) each cloud index is centred on."""
    return _dithered_centres(size) * ((top + bottom) / size) - top


# --------------------------------------------------------------------------- islands: ρ(N)
def _nu_nv(normals, sun: Sun) -> tuple[np.ndarray, np.ndarray]:
    n = np.asarray(normals, dtype=float)
    return n @ sun.U, n @ sun.V


def rho(normals, sun: Sun) -> np.ndarray:
    """ρ(N) = −(N·U)/√((N·U)² + (N·V)²), the paper's shading parameter.

    For N·V > 0 and θ in [−π/2, π/2], N·P(θ) > 0 (lit) exactly when
    ρ(N) < sin θ; for N·V < 0 it is lit exactly when sin θ < −ρ(N)
    (see :func:`rho_hat`). Normals along ±W (N·U = N·V = 0), which the sun's
    plane never lights, get ρ = 1.

    Parameters
    ----------
    normals : array_like (..., 3)
        Unit surface normals N.
    sun : Sun

    Returns
    -------
    ndarray (...)
        ρ(N) in [−1, 1].
    """
    return _rho(*_nu_nv(normals, sun))


def _rho(a, b) -> np.ndarray:
    """ρ from a = N·U and b = N·V."""
    r = np.hypot(a, b)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(r > 1e-12, -a / np.where(r > 1e-12, r, 1.0), 1.0)
    return np.clip(out, -1.0, 1.0)


def rho_hat(normals, sun: Sun) -> np.ndarray:
    """ρ̂(N): ρ(N) where N·V > 0, 2 − ρ(N) elsewhere; in [−1, 3).

    A monotone function of the sun-plane angle ψ = atan2(N·V, N·U) in [0, 2π):
    ρ̂ = −cos ψ for ψ <= π and 2 + cos ψ for ψ >= π. For θ in [−π/2, π/2],
    N·P(θ) <= 0 (shadow) exactly when sin θ <= ρ̂(N) <= 2 + sin θ.
    """
    a, b = _nu_nv(normals, sun)
    r = _rho(a, b)
    out = np.where(b > 0, r, 2.0 - r)
    return np.where(out >= 3.0, out - 4.0, out)


def sun_plane_angle(rh) -> np.ndarray:
    """ψ in [0, 2π) from ρ̂ (the inverse of ρ̂ = −cos ψ | 2 + cos ψ); ρ̂ is taken modulo 4."""
    rh = np.mod(np.asarray(rh, dtype=float) + 1.0, 4.0) - 1.0
    return np.where(rh <= 1.0, np.arccos(np.clip(-rh, -1.0, 1.0)),
                    2.0 * np.pi - np.arccos(np.clip(rh - 2.0, -1.0, 1.0)))


def island_offsets(rh, size: int, u) -> np.ndarray:
    """Offsets in an island range: ⌊B (ρ̂ + 1) + u⌋ mod 4B, B = size/4 (ints)."""
    y = np.asarray(rh, dtype=float) + 1.0
    return np.mod(np.floor(y * (size / 4.0) + u).astype(np.int64), size)


def island_code_rho(size: int) -> np.ndarray:
    """ρ̂ at which each offset of an island range is centred (offset k ↔ ρ̂ = 4k/size − 1).

    With the dither u the expected offset equals B(ρ̂ + 1) exactly, so offset k
    is centred on ρ̂ = k/B − 1 and holds values up to 1/B either side.
    """
    return np.arange(size) * (4.0 / size) - 1.0


# --------------------------------------------------------------------------- sky and glitter
def sky_index(z, size: int, u) -> np.ndarray:
    """Index in the sky range: ⌊n √max(z, 0) + u⌋, clipped to 0..n−1."""
    y = np.sqrt(np.clip(np.asarray(z, dtype=float), 0.0, 1.0)) * size
    return np.clip(np.floor(y + u).astype(np.int64), 0, size - 1)


def sky_code_z(size: int) -> np.ndarray:
    """The z component each sky index is centred on (index k ↔ √z = k/n; ends adjusted)."""
    y = _dithered_centres(size)
    return (y / size) ** 2


def _dithered_centres(size: int) -> np.ndarray:
    """Mean of y over the values coded k by ⌊y + u⌋ clipped to 0..n−1, y uniform on [0, n].

    k for interior codes; 1/3 for the first (it only gets y in [0, 1)) and
    n − 7/9 for the last (it also absorbs ⌊y + u⌋ = n).
    """
    y = np.arange(size, dtype=float)
    if size >= 2:
        y[0] = 1.0 / 3.0
        y[-1] = size - 7.0 / 9.0
    else:
        y[0] = 0.5
    return y


def track_elevation_max(sun: Sun) -> float:
    """e_max: the highest elevation the track and halo codes resolve, radians.

    The sun climbs no higher than its tilt, and a ray within 3δ of its plane no
    higher than tilt + 3δ.
    """
    return min(math.pi / 2.0, math.radians(sun.tilt) + HALO_FACTOR * sun.delta)


def elevation_index(z, size: int, e_max: float, u) -> np.ndarray:
    """Index ⌊n asin(z)/e_max + u⌋ clipped to 0..n−1 (track and halo ranges)."""
    e = np.arcsin(np.clip(np.asarray(z, dtype=float), 0.0, 1.0))
    return np.clip(np.floor(e * (size / e_max) + u).astype(np.int64), 0, size - 1)


def track_code_elevations(size: int, sun: Sun) -> np.ndarray:
    """The elevation (radians) each track or halo index is centred on."""
    return _dithered_centres(size) * (track_elevation_max(sun) / size)


# --------------------------------------------------------------------------- encoding a frame
