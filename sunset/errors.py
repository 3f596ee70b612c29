"""Errors a user can act on, and the checks that raise them.

Every error meant for a user (a bad scene file, a negative size, a NaN
parameter) is a :class:`SunsetError`; the command line prints its message as a
single line and exits with status 2, with no traceback.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: The longest echo of a user's value (or path) in an error message, characters.
MAX_SHOWN = 80


class SunsetError(ValueError):
    """An error in what the user asked for, with a message that names it."""


def shown(value: Any) -> str:
    """``value`` as an error message shows it: one line, at most :data:`MAX_SHOWN` characters.

    A path or a string is shown as itself when it is printable and as its
    ``repr`` otherwise (so a newline in a file name cannot break the one-line
    message); anything else by ``repr``. Long texts are cut in the middle.
    """
    import os

    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if isinstance(value, bytes):
        value = os.fsdecode(value)
    if isinstance(value, str):
        from .escape import terminal_text

        text = terminal_text(value)
    else:
        text = repr(value)
    if len(text) > MAX_SHOWN:
        half = (MAX_SHOWN - 5) // 2
        text = f"{text[:half]} ... {text[-half:]}"
    return text


def require_finite(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless every element of ``value`` is finite."""
    try:
        arr = np.asarray(value, dtype=float)
    except OverflowError:
        raise SunsetError(f"{name} must be a finite number, got {shown(value)}") from None
    if not np.all(np.isfinite(arr)):
        raise SunsetError(f"{name} must be a finite number, got {shown(value)}")


def require_positive(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and > 0."""
    require_finite(name, value)
    if not np.all(np.asarray(value, dtype=float) > 0):
        raise SunsetError(f"{name} must be positive, got {shown(value)}")


def require_nonnegative(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and >= 0."""
    require_finite(name, value)
    if not np.all(np.asarray(value, dtype=float) >= 0):
        raise SunsetError(f"{name} must not be negative, got {shown(value)}")


def require_int_range(name: str, value: Any, lo: int, hi: int | None = None) -> None:
    """Raise :class:`SunsetError` unless ``value`` is an integer in [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise SunsetError(f"{name} must be an integer, got {shown(value)}")
    if value < lo or (hi is not None and value > hi):
        span = f">= {lo}" if hi is None else f"in {lo}..{hi}"
        raise SunsetError(f"{name} must be {span}, got {shown(value)}")



def require_range(name: str, value: Any, lo: float, hi: float, unit: str = "", lo_open: bool = False) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and lo <= value <= hi (lo < value if ``lo_open``).

    The physical range of a scene field: the message names the field, the
    range and the unit.
    """
    require_finite(name, value)
    v = float(value)
    if v < lo or v > hi or (lo_open and v == lo):
        unit = f" {unit}" if unit else ""
        left = "(" if lo_open else "["
        raise SunsetError(f"{name} must be in {left}{lo:g}, {hi:g}]{unit}, got {shown(value)}")
