"""Islands: elliptical paraboloids with cosine hills (paper eqs. 3 and 4).

Heights in this module's data are metres above mean sea level; the camera
puts mean sea level at z = −h.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .errors import SunsetError, require_finite, require_nonnegative, require_positive


@dataclass(frozen=True)
class Cosine:
    """One rolling-hill term a cos(ℓx + my) of eq. 4.

    amplitude in metres (>= 0); l, m in rad m⁻¹.
    """

    amplitude: float
    l: float
    m: float

    def __post_init__(self):
        require_nonnegative("amplitude", self.amplitude)
        require_finite("l", self.l)
        require_finite("m", self.m)


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
        require_finite("height", self.height)
        require_positive("e", self.e)
        require_finite("f", self.f)
        require_positive("g", self.g)
        if not self.f * self.f < 4.0 * self.e * self.g:
            raise SunsetError(f"f must satisfy f² < 4·e·g (an elliptical paraboloid), got e={self.e!r}, f={self.f!r}, g={self.g!r}")


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
        object.__setattr__(self, "cosines", tuple(self.cosines))
        require_finite("x", self.x)
        require_finite("y", self.y)
        if not self.y > 0:
            raise SunsetError(f"y must be positive: the island is behind the eye (y = {self.y!r})")
        require_finite("cliff_top", self.cliff_top)
        if not self.cliff_top < self.cliff.height:
            raise SunsetError(f"cliff_top must be below the cliff paraboloid's apex {self.cliff.height!r}, got {self.cliff_top!r}")
        require_positive("hill_factor", self.hill_factor)
        if self.hill_factor > 1:
            raise SunsetError(f"hill_factor must be in (0, 1], got {self.hill_factor!r}")

    @property
    def max_perturbation(self) -> float:
        """d_k = Σ_j a_jk, the most the cosine terms can add, metres."""
        return float(sum(c.amplitude for c in self.cosines))
