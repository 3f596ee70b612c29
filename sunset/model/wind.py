"""The wind over the sea: its speed at any height, and the friction velocity u*.

Wave spectra are fitted to the wind at different heights: Pierson and
Moskowitz (1964) to the wind at 19.5 m, JONSWAP (Hasselmann et al. 1973) and
Elfouhaily et al. (1997) to the wind at 10 m, Cox and Munk (1954) to the wind
at 12.5 m (41 ft, their anemometer's height). A wind given at one height is
carried to the others by the neutral logarithmic profile

    U(z) = (u*/κ) ln(z/z₀),    z₀ = α_c u*²/g + 0.11 ν/u*,

with von Kármán's κ = 0.40 and the sea's roughness length z₀ of Smith (1988):
Charnock's term with α_c = 0.011 (rough flow) plus the smooth-flow term with
the air's kinematic viscosity ν = 1.5·10⁻⁵ m² s⁻¹. Given U at one height the
friction velocity u* is the fixed point of u* = κU/ln(z/z₀(u*)), found by
iteration (a contraction: it converges to round-off in a few dozen steps).

At 10 m s⁻¹ the profile gives U(19.5)/U(10) ≈ 1.06 and U(12.5)/U(10) ≈ 1.02.
Stewart (2008, eq. 16.29) quotes U₁₉.₅ ≈ 1.026 U₁₀ for a drag coefficient of
1.3·10⁻³, but the log profile with that drag coefficient gives
1 + (√C_D/κ) ln 1.95 ≈ 1.060: we use the profile.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..constants import GRAVITY
from ..errors import require_range

#: von Kármán's constant κ (Smith 1988).
KARMAN = 0.40
#: Charnock's constant α_c of the rough-flow roughness length α_c u*²/g (Smith 1988).
CHARNOCK = 0.011
#: Kinematic viscosity of air ν, m² s⁻¹, in the smooth-flow roughness 0.11 ν/u*.
AIR_VISCOSITY = 1.5e-5
#: Heights of the wind the fits use, metres: JONSWAP and Elfouhaily et al., Cox and Munk, Pierson and Moskowitz.
HEIGHT_JONSWAP, HEIGHT_COX_MUNK, HEIGHT_PIERSON_MOSKOWITZ = 10.0, 12.5, 19.5
#: The range of wind speeds a wind sea accepts, m s⁻¹ (Cox and Munk measured 0–14; PM's fits reach 20).
MIN_WIND, MAX_WIND = 1.0, 25.0
#: The range of heights a wind may be given at, metres.
MIN_HEIGHT, MAX_HEIGHT = 1.0, 100.0


def roughness_length(u_star: float, gravity: float = GRAVITY) -> float:
    """z₀ = α_c u*²/g + 0.11 ν/u* (Smith 1988), metres."""
    return CHARNOCK * u_star * u_star / gravity + 0.11 * AIR_VISCOSITY / u_star


@dataclass(frozen=True)
class Wind:
    """A neutral wind over the sea, given by its speed at one height.

    Parameters
    ----------
    speed : float
        Wind speed U at ``height``, m s⁻¹, in [1, 25].
    height : float
        The height of ``speed`` above the mean sea level, metres, in [1, 100]
        (10 for U₁₀, 12.5 for Cox and Munk's wind, 19.5 for Pierson and Moskowitz's).
    gravity : float
        g, m s⁻² (in the Charnock term).
    """

    speed: float
    height: float = HEIGHT_JONSWAP
    gravity: float = GRAVITY

    def __post_init__(self):
        require_range("speed", self.speed, MIN_WIND, MAX_WIND, "m/s")
        require_range("height", self.height, MIN_HEIGHT, MAX_HEIGHT, "m")
        require_range("gravity", self.gravity, 0.0, 100.0, "m/s²", lo_open=True)

    @property
    def friction_velocity(self) -> float:
        """u*, m s⁻¹: the fixed point of u* = κU/ln(z/z₀(u*))."""
        u = KARMAN * self.speed / math.log(self.height / 1e-4)
        for _ in range(200):
            z0 = roughness_length(u, self.gravity)
            new = KARMAN * self.speed / math.log(self.height / z0)
            if abs(new - u) <= 1e-15 * new:
                return new
            u = new
        return u                      # pragma: no cover - it contracts fast

    @property
    def roughness(self) -> float:
        """z₀, metres, at this wind's u*."""
        return roughness_length(self.friction_velocity, self.gravity)

    def at(self, height: float) -> float:
        """U at another height, m s⁻¹: (u*/κ) ln(height/z₀)."""
        require_range("height", height, MIN_HEIGHT, MAX_HEIGHT, "m")
        return self.friction_velocity / KARMAN * math.log(height / self.roughness)

    @property
    def u10(self) -> float:
        """U₁₀, m s⁻¹ (JONSWAP, Elfouhaily et al.)."""
        return self.at(HEIGHT_JONSWAP)

    @property
    def u12_5(self) -> float:
        """U at 12.5 m, m s⁻¹ (Cox and Munk)."""
        return self.at(HEIGHT_COX_MUNK)

    @property
    def u19_5(self) -> float:
        """U₁₉.₅, m s⁻¹ (Pierson and Moskowitz)."""
        return self.at(HEIGHT_PIERSON_MOSKOWITZ)

    @property
    def drag_coefficient(self) -> float:
        """C_D = (u*/U₁₀)², dimensionless."""
        return (self.friction_velocity / self.u10) ** 2
