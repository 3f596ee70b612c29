"""Errors a user can act on, and the checks that raise them.

Every error meant for a user (a bad scene file, a negative size, a NaN
parameter) is a :class:`SunsetError`; the command line prints its message as a
single line and exits with status 2, with no traceback.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class SunsetError(ValueError):
    """An error in what the user asked for, with a message that names it."""


def require_finite(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless every element of ``value`` is finite."""
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise SunsetError(f"{name} must be a finite number, got {value!r}")


def require_positive(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and > 0."""
    require_finite(name, value)
    if not np.all(np.asarray(value, dtype=float) > 0):
        raise SunsetError(f"{name} must be positive, got {value!r}")


def require_nonnegative(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and >= 0."""
    require_finite(name, value)
    if not np.all(np.asarray(value, dtype=float) >= 0):
        raise SunsetError(f"{name} must not be negative, got {value!r}")


def require_int_range(name: str, value: Any, lo: int, hi: int | None = None) -> None:
    """Raise :class:`SunsetError` unless ``value`` is an integer in [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise SunsetError(f"{name} must be an integer, got {value!r}")
    if value < lo or (hi is not None and value > hi):
        span = f">= {lo}" if hi is None else f"in {lo}..{hi}"
        raise SunsetError(f"{name} must be {span}, got {value!r}")

