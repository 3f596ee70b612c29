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


def terminal_text(text) -> str:
    """``text`` for one line of a terminal: itself when printable, else its ``repr`` (escapes shown, in quotes).

    No escape sequence (colours, the cursor, the window's title), no
    bidirectional override, no line break reaches the terminal;
    :func:`shown` (every value an error message echoes) uses it; :mod:`sunset.escape` lists it
    with the other formats' functions.
    """
    if isinstance(text, bytes):
        text = text.decode("utf-8", "surrogateescape")
    text = str(text)
    return text if text.isprintable() else repr(text)


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
        text = terminal_text(value)
    elif isinstance(value, int) and abs(value).bit_length() > 4000:   # repr would raise past 4300 digits
        text = f"an integer of {abs(value).bit_length()} bits"
    else:
        try:
            text = " ".join(repr(value).split())       # one line: NumPy writes its arrays on several
        except Exception:                    # a hostile object's own __repr__
            text = f"a {type(value).__name__}"
    if len(text) > MAX_SHOWN:
        half = (MAX_SHOWN - 5) // 2
        text = f"{text[:half]} ... {text[-half:]}"
    return text


def typed(value: Any) -> str:
    """``value`` as :func:`shown` shows it, with its type: ``6 (str)``, so that text is not read as a number."""
    return f"{shown(value)} ({shown(type(value).__name__)})"


#: What a number may not be, although NumPy would read it as one: text, a truth value, nothing.
_NOT_NUMBERS = (str, bytes, bytearray, bool, np.bool_, type(None), complex, np.complexfloating)


def real_array(name: str, value: Any) -> np.ndarray:
    """``value`` as a float64 array: a real number or an array (nested sequence) of them, else :class:`SunsetError`.

    Text (``"0.5"``, which NumPy would read), truth values, None, complex
    numbers, ragged or object arrays, and integers beyond float64's range are
    refused with one line naming ``name``; NaN and infinities are not
    checked here (see :func:`require_finite`).
    """
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf":     # the common case, at once
        return value.astype(float, copy=False)

    def bad():                              # made only when refused: the repr of a large array is slow
        return SunsetError(f"{name} must be a number (or an array of numbers), got {typed(value)}")

    if isinstance(value, _NOT_NUMBERS):
        raise bad()
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError, OverflowError, RecursionError):
        raise bad() from None
    if arr.dtype.kind == "O":               # Fractions, integers beyond 64 bits, or anything at all
        flat = arr.ravel().tolist()
        if any(isinstance(v, _NOT_NUMBERS) or not hasattr(v, "__float__") for v in flat):
            raise bad()
        try:
            arr = np.array([float(v) for v in flat], dtype=float).reshape(arr.shape)
        except (OverflowError, TypeError, ValueError):
            raise SunsetError(f"{name} must be a finite number, got {shown(value)}") from None
    elif arr.dtype.kind not in "iuf":
        raise bad()
    return arr.astype(float, copy=False)


def real_number(name: str, value: Any) -> float:
    """``value`` as one finite float (a real number, or an array of one element's shape ()), else :class:`SunsetError`."""
    arr = real_array(name, value)
    if arr.ndim != 0:
        raise SunsetError(f"{name} must be a single number, got an array of shape {arr.shape}")
    v = float(arr)
    if not np.isfinite(v):
        raise SunsetError(f"{name} must be a finite number, got {shown(value)}")
    return v


def require_finite(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is a real number, or an array of them, every element finite."""
    if not np.all(np.isfinite(real_array(name, value))):
        raise SunsetError(f"{name} must be a finite number, got {shown(value)}")


def require_positive(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and > 0."""
    require_finite(name, value)
    if not np.all(real_array(name, value) > 0):
        raise SunsetError(f"{name} must be positive, got {shown(value)}")


def require_nonnegative(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and >= 0."""
    require_finite(name, value)
    if not np.all(real_array(name, value) >= 0):
        raise SunsetError(f"{name} must not be negative, got {shown(value)}")


def require_length(name: str, value: Any, lo: float, hi: float, zero: bool = False, unit: str = "m") -> None:
    """Raise :class:`SunsetError` unless ``value`` is one length in [lo, hi] (or exactly 0 when ``zero``).

    Every length has a physical minimum ``lo`` > 0, not only a positive one:
    a denormal radius or semi-axis passes ``> 0`` and then overflows the
    arithmetic that divides by it.
    """
    v = real_number(name, value)
    if zero and v == 0.0:
        return
    if not lo <= v <= hi:
        either = "0 or " if zero else ""
        raise SunsetError(f"{name} must be {either}in [{lo:g}, {hi:g}] {unit}, got {shown(value)}")


def require_int_range(name: str, value: Any, lo: int, hi: int | None = None) -> None:
    """Raise :class:`SunsetError` unless ``value`` is an integer in [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise SunsetError(f"{name} must be an integer, got {typed(value)}")
    if value < lo or (hi is not None and value > hi):
        span = f">= {lo}" if hi is None else f"in {lo}..{hi}"
        raise SunsetError(f"{name} must be {span}, got {shown(value)}")



def require_time(name: str, value: Any, nan: bool = False) -> np.ndarray:
    """``value`` as times in seconds, each finite and within ±MAX_TIME (sunset.constants); else SunsetError.

    A number or an array (checked element by element); ``nan=True`` lets NaN
    through (the sea's functions answer NaN with NaN). Returns the float64 array.
    """
    from .constants import MAX_TIME

    arr = real_array(name, value)
    if not np.all(np.isfinite(arr) | (np.isnan(arr) if nan else False)):
        raise SunsetError(f"{name} must be a finite number, got {shown(value)}")
    if np.any(np.abs(arr) > MAX_TIME):
        raise SunsetError(f"{name} must be a time within ±{MAX_TIME:g} s, got {shown(value)}")
    return arr


def require_range(name: str, value: Any, lo: float, hi: float, unit: str = "", lo_open: bool = False) -> None:
    """Raise :class:`SunsetError` unless ``value`` is finite and lo <= value <= hi (lo < value if ``lo_open``).

    The physical range of a scene field: the message names the field, the
    range and the unit.
    """
    v = real_number(name, value)
    if v < lo or v > hi or (lo_open and v == lo):
        unit = f" {unit}" if unit else ""
        left = "(" if lo_open else "["
        raise SunsetError(f"{name} must be in {left}{lo:g}, {hi:g}]{unit}, got {shown(value)}")


def require_bool(name: str, value: Any) -> None:
    """Raise :class:`SunsetError` unless ``value`` is True or False (not ``'no'``, not None, not 1)."""
    if not isinstance(value, (bool, np.bool_)):
        raise SunsetError(f"{name} must be True or False, got {typed(value)}")


def require_instance(name: str, value: Any, kind: type, what: str | None = None) -> None:
    """Raise :class:`SunsetError` unless ``value`` is a ``kind`` (named ``what`` in the message)."""
    if not isinstance(value, kind):
        raise SunsetError(f"{name} must be a {what or kind.__name__}, got {typed(value)}")


def require_items(name: str, value: Any, kind: type, most: int | None = None) -> tuple:
    """``value`` as a tuple of ``kind`` (a list or tuple of them, at most ``most``), else :class:`SunsetError`."""
    if not isinstance(value, (list, tuple)):
        raise SunsetError(f"{name} must be a list of {kind.__name__}, got {typed(value)}")
    if most is not None and len(value) > most:
        raise SunsetError(f"{name} must hold at most {most} entries, got {len(value)}")
    for k, item in enumerate(value):
        if not isinstance(item, kind):
            raise SunsetError(f"{name}[{k}] must be a {kind.__name__}, got {typed(item)}")
    return tuple(value)


def require_text(name: str, value: Any, most: int | None = None) -> None:
    """Raise :class:`SunsetError` unless ``value`` is text of at most ``most`` printable characters.

    Printable as Python's ``str.isprintable``: letters, marks, digits,
    punctuation, symbols and the space, in any script; no control
    character (line breaks, tabs, escapes, NUL), no format character
    (bidirectional overrides, zero-width joiners), no surrogate (a byte that
    was not UTF-8), no private-use or unassigned code point, no line or
    paragraph separator. What a scene's text fields hold
    (:func:`sunset.model.scene.check_text`).
    """
    if not isinstance(value, str):
        raise SunsetError(f"{name} must be text, got {shown(value)}")
    if most is not None and len(value) > most:
        raise SunsetError(f"{name} must be at most {most} characters, got {len(value)}")
    bad = next((ch for ch in value if not ch.isprintable()), None)
    if bad is not None:
        raise SunsetError(f"{name} must hold printable characters only (no line break, control or format character), "
                          f"got {shown(bad)} (U+{ord(bad):04X}) at {value.index(bad)}")


def require_scalars(obj: Any) -> None:
    """Raise :class:`SunsetError` unless every ``float`` field of the dataclass ``obj`` is one finite number,
    and every ``int`` field one integer.

    The model's dataclasses call it first in ``__post_init__``, so that an
    array, a text or an integer past float64 in a scalar field is one line
    naming the field, before any comparison that would raise another error.
    """
    import dataclasses

    for f in dataclasses.fields(obj):
        kind = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "")
        value = getattr(obj, f.name)
        if kind == "float":
            real_number(f.name, value)
        elif kind == "int":                 # the field's own range is checked next, on a number it can compare
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
                raise SunsetError(f"{f.name} must be an integer, got {typed(value)}")
            if abs(int(value)) > 1 << 62:
                raise SunsetError(f"{f.name} must be an integer of at most 62 bits, got {shown(value)}")


def require_size(name: str, size: Any) -> tuple[int, int]:
    """``size`` as (width, height): a pair of whole numbers >= 1, else :class:`SunsetError` (their most is the camera's)."""
    if isinstance(size, (str, bytes)) or not isinstance(size, (tuple, list)) or len(size) != 2:
        raise SunsetError(f"{name} must be (width, height), got {shown(size)}")
    for what, v in zip(("width", "height"), size):
        require_int_range(f"{name} {what}", v, 1)
    return int(size[0]), int(size[1])
