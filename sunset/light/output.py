"""Writing RGB frames: 8- or 16-bit sRGB PNG for looking, float32 .npy for grading.

* ``.png``, ``depth=8``: the display image, sRGB-encoded, 8 bits per channel.
* ``.png``, ``depth=16``: the same image with 16 bits per channel (no banding
  when it is graded further). Pillow writes no 16-bit RGB PNG, so this
  module writes one itself (PNG specification, ISO/IEC 15948: signature,
  IHDR with bit depth 16 and colour type 2, one zlib stream of scan lines
  each led by filter byte 0, IEND; big-endian samples); deterministic, no
  time chunk.
* ``.npy``: float32 (H, W, 3) *scene-referred* linear sRGB, exposed for the
  hour but before the eye's response: values above 1 are kept (the sun, its
  glitter), for people who tone-map and grade the image themselves.
"""

from __future__ import annotations

import io
import os
import struct
import zlib
from pathlib import Path

import numpy as np

from ..errors import SunsetError
from ..io import check_writable, save_png, write_bytes
from .tone import encode_srgb

__all__ = ["RGB_SUFFIXES", "png16_bytes", "to_uint8", "to_uint16", "save_rgb", "check_rgb_output"]

#: The name endings ``--shading rgb`` writes.
RGB_SUFFIXES = (".png", ".npy")


def to_uint8(display_linear) -> np.ndarray:
    """Linear display RGB in [0, 1] → sRGB bytes."""
    return np.clip(np.rint(encode_srgb(display_linear) * 255.0), 0, 255).astype(np.uint8)


def to_uint16(display_linear) -> np.ndarray:
    """Linear display RGB in [0, 1] → 16-bit sRGB-encoded values."""
    return np.clip(np.rint(encode_srgb(display_linear) * 65535.0), 0, 65535).astype(np.uint16)


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png16_bytes(rgb16: np.ndarray, metadata: dict[str, str] | None = None) -> bytes:
    """Encode an (H, W, 3) uint16 image as a 16-bit RGB PNG (with tEXt metadata and the provenance).

    As every PNG of the package, it records what made it: ``metadata`` with
    ``Software`` and ``sunset:provenance`` added unless given
    (:func:`sunset.provenance.stamped`).
    """
    from ..provenance import stamped

    arr = np.asarray(rgb16)
    if arr.dtype != np.uint16 or arr.ndim != 3 or arr.shape[2] != 3:
        raise TypeError(f"expected an (H, W, 3) uint16 image, got {arr.dtype} {arr.shape}")
    h, w = arr.shape[:2]
    rows = np.ascontiguousarray(arr.astype(">u2")).view(np.uint8).reshape(h, w * 6)   # big-endian samples
    raw = np.concatenate([np.zeros((h, 1), np.uint8), rows], axis=1).tobytes()     # filter type 0 per row
    out = [b"\x89PNG\r\n\x1a\n", _chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 2, 0, 0, 0))]
    for key, value in stamped(metadata).items():
        out.append(_chunk(b"tEXt", key.encode("latin-1") + b"\x00" + str(value).encode("latin-1", "replace")))
    out.append(_chunk(b"IDAT", zlib.compress(raw, 6)))
    out.append(_chunk(b"IEND", b""))
    return b"".join(out)


def check_rgb_output(path, depth: int = 8) -> Path:
    """Check an output path for the RGB back end before any work (suffix, directory, depth)."""
    path = check_writable(path, RGB_SUFFIXES)
    if depth not in (8, 16):
        raise SunsetError(f"depth must be 8 or 16 bits, got {depth!r}")
    if depth == 16 and path.suffix.lower() != ".png":
        raise SunsetError("depth 16 applies to PNG output; .npy output is float32")
    return path


def save_rgb(path: str | os.PathLike, display, scene_linear=None, depth: int = 8,
             metadata: dict[str, str] | None = None) -> Path:
    """Write a frame by ``path``'s suffix (module docstring), atomically.

    Parameters
    ----------
    display : ndarray (H, W, 3)
        Linear display RGB in [0, 1] (for PNG).
    scene_linear : ndarray (H, W, 3), optional
        Exposed scene-referred linear sRGB (for .npy; required there).
    """
    path = check_rgb_output(path, depth)
    if path.suffix.lower() == ".npy":
        if scene_linear is None:
            raise SunsetError(".npy output needs the scene-referred frame")
        buf = io.BytesIO()
        np.save(buf, np.ascontiguousarray(scene_linear, np.float32), allow_pickle=False)
        write_bytes(path, buf.getvalue())
        return path
    if depth == 16:
        write_bytes(path, png16_bytes(to_uint16(display), metadata))
        return path
    return save_png(path, to_uint8(display), metadata)
