"""What the paper says of its Figures 2 and 4–7, measured in ours.

Each function measures one claim the paper makes about one of its figures,
on the renderer's own output (frames, codes, tables), so that the book can
set the paper's words beside numbers:

* Figure 2, "wide shallow troughs, and narrow more highly curved crests":
  :func:`stokes_shape`.
* Figure 4, the still-water reflection of the sun, "oblong" and
  "trapezoidal": :func:`glitter_map` and :func:`still_reflection` (its extent
  in degrees against the sun's disk, the lean of its sides against the one W
  gives, and whether it is one patch or two streaks).
* Figure 5, "colourful bands on the waves' downslopes", and the difference
  between Figures 5 and 6: :func:`reflection_modes` (where the first
  reflected ray points down, where it would strike the next wave, where the
  two figures' codes differ, and how those places sit on the waves' slopes).
* Figure 6, "about 10% to 15% of the rays undergo secondary reflection":
  :attr:`ReflectionModes.twice_share`.
* Figure 7, early-afternoon lighting of Figure 6's data: :func:`afternoon_glitter`
  (why no glitter appears: how high the reflected rays reach against the sun).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SunsetError, require_finite, require_time


# --------------------------------------------------------------------------- Figure 2
@dataclass(frozen=True)
class StokesShape:
    """The shape of Stokes' series (eq. 2) summed to ``order`` terms, in units of the wave number k.

    Attributes
    ----------
    crest_height, trough_depth : float
        k × elevation of the crest above, and of the trough below, the mean level.
    crest_curvature, trough_curvature : float
        |d²(kz)/d(kx)²| at the crest (kx = 0) and at the trough (kx = π).
    crest_fraction : float
        Share of one wavelength where the surface is above its mean level
        (0.5 for a cosine).
    """

    crest_height: float
    trough_depth: float
    crest_curvature: float
    trough_curvature: float
    crest_fraction: float


def stokes_shape(alpha: float, order: int = 4, samples: int = 20000) -> StokesShape:
    """Measure the series' wave form on a grid: heights, curvatures (finite differences), crest width."""
    from ..model.stokes import stokes_coefficients

    require_finite("alpha", alpha)
    if int(samples) != samples or samples < 100:
        raise SunsetError(f"samples must be an integer of at least 100, got {samples!r}")
    amps = np.asarray(stokes_coefficients(float(alpha), order), dtype=float)
    kx = np.linspace(-math.pi, math.pi, int(samples), endpoint=False)
    n = np.arange(1, len(amps) + 1)
    z = (amps[None, :] * np.cos(np.outer(kx, n))).sum(axis=1)
    z -= z.mean()                                   # the mean level (the series has none, but be exact)
    step = kx[1] - kx[0]
    curv = (np.roll(z, -1) - 2 * z + np.roll(z, 1)) / step**2
    crest = int(np.argmin(np.abs(kx)))
    trough = 0                                      # kx = −π
    return StokesShape(crest_height=float(z[crest]), trough_depth=float(-z[trough]),
                       crest_curvature=float(abs(curv[crest])), trough_curvature=float(abs(curv[trough])),
                       crest_fraction=float(np.mean(z > 0)))


# --------------------------------------------------------------------------- Figure 4
def glitter_map(scene, codes, hours: float, weights=None) -> np.ndarray:
    """How far each pixel's colour is turned to the sun's (0..1), from its code and the tables' weights.

    ``weights`` (256,) defaults to :func:`sunset.recorder.colour_tables.glitter_weights` for
    ``scene.sun`` at ``hours`` before sunset.
    """
    from ..recorder.colour_tables import glitter_weights

    codes = np.asarray(codes)
    if codes.dtype != np.uint8:
        raise SunsetError(f"codes must be uint8, got {codes.dtype}")
    w = glitter_weights(scene.sun, hours) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != (256,):
        raise SunsetError(f"weights must have shape (256,), got {w.shape}")
    return w[codes]


def pixel_angles(camera) -> tuple[np.ndarray, np.ndarray]:
    """Azimuth (right of the view axis) and elevation of every pixel centre's ray, degrees, (H, W) each."""
    d = camera.directions()
    return np.degrees(np.arctan2(d[..., 0], d[..., 1])), np.degrees(np.arcsin(np.clip(d[..., 2], -1.0, 1.0)))


@dataclass(frozen=True)
class StillReflection:
    """The sun's reflection in still water (Figure 4), as the glitter map lights it.

    Angles in degrees; depression is the angle below the horizon.

    Attributes
    ----------
    pixels : int
        Pixels whose colour is at least ``threshold`` of the way to the sun's.
    width, height : float
        The lit patch's extent in azimuth and in depression.
    row_width : float
        Median width in azimuth of the lit span of one pixel row.
    disk : float
        The sun's (enlarged) diameter 2δ.
    centre_azimuth, centre_depression : float
        The lit patch's centroid.
    sun_azimuth, sun_elevation : float
        Where the sun stands (a mirror puts its image at the same azimuth,
        as far below the horizon as the sun is above it).
    lean, lean_expected : float
        How far the patch's rows drift in azimuth per degree of depression
        (a least-squares slope of row centres; 0 for a rectangle standing
        upright), and the drift of the mirrored sun's path at the sun's
        elevation, from U, V and W.
    double_rows : float
        Share of lit rows whose lit pixels form two spans separated by a gap
        wider than δ: 0 for one patch; large for two streaks.
    """

    pixels: int
    width: float
    height: float
    row_width: float
    disk: float
    centre_azimuth: float
    centre_depression: float
    sun_azimuth: float
    sun_elevation: float
    lean: float
    lean_expected: float
    double_rows: float

    @property
    def aspect(self) -> float:
        """Median row width over height: above 1, the patch is wider than tall."""
        return self.row_width / self.height if self.height > 0 else math.inf


def _path_lean(sun, elevation: float) -> float:
    """d(azimuth)/d(elevation) of the sun's path at ``elevation`` (radians), degrees per degree."""
    tilt = math.radians(sun.tilt)
    s = math.sin(elevation) / math.sin(tilt)
    if not -1.0 < s < 1.0:
        return math.nan

    def azimuth(theta):
        p = sun.U * math.cos(theta) + sun.V * math.sin(theta)
        return math.degrees(math.atan2(p[0], p[1]))

    theta = math.asin(s)
    h = 1e-4
    de = math.degrees(math.asin(math.sin(tilt) * math.sin(theta + h)) - math.asin(math.sin(tilt) * math.sin(theta - h)))
    return (azimuth(theta + h) - azimuth(theta - h)) / de


def _box_mean(a: np.ndarray, n: int) -> np.ndarray:
    """Mean over an n × n box around each pixel (edges: the part of the box inside), by cumulative sums."""
    if n <= 1:
        return a
    lo, hi = n // 2, n - n // 2

    def along(x, axis):
        c = np.cumsum(np.insert(x, 0, 0.0, axis=axis), axis=axis)
        m = x.shape[axis]
        i = np.arange(m)
        a0, a1 = np.clip(i - lo, 0, m), np.clip(i + hi, 0, m)
        return (np.take(c, a1, axis=axis) - np.take(c, a0, axis=axis)) / np.expand_dims(a1 - a0, 1 - axis)

    return along(along(np.asarray(a, dtype=float), 1), 0)


def still_reflection(scene, glitter: np.ndarray, hours: float, threshold: float = 0.25) -> StillReflection:
    """Measure the lit patch of a still-water glitter map (from :func:`glitter_map`).

    The map is first averaged over boxes δ/2 on a side, so that the dither
    (random numbers added before the codes are cut) does not break the patch
    into specks; a pixel is lit when that average reaches ``threshold``.

    Parameters
    ----------
    scene : Scene
        Its camera (pixel directions) and sun.
    glitter : ndarray (H, W)
        Weights 0..1 per pixel.
    hours : float
        Hours before sunset (where the sun stands).
    threshold : float
        A pixel is lit when its box-averaged weight is at least this, in (0, 1].
    """
    require_finite("hours", hours)
    if not 0.0 < threshold <= 1.0:
        raise SunsetError(f"threshold must be in (0, 1], got {threshold!r}")
    cam = scene.camera
    glitter = np.asarray(glitter, dtype=float)
    if glitter.shape != (cam.height, cam.width):
        raise SunsetError(f"glitter must have the camera's shape {(cam.height, cam.width)}, got {glitter.shape}")
    az, el = pixel_angles(cam)
    ds = cam.pixel_pitch[0]
    gap_px = math.radians(scene.sun.radius) / ds           # δ in pixels, near the view axis
    lit = _box_mean(glitter, max(1, int(round(gap_px / 2)))) >= threshold
    sun = scene.sun
    p = sun.position(hours)
    sun_az = math.degrees(math.atan2(p[0], p[1]))
    sun_el = math.degrees(math.asin(max(-1.0, min(1.0, float(p[2])))))
    n = int(lit.sum())
    if n == 0:
        return StillReflection(0, 0.0, 0.0, 0.0, 2 * sun.radius, math.nan, math.nan, sun_az, sun_el,
                               math.nan, _path_lean(sun, math.radians(sun_el)), 0.0)
    dep = -el
    rows, widths, centres, depths, doubles = [], [], [], [], 0
    for r in np.flatnonzero(lit.any(axis=1)):
        cols = np.flatnonzero(lit[r])
        rows.append(r)
        widths.append(float(az[r, cols[-1]] - az[r, cols[0]]))
        centres.append(float(az[r, cols].mean()))
        depths.append(float(dep[r, cols[0]]))
        if np.any(np.diff(cols) > gap_px):
            doubles += 1
    lean = float(np.polyfit(depths, centres, 1)[0]) if len(rows) >= 3 else math.nan
    return StillReflection(
        pixels=n, width=float(az[lit].max() - az[lit].min()), height=float(dep[lit].max() - dep[lit].min()),
        row_width=float(np.median(widths)), disk=2.0 * sun.radius,
        centre_azimuth=float(az[lit].mean()), centre_depression=float(dep[lit].mean()),
        sun_azimuth=sun_az, sun_elevation=sun_el,
        # the mirror turns elevation into depression, so the path's lean keeps its sign per degree down
        lean=lean, lean_expected=_path_lean(sun, math.radians(sun_el)), double_rows=doubles / len(rows))


# --------------------------------------------------------------------------- Figures 5 and 6
@dataclass
class ReflectionModes:
    """Figures 5 and 6 of one scene at one time, pixel by pixel.

    Attributes
    ----------
    sea : ndarray (H, W) bool
        Pixels whose direct ray meets the sea.
    downslope : ndarray (H, W) bool
        Sea pixels on a face that leans away from the eye (the normal's
        horizontal part points along the ray's): a wave's downslope.
    down : ndarray (H, W) bool
        Sea pixels whose first reflected ray points down (R_z < 0): Figure 5
        sends it up instead (|R_z|).
    twice : ndarray (H, W) bool
        Sea pixels that Figure 6 reflects a second time (the crest cylinder ahead).
    changed : ndarray (H, W) bool
        Pixels whose code differs between Figures 5 and 6.
    codes5, codes6 : ndarray (H, W) uint8
        The two figures' tapes.
    elevation5 : ndarray (H, W) float
        Elevation (degrees) of Figure 5's final ray, the one its code stands for.
    """

    sea: np.ndarray
    downslope: np.ndarray
    down: np.ndarray
    twice: np.ndarray
    changed: np.ndarray
    codes5: np.ndarray
    codes6: np.ndarray
    elevation5: np.ndarray

    def _share(self, mask, of) -> float:
        n = int(of.sum())
        return float((mask & of).sum()) / n if n else math.nan

    @property
    def twice_share(self) -> float:
        """Share of the sea's pixels that reflect twice in Figure 6."""
        return self._share(self.twice, self.sea)

    @property
    def down_share(self) -> float:
        """Share of the sea's pixels whose first reflected ray points down."""
        return self._share(self.down, self.sea)

    @property
    def downslope_share(self) -> float:
        """Share of the sea's pixels on downslopes."""
        return self._share(self.downslope, self.sea)

    @property
    def down_on_downslopes(self) -> float:
        """Of the rays that point down after one reflection, the share met on downslopes."""
        return self._share(self.downslope, self.down)

    @property
    def twice_on_downslopes(self) -> float:
        """Of the rays Figure 6 reflects twice, the share met on downslopes."""
        return self._share(self.downslope, self.twice)

    @property
    def changed_share(self) -> float:
        """Share of the sea's pixels whose code differs between Figures 5 and 6."""
        return self._share(self.changed, self.sea)

    @property
    def changed_twice(self) -> float:
        """Of the sea pixels whose code changes from Figure 5 to 6, the share that reflect twice.

        1 by construction: a ray that does not meet the crest cylinder takes
        the same path, and gets the same code, in both figures.
        """
        return self._share(self.twice, self.changed & self.sea)

    @property
    def twice_changed(self) -> float:
        """Of the rays Figure 6 reflects twice, the share whose code changes."""
        return self._share(self.changed, self.twice)


def reflection_modes(scene, t: float = 0.0, seed: int = 0) -> ReflectionModes:
    """Render ``scene`` at time ``t`` as Figure 5 (one reflection, |R_z|) and Figure 6 (two), and compare."""
    from ..pipeline.frame import encode, render
    from ..constants import SEA
    from ..vector.pierce import reflect

    require_time("t", t)
    f5 = render(scene, t, 1)
    f6 = render(scene, t, 2)
    sea = f5.surface == SEA
    d = f5.direction.astype(float)
    n = f5.normal.astype(float)
    r = np.zeros_like(d)
    r[sea] = reflect(d[sea], n[sea])
    down = sea & (r[..., 2] < 0)
    downslope = sea & (n[..., 0] * d[..., 0] + n[..., 1] * d[..., 1] > 0)
    twice = sea & (f6.bounces == 2)
    c5 = encode(scene, f5, seed=seed)
    c6 = encode(scene, f6, seed=seed)
    el5 = np.degrees(np.arcsin(np.clip(f5.ray[..., 2].astype(float), -1.0, 1.0)))
    return ReflectionModes(sea=sea, downslope=downslope, down=down, twice=twice, changed=c5 != c6,
                           codes5=c5, codes6=c6, elevation5=el5)


# --------------------------------------------------------------------------- Figure 7
@dataclass(frozen=True)
class AfternoonGlitter:
    """Why Figure 7 has (or lacks) glitter: the sun's height against the reflected rays'.

    Angles in degrees.

    Attributes
    ----------
    sun_elevation : float
        The sun's elevation at ``hours`` before sunset.
    highest_reflection : float
        The highest elevation of a reflected ray that reaches the sky.
    highest_single : float
        The same, among rays reflected only once.
    glitter_from_hours : float
        The sun sinks to ``highest_reflection`` this many hours before
        sunset: from then on some reflected ray can see it (NaN if it never
        climbs that high).
    steepest_face : float
        The steepest sea face any pixel sees (the angle of its normal from the vertical).
    face_needed : float
        The tilt towards the eye that a face must have to reflect a ray
        arriving at the horizon (d = 0) up to the sun: half the sun's
        elevation (a ray arriving d below the horizon leaves at d + 2β).
    """

    sun_elevation: float
    highest_reflection: float
    highest_single: float
    glitter_from_hours: float
    steepest_face: float
    face_needed: float

    @property
    def has_glitter(self) -> bool:
        """Whether any reflected ray climbs as high as the sun."""
        return self.highest_reflection >= self.sun_elevation


def afternoon_glitter(scene, frame, hours: float) -> AfternoonGlitter:
    """Measure, on a traced frame, whether the sun ``hours`` before sunset can glitter on its sea."""
    from ..constants import RADIANS_PER_HOUR, SEA, SKY

    require_finite("hours", hours)
    sun = scene.sun
    e_sun = math.degrees(math.asin(max(-1.0, min(1.0, float(sun.position(hours)[2])))))
    to_sky = (frame.bounces > 0) & (frame.final_surface == SKY)
    el = np.degrees(np.arcsin(np.clip(frame.ray[..., 2].astype(float), -1.0, 1.0)))
    top = float(el[to_sky].max()) if to_sky.any() else -90.0
    once = to_sky & (frame.bounces == 1)
    top1 = float(el[once].max()) if once.any() else -90.0
    s = math.sin(math.radians(top)) / math.sin(math.radians(sun.tilt))
    back = math.degrees(math.asin(s)) / math.degrees(RADIANS_PER_HOUR) if 0.0 <= s <= 1.0 else math.nan
    sea = frame.surface == SEA
    nz = np.clip(frame.normal[..., 2][sea].astype(float), -1.0, 1.0)
    steepest = float(np.degrees(np.arccos(nz)).max()) if sea.any() else 0.0
    return AfternoonGlitter(sun_elevation=e_sun, highest_reflection=top, highest_single=top1, glitter_from_hours=back,
                            steepest_face=steepest, face_needed=0.5 * e_sun)
