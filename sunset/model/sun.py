"""The sun's great circle C on the unit sphere at the eye (paper, Figure 1).

U points to the setting sun, V to the sun at its highest, W = U × V is normal to
the plane of C, and the sun at θ = 15° per hour before sunset is

    P(θ) = U cos θ + V sin θ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import (MAX_DEGREES, MAX_HOURS_FROM_SUNSET, MIN_SUN_RADIUS, RADIANS_PER_HOUR,
                         SUN_PAPER_RADIUS_DEGREES)
from ..errors import require_scalars, SunsetError, require_finite, require_positive, require_range, shown


def require_hours(name: str, hours) -> None:
    """Raise :class:`SunsetError` unless every value of ``hours`` (hours before sunset) is within ±12 h.

    The sun goes round its circle in 24 hours, so every position is reached
    within half a day of sunset; a user's ``hours`` outside that range is a
    mistake, not another picture. Scalars or arrays.
    """
    require_finite(name, hours)
    worst = float(np.max(np.abs(np.asarray(hours, dtype=float)), initial=0.0))
    if worst > MAX_HOURS_FROM_SUNSET:
        raise SunsetError(f"{name} must be within ±{MAX_HOURS_FROM_SUNSET:g} hours of sunset (the sun's circle "
                          f"takes {2 * MAX_HOURS_FROM_SUNSET:g} h), got {shown(hours)}")


@dataclass(frozen=True)
class Sun:
    """The sun's daily track, as seen from the eye.

    Parameters
    ----------
    azimuth : float
        Direction of the setting sun U on the horizon, degrees from the view
        axis +y toward +x (0: the sun sets straight ahead).
    tilt : float
        Angle between the sun's great circle and the horizon, degrees, in
        (0, 90]; it is also the sun's highest elevation (at an equinox, 90°
        minus the latitude). The sun climbs on the −x side of U (it sets
        moving down and to the right, as seen in the northern hemisphere).
    radius : float
        δ, the sun's angular radius, degrees (the paper enlarged it to about
        0.75°; the true value is about 0.27°).
    """

    azimuth: float = 0.0
    tilt: float = 45.0
    radius: float = SUN_PAPER_RADIUS_DEGREES

    def __post_init__(self):
        require_scalars(self)
        require_range("azimuth", self.azimuth, -MAX_DEGREES, MAX_DEGREES, "degrees")
        require_finite("tilt", self.tilt)
        if not 0.0 < self.tilt <= 90.0:
            raise SunsetError(f"tilt must be in (0, 90] degrees, got {self.tilt!r}")
        require_positive("radius", self.radius)
        if self.radius < MIN_SUN_RADIUS:
            raise SunsetError(f"radius must be at least {MIN_SUN_RADIUS:g} degrees, got {self.radius!r}")
        if self.radius >= 10.0:
            raise SunsetError(f"radius must be below 10 degrees, got {self.radius!r}")

    @property
    def delta(self) -> float:
        """δ in radians."""
        return math.radians(self.radius)

    @property
    def U(self) -> np.ndarray:
        """Unit vector to the setting sun (on the horizon)."""
        a = math.radians(self.azimuth)
        return np.array([math.sin(a), math.cos(a), 0.0])

    @property
    def V(self) -> np.ndarray:
        """Unit vector to the sun at its highest, perpendicular to U."""
        a = math.radians(self.azimuth)
        t = math.radians(self.tilt)
        side = np.array([-math.cos(a), math.sin(a), 0.0])  # horizontal, 90° from U
        return math.cos(t) * side + math.sin(t) * np.array([0.0, 0.0, 1.0])

    @property
    def W(self) -> np.ndarray:
        """W = U × V, the unit normal of the plane of C."""
        return np.cross(self.U, self.V)

    @staticmethod
    def theta(hours) -> np.ndarray:
        """θ = 2π/24 × hours before sunset, radians."""
        require_finite("hours", hours)
        return np.asarray(hours, dtype=float) * RADIANS_PER_HOUR

    def position(self, hours) -> np.ndarray:
        """P(θ) = U cos θ + V sin θ for ``hours`` before sunset.

        Shape ``shape(hours) + (3,)``.
        """
        th = self.theta(hours)[..., None]
        return self.U * np.cos(th) + self.V * np.sin(th)

    def elevation(self, hours) -> np.ndarray:
        """The sun's elevation above the horizon, radians."""
        return np.arcsin(np.clip(self.position(hours)[..., 2], -1.0, 1.0))
