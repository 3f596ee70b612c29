"""The player's data document read back: its codes, its tables and a frame composed as ``player.js`` draws it.

:func:`compose` is the reference of the data format (:mod:`sunset.recorder.player` writes it): it must equal
:func:`sunset.expose` on the same codes and hour. Every function checks the document first
(:func:`check_data`): a damaged or hostile one is a :class:`~sunset.errors.SunsetError`.
"""

from __future__ import annotations

import base64
import io

import numpy as np

from ..errors import SunsetError, require_int_range, shown

__all__ = ["check_data", "decode_codes", "data_tables", "compose"]


def check_data(data, *keys) -> dict:
    """Raise :class:`SunsetError` unless ``data`` is a player's data document with ``keys`` of their types."""
    if not isinstance(data, dict):
        raise SunsetError(f"data must be a player's data document (a dict), got {shown(data)}")
    for key in keys:
        kind = _DATA_TYPES[key]
        if key not in data or isinstance(data[key], bool) or not isinstance(data[key], kind):
            raise SunsetError(f"player data: {key} must be {kind.__name__ if isinstance(kind, type) else 'a number'}, "
                              f"got {shown(data.get(key))}")
    return data


#: The types of the data document's fields that the functions below read.
_DATA_TYPES = {"title": str, "codes": list, "tables": str, "hours": list, "sun": list, "supersample": int,
               "sky_start": int, "decode": list, "encode": list, "width": int, "height": int}


def decode_codes(data: dict) -> np.ndarray:
    """The codes of every frame, (N, H, W) uint8, decoded from the data's PNGs."""
    import binascii

    from PIL import Image, UnidentifiedImageError

    check_data(data, "codes", "width", "height")
    frames = []
    try:
        for b64 in data["codes"]:
            with Image.open(io.BytesIO(base64.b64decode(b64, validate=True))) as img:
                if img.mode != "L" or img.size != (data["width"], data["height"]):
                    raise SunsetError(f"player codes must be 8-bit greyscale PNGs of {data['width']}x{data['height']}, "
                                      f"got mode {img.mode}, {img.size[0]}x{img.size[1]}")
                frames.append(np.asarray(img, dtype=np.uint8))
    except (binascii.Error, TypeError, ValueError, UnidentifiedImageError, OSError) as exc:
        raise SunsetError(f"player data: damaged codes ({shown(str(exc))})") from None
    if not frames:
        raise SunsetError("player data: no codes")
    return np.stack(frames)


def data_tables(data: dict) -> np.ndarray:
    """The tables of every grid hour, (M, 3, 256) uint8."""
    import binascii

    check_data(data, "tables", "hours")
    try:
        raw = np.frombuffer(base64.b64decode(data["tables"], validate=True), dtype=np.uint8)
        return raw.reshape(len(data["hours"]), 3, 256)
    except (binascii.Error, ValueError) as exc:
        raise SunsetError(f"player data: damaged tables ({shown(str(exc))})") from None


def compose(data: dict, frame: int, hour: int,
            codes: np.ndarray | None = None) -> np.ndarray:
    """What ``player.js`` draws for a frame and a grid hour (an index), in NumPy.

    Returns (H, W, 3) uint8.

    Table lookup in each pass, then the sun's disk from the exported
    coverage, mixed in linear light and rounded through the exported
    thresholds. The reference of the data format: it must equal
    :func:`sunset.expose` on the same codes and hour.
    """
    check_data(data, "sun", "supersample", "sky_start", "decode", "encode",
               "width", "height")
    tables = data_tables(data)
    require_int_range("hour", hour, 0, len(tables) - 1)
    if codes is None:
        frames = decode_codes(data)
        require_int_range("frame", frame, 0, len(frames) - 1)
        codes = frames[frame]
    else:
        require_int_range("frame", frame, 0)
        shape = (data["height"], data["width"])
        if (not isinstance(codes, np.ndarray) or codes.dtype != np.uint8
                or codes.shape != shape):
            raise SunsetError(f"codes must be a uint8 array {shape}, "
                              f"got {shown(codes)}")
    if len(data["sun"]) != len(tables):
        raise SunsetError("player data: sun must hold one entry per hour")
    tab = tables[hour]
    rgb = np.stack([tab[k][codes] for k in range(3)], axis=-1)
    s = data["sun"][hour]
    if s is not None:
        rows = slice(s["r0"], s["r0"] + s["h"])
        cols = slice(s["c0"], s["c0"] + s["w"])
        k = np.asarray(s["cover"], dtype=np.int64).reshape(s["h"], s["w"])
        n2 = data["supersample"] ** 2
        use = (k > 0) & (codes[rows, cols] >= data["sky_start"])
        w = (k / n2)[..., None]
        box = np.asarray(data["decode"])[rgb[rows, cols]]
        mixed = (1.0 - w) * box + w * np.asarray(s["colour"])
        byte = np.searchsorted(np.asarray(data["encode"]), mixed, side="right")
        byte = byte.astype(np.uint8)
        rgb[rows, cols] = np.where(use[..., None], byte, rgb[rows, cols])
    return rgb
