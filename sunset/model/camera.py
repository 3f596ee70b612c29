"""The eye, the picture plane y = 1 and its pixels.

Coordinates throughout the package: the eye at the origin, looking along +y,
x to the right, z up; the picture plane is y = 1 and mean sea level is the
plane z = −h. A point (x, y, z) projects to (s, ζ) = (x/y, z/y) on the picture
plane; the vertical scan line at s holds the projections of the plane x = s·y.
Pixel columns are scan lines; row 0 is the top of the picture.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..constants import (MAX_EYE_HEIGHT, MAX_PIXELS, MAX_WINDOW_SLOPE, MIN_EYE_HEIGHT, MIN_WINDOW_SPAN, PAPER_HEIGHT,
                         PAPER_SIGMA, PAPER_WIDTH, SIGMA_MAX, SIGMA_MIN)
from ..errors import require_scalars, SunsetError, require_finite, require_int_range, require_positive, require_range


@dataclass(frozen=True)
class Camera:
    """The eye and its picture window.

    Parameters
    ----------
    eye_height : float
        h, height of the eye above mean sea level, metres (> 0).
    width, height : int
        Picture size in pixels: ``width`` scan lines of ``height`` pixels.
    s_min, s_max : float
        The window's left and right edges on the picture plane, s = x/y.
    zy_min, zy_max : float
        The window's bottom and top edges on the picture plane, ζ = z/y.
    sigma : float
        σ, the projected spacing of height-field samples on the mean sea
        plane, in pixels (the paper: 1/4).
    """

    eye_height: float = 2.0
    width: int = PAPER_WIDTH
    height: int = PAPER_HEIGHT
    s_min: float = -0.5
    s_max: float = 0.5
    zy_min: float = -0.35
    zy_max: float = 0.15
    sigma: float = PAPER_SIGMA

    def __post_init__(self):
        require_scalars(self)
        require_positive("eye_height", self.eye_height)
        require_int_range("width", self.width, 1)
        require_int_range("height", self.height, 1)
        for name in ("s_min", "s_max", "zy_min", "zy_max"):
            require_range(name, getattr(self, name), -MAX_WINDOW_SLOPE, MAX_WINDOW_SLOPE)
        if not self.s_max - self.s_min >= MIN_WINDOW_SPAN:
            raise SunsetError(f"s_max must be greater than s_min by at least {MIN_WINDOW_SPAN:g}, got "
                              f"{self.s_min!r} .. {self.s_max!r}")
        if not self.zy_max - self.zy_min >= MIN_WINDOW_SPAN:
            raise SunsetError(f"zy_max must be greater than zy_min by at least {MIN_WINDOW_SPAN:g}, got "
                              f"{self.zy_min!r} .. {self.zy_max!r}")
        require_positive("sigma", self.sigma)
        if not SIGMA_MIN <= self.sigma <= SIGMA_MAX:
            raise SunsetError(f"sigma must be in {SIGMA_MIN:g}..{SIGMA_MAX:g} pixels (the sample spacing), "
                              f"got {self.sigma!r}")
        if self.eye_height < MIN_EYE_HEIGHT:
            raise SunsetError(f"eye_height must be at least {MIN_EYE_HEIGHT:g} m, got {self.eye_height!r}")
        if self.eye_height > MAX_EYE_HEIGHT:
            raise SunsetError(f"eye_height must be at most {MAX_EYE_HEIGHT:g} m (the sea is flat, the Earth "
                              f"is not), got {self.eye_height!r}")
        if self.width * self.height > MAX_PIXELS:
            raise SunsetError(f"width × height must be at most {MAX_PIXELS:,} pixels, "
                              f"got {self.width} × {self.height}")

    def with_size(self, width: int, height: int) -> "Camera":
        """The same window at another pixel size."""
        return replace(self, width=width, height=height)

    @property
    def pixel_pitch(self) -> tuple[float, float]:
        """(Δs, Δζ): the size of one pixel on the picture plane."""
        return ((self.s_max - self.s_min) / self.width, (self.zy_max - self.zy_min) / self.height)

    def s_centres(self) -> np.ndarray:
        """s = x/y at the centre of each column (scan line), shape (width,)."""
        ds = (self.s_max - self.s_min) / self.width
        return self.s_min + (np.arange(self.width) + 0.5) * ds

    def zy_centres(self) -> np.ndarray:
        """ζ = z/y at the centre of each row, shape (height,), row 0 at the top."""
        dz = (self.zy_max - self.zy_min) / self.height
        return self.zy_max - (np.arange(self.height) + 0.5) * dz

    def horizon_row(self) -> float:
        """Fractional row of the horizon ζ = 0 (the sea's vanishing line)."""
        return self.zy_max / ((self.zy_max - self.zy_min) / self.height) - 0.5

    def sea_y(self) -> np.ndarray:
        """Where each row's ray meets mean sea level, y in metres, shape (height,).

        The plane z = −h projects to ζ = −h/y, so the ray through a row
        centre ζ < 0 meets still water at y = −h/ζ, on every scan line (the
        distance is measured along the view axis, not along the ray). Rows
        at or above the horizon ζ = 0 never meet it: ``inf``.
        """
        z = self.zy_centres()
        out = np.full(z.shape, np.inf)
        below = z < 0
        out[below] = -self.eye_height / z[below]
        return out

    def directions(self) -> np.ndarray:
        """Unit rays through the pixel centres, shape (height, width, 3)."""
        s = self.s_centres()[None, :]
        z = self.zy_centres()[:, None]
        s, z = np.broadcast_arrays(s, z)
        d = np.stack([s, np.ones_like(s), z], axis=-1)
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def project(self, x, y, z):
        """Project points to the picture plane: (s, ζ) = (x/y, z/y)."""
        y = np.asarray(y, dtype=float)
        return np.asarray(x) / y, np.asarray(z) / y

    def to_pixel(self, s, zy):
        """Picture-plane (s, ζ) to fractional (column, row); pixel centres at integers."""
        ds, dz = self.pixel_pitch
        return (np.asarray(s) - self.s_min) / ds - 0.5, (self.zy_max - np.asarray(zy)) / dz - 0.5

    @property
    def field_of_view(self) -> tuple[float, float]:
        """Horizontal and vertical angles of view through the centre, degrees."""
        return (math.degrees(math.atan(self.s_max) - math.atan(self.s_min)),
                math.degrees(math.atan(self.zy_max) - math.atan(self.zy_min)))
