"""Islands: elliptical paraboloids with cosine hills (paper eqs. 3 and 4).

Heights in this module are metres above mean sea level; the camera puts mean
sea level at z = −h, so an island point of height H sits at z = H − h in the
eye's coordinates (the paper writes its paraboloids in the eye's coordinates,
which is why its bounding ellipse carries a "+ h").

An island is made of two paraboloids with a common apex (X, Y):

* the *cliff* paraboloid P_c (eq. 3) plus the cosine terms gives the cliff/hill
  equation Q = P_c + Σ_j a_j cos(ℓ_j x + m_j y) (eq. 4);
* above the cliff-top plane H = c the height above that plane is multiplied by
  the hill factor φ: the *hill* surface is c + φ (Q − c) (the paper's "the height
  above the cliff level is decreased by a constant factor");
* the *beach* paraboloid P_b (no cosine terms) shows wherever it is higher.

So the island's surface is

    H(x, y) = max(P_b, min(Q, c + φ (Q − c)))

(for 0 < φ <= 1 the min picks Q below the cliff top and the flattened hill
above it), and each point belongs to one part: beach where P_b is on top, cliff
where Q <= c, hill above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..constants import (MAX_COSINES, MAX_PHASE, MAX_TEXT_CHARS, MAX_CURVATURE, MAX_DISTANCE, MAX_HILL_WAVENUMBER, MAX_ISLAND_HEIGHT,
                         MIN_CURVATURE, PART_BEACH, PART_CLIFF, PART_HILL)
from ..errors import (SunsetError, require_finite, require_instance, require_items, require_nonnegative, require_positive,
                      require_range, require_scalars, require_text)
from .waves import unit_normal


@dataclass(frozen=True)
class Cosine:
    """One rolling-hill term a cos(ℓx + my + φ) of eq. 4.

    amplitude in metres (>= 0); l, m in rad m⁻¹; phase φ in radians (the
    paper's terms have φ = 0, the default; φ = π turns hills into hollows,
    as a negative amplitude would).
    """

    amplitude: float
    l: float
    m: float
    phase: float = 0.0

    def __post_init__(self):
        require_scalars(self)
        require_nonnegative("amplitude", self.amplitude)
        require_range("amplitude", self.amplitude, 0.0, MAX_ISLAND_HEIGHT, "m")
        require_range("l", self.l, -MAX_HILL_WAVENUMBER, MAX_HILL_WAVENUMBER, "rad/m")
        require_range("m", self.m, -MAX_HILL_WAVENUMBER, MAX_HILL_WAVENUMBER, "rad/m")
        require_range("phase", self.phase, -MAX_PHASE, MAX_PHASE, "radians")


@dataclass(frozen=True)
class Paraboloid:
    """P(x, y) = height − e(x−X)² − f(x−X)(y−Y) − g(y−Y)² (eq. 3), apex at (X, Y).

    ``height`` in metres above mean sea level, e, f, g in m⁻¹; the form must
    be positive definite (e > 0, g > 0, f² < 4eg) so that P has a top.
    """

    height: float
    e: float
    f: float
    g: float

    def __post_init__(self):
        require_scalars(self)
        require_range("height", self.height, -MAX_ISLAND_HEIGHT, MAX_ISLAND_HEIGHT, "m")
        require_positive("e", self.e)
        require_range("e", self.e, MIN_CURVATURE, MAX_CURVATURE, "1/m")
        require_finite("f", self.f)
        require_positive("g", self.g)
        require_range("g", self.g, MIN_CURVATURE, MAX_CURVATURE, "1/m")
        if not self.f * self.f < 4.0 * self.e * self.g:
            raise SunsetError(f"f must satisfy f² < 4·e·g (an elliptical paraboloid), got e={self.e!r}, f={self.f!r}, g={self.g!r}")

    def value(self, dx, dy):
        """P at offsets (dx, dy) = (x − X, y − Y) from the apex, metres (eq. 3)."""
        return self.height - (self.e * dx * dx + self.f * dx * dy + self.g * dy * dy)

    def gradient(self, dx, dy):
        """(∂P/∂x, ∂P/∂y) at offsets (dx, dy) from the apex (dimensionless slopes)."""
        return -(2.0 * self.e * dx + self.f * dy), -(self.f * dx + 2.0 * self.g * dy)

    @property
    def min_curvature(self) -> float:
        """The smallest eigenvalue λ of the form [[e, f/2], [f/2, g]], m⁻¹.

        P <= height − λ r² at distance r from the apex, so P falls below a
        level L outside the circle r = √((height − L)/λ).
        """
        return 0.5 * (self.e + self.g - math.hypot(self.e - self.g, self.f))

    def chord(self, X: float, Y: float, level: float, s):
        """Where the scan line x = s·y crosses inside the ellipse P = level.

        Substituting x = s·y into eq. 3 gives A y² − B y + C = height − level
        with A = e s² + f s + g, B = 2 e s X + f (X + s Y) + 2 g Y and
        C = e X² + f X Y + g Y², so the chord is the interval between the two
        roots.

        Parameters
        ----------
        X, Y : float
            The apex, metres.
        level : float
            Height of the ellipse's plane, metres above mean sea level.
        s : array_like
            Scan-line slopes x/y.

        Returns
        -------
        y_near, y_far : ndarray
            The chord's ends along y, metres, shape of ``s``; NaN where the
            scan line misses the ellipse (or the level is above the apex).
        """
        s = np.asarray(s, dtype=float)
        a = self.e * s * s + self.f * s + self.g  # > 0: positive-definite form
        b = 2.0 * self.e * s * X + self.f * (X + s * Y) + 2.0 * self.g * Y
        c = self.e * X * X + self.f * X * Y + self.g * Y * Y - (self.height - level)
        disc = b * b - 4.0 * a * c
        ok = disc >= 0
        root = np.sqrt(np.where(ok, disc, 0.0))
        # numerically stable pair of roots
        q = 0.5 * (b + np.copysign(root, b))
        with np.errstate(divide="ignore", invalid="ignore"):
            r1 = q / a
            r2 = np.where(q != 0, c / q, r1)
        y_near = np.where(ok, np.minimum(r1, r2), np.nan)
        y_far = np.where(ok, np.maximum(r1, r2), np.nan)
        return y_near, y_far


@dataclass(frozen=True)
class Island:
    """One island: a beach paraboloid and a cliff paraboloid that turns into hills.

    Parameters
    ----------
    x, y : float
        (X_k, Y_k), the apex of both paraboloids, metres; y > 0 (in front of the eye).
    cliff : Paraboloid
        The steep brown paraboloid; above ``cliff_top`` its height above the
        cliff top is multiplied by ``hill_factor`` and it is coloured green.
    beach : Paraboloid
        The shallow tan paraboloid around the cliff's foot.
    cliff_top : float
        Height of the cliff-top plane, metres above mean sea level.
    hill_factor : float
        The constant factor (0, 1] applied above the cliff top.
    cosines : tuple of Cosine
        The rolling-hill terms of eq. 4, added to the cliff/hill paraboloid.
    name : str
        A label for the book and error messages.
    """

    x: float
    y: float
    cliff: Paraboloid
    beach: Paraboloid
    cliff_top: float
    hill_factor: float = 0.3
    cosines: tuple[Cosine, ...] = field(default_factory=tuple)
    name: str = ""

    def __post_init__(self):
        require_scalars(self)
        require_instance("cliff", self.cliff, Paraboloid)
        require_instance("beach", self.beach, Paraboloid)
        object.__setattr__(self, "cosines", require_items("cosines", self.cosines, Cosine, MAX_COSINES))
        require_text("name", self.name, MAX_TEXT_CHARS)
        require_range("x", self.x, -MAX_DISTANCE, MAX_DISTANCE, "m")
        require_finite("y", self.y)
        if not self.y > 0:
            raise SunsetError(f"y must be positive: the island is behind the eye (y = {self.y!r})")
        if not self.y <= MAX_DISTANCE:
            raise SunsetError(f"y must be at most {MAX_DISTANCE:g} m, got {self.y!r}")
        require_range("cliff_top", self.cliff_top, -MAX_ISLAND_HEIGHT, MAX_ISLAND_HEIGHT, "m")
        if not self.cliff_top < self.cliff.height:
            raise SunsetError(f"cliff_top must be below the cliff paraboloid's apex {self.cliff.height!r}, got {self.cliff_top!r}")
        require_positive("hill_factor", self.hill_factor)
        if self.hill_factor > 1:
            raise SunsetError(f"hill_factor must be in (0, 1], got {self.hill_factor!r}")

    @property
    def max_perturbation(self) -> float:
        """d_k = Σ_j a_jk, the most the cosine terms can add, metres."""
        return float(sum(c.amplitude for c in self.cosines))

    @property
    def max_height(self) -> float:
        """An upper bound of the island's height H, metres above mean sea level.

        The hill above the cliff top is c + φ(Q − c) with Q <= h_k + d_k.
        """
        q = self.cliff.height + self.max_perturbation
        return max(self.beach.height, self.cliff_top + self.hill_factor * (q - self.cliff_top))

    @property
    def smooth_height(self) -> float:
        """Top of the smooth island (eq. 3 without its cosine terms, which reflected rays pierce), m."""
        return max(self.beach.height, self.cliff_top + self.hill_factor * (self.cliff.height - self.cliff_top))

    def smooth_radius(self, level: float) -> float:
        """Distance from the apex beyond which the smooth beach and cliff are below ``level``, metres.

        ``level`` is metres above mean sea level; see :attr:`Paraboloid.min_curvature`.
        """
        return max(math.sqrt(max(p.height - level, 0.0) / p.min_curvature) for p in (self.cliff, self.beach))

    # -- eqs. 3 and 4 ----------------------------------------------------------
    def paraboloid(self, x, y, which: str = "cliff"):
        """P_k(x, y) of eq. 3 for the ``"cliff"`` or ``"beach"`` paraboloid, metres."""
        par = self._paraboloid(which)
        x, y = _xy(x, y)
        return par.value(x - self.x, y - self.y)

    def cliff_equation(self, x, y):
        """Q_k(x, y) = P_k + Σ_j a_jk cos(ℓ_jk x + m_jk y + φ_jk), metres.

        The paper's eq. 4, with a phase.
        """
        x, y = _xy(x, y)
        return self._cliff_value(x, y, self._phases(x, y))

    def cliff_equation_gradient(self, x, y):
        """(∂Q/∂x, ∂Q/∂y) of eq. 4."""
        x, y = _xy(x, y)
        return self._cliff_gradient(x, y, self._phases(x, y))

    def _phases(self, x, y) -> list:
        """ℓ_jk x + m_jk y + φ_jk of each cosine term."""
        return [c.l * x + c.m * y + c.phase for c in self.cosines]

    def _cliff_value(self, x, y, phases):
        q = self.cliff.value(x - self.x, y - self.y)
        for c, ph in zip(self.cosines, phases):
            q = q + c.amplitude * np.cos(ph)
        return q

    def _cliff_gradient(self, x, y, phases):
        qx, qy = self.cliff.gradient(x - self.x, y - self.y)
        for c, ph in zip(self.cosines, phases):
            sn = c.amplitude * np.sin(ph)
            qx = qx - c.l * sn
            qy = qy - c.m * sn
        return qx, qy

    # -- the composite surface ---------------------------------------------------
    def surface(self, x, y, *, with_gradient: bool = True):
        """Height, part and (optionally) gradient of the island's surface.

        H = max(P_b, min(Q, c + φ(Q − c))). The gradient follows the part on
        top: ∇P_b on the beach, ∇Q on the cliff, φ∇Q on the hill (the chain
        rule through the hill factor); on the creases between parts it is
        the one-sided gradient of the part the point is assigned to.

        Parameters
        ----------
        x, y : array_like
            Points, metres; broadcast together. float32 in, float32 out.

        Returns
        -------
        height : ndarray
            H, metres above mean sea level.
        part : ndarray of int8
            PART_BEACH, PART_CLIFF or PART_HILL.
        gx, gy : ndarray
            ∂H/∂x, ∂H/∂y (only when ``with_gradient``).
        """
        x, y = _xy(x, y)
        phases = self._phases(x, y)
        q = self._cliff_value(x, y, phases)
        ct, phi = self.cliff_top, self.hill_factor
        hill = q > ct
        upper = np.where(hill, ct + phi * (q - ct), q)
        beach = self.beach.value(x - self.x, y - self.y)
        on_beach = beach >= upper
        height = np.where(on_beach, beach, upper)
        part = np.where(on_beach, PART_BEACH, np.where(hill, PART_HILL, PART_CLIFF))
        part = part.astype(np.int8)
        if not with_gradient:
            return height, part
        qx, qy = self._cliff_gradient(x, y, phases)
        scale = np.where(hill, phi, 1.0).astype(np.result_type(qx), copy=False)
        bx, by = self.beach.gradient(x - self.x, y - self.y)
        gx = np.where(on_beach, bx, scale * qx)
        gy = np.where(on_beach, by, scale * qy)
        return height, part, gx, gy

    def height(self, x, y):
        """H(x, y), metres above mean sea level (see :meth:`surface`)."""
        return self.surface(x, y, with_gradient=False)[0]

    def part(self, x, y):
        """Which part each point belongs to: PART_BEACH, PART_CLIFF or PART_HILL (int8)."""
        return self.surface(x, y, with_gradient=False)[1]

    def gradient(self, x, y):
        """(∂H/∂x, ∂H/∂y) of the island's surface (see :meth:`surface`)."""
        _, _, gx, gy = self.surface(x, y)
        return gx, gy

    def normal(self, x, y):
        """Unit upward normal (−H_x, −H_y, 1)/√(H_x² + H_y² + 1), shape ``broadcast + (3,)``."""
        return unit_normal(*self.gradient(x, y))

    # -- where samples are needed -------------------------------------------------
    def bound_levels(self, sea_max_elevation: float) -> dict[str, float]:
        """The bounding ellipses' levels, metres above mean sea level.

        The island can show above the water only where H > −d (d: the sea's
        largest departure from its mean level). Since Q <= P_c + d_k and the
        hill is lower than Q above the cliff top, that needs P_c + d_k + d > 0
        or P_b + d > 0: the insides of the ellipses P_c = −(d_k + d) and
        P_b = −d. (In the paper's eye coordinates P_k carries the −h, hence
        its P_k + d_k + h + d = 0.)
        """
        require_nonnegative("sea_max_elevation", sea_max_elevation)
        return {"cliff": -(self.max_perturbation + sea_max_elevation), "beach": -sea_max_elevation}

    def bound_contains(self, x, y, sea_max_elevation: float):
        """True where (x, y) lies inside the bounding ellipses (samples are needed)."""
        lv = self.bound_levels(sea_max_elevation)
        x, y = _xy(x, y)
        dx, dy = x - self.x, y - self.y
        return (self.cliff.value(dx, dy) > lv["cliff"]) | (self.beach.value(dx, dy) > lv["beach"])

    def chord(self, s, sea_max_elevation: float):
        """The y-interval of scan line x = s·y inside the bounding ellipses.

        The hull of the chords of the cliff ellipse P_c + d_k + d = 0 and the
        beach ellipse P_b + d = 0 (the paper's P_k + d_k + h + d = 0 in our
        heights above mean sea level).

        Returns
        -------
        y_near, y_far : ndarray
            Metres, shape of ``s``; NaN where the scan line misses both.
        """
        lv = self.bound_levels(sea_max_elevation)
        a0, a1 = self.cliff.chord(self.x, self.y, lv["cliff"], s)
        b0, b1 = self.beach.chord(self.x, self.y, lv["beach"], s)
        return np.fmin(a0, b0), np.fmax(a1, b1)

    def _paraboloid(self, which: str) -> Paraboloid:
        if which == "cliff":
            return self.cliff
        if which == "beach":
            return self.beach
        raise SunsetError(f"which must be 'cliff' or 'beach', got {which!r}")


def _xy(x, y):
    x = np.asarray(x)
    y = np.asarray(y)
    if x.dtype.kind not in "fc":
        x = x.astype(float)
    if y.dtype.kind not in "fc":
        y = y.astype(float)
    return x, y
