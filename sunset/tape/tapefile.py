"""The tape: the 8-bit frames of one wave cycle, with what made them.

The Cray wrote one magnetic tape per film sequence: the codes of every frame
of one cycle of the periodic wave motion, which the film recorder then read
again and again through changing colour tables. A :class:`Tape` is that
tape, plus what a reader needs to reproduce it: the scene (as TOML), the
times, the reflection mode, the dither seed and the package version.

File format (version 1)
-----------------------
All integers little-endian::

    offset  size  content
    0       8     magic b"SUNTAPE\\x1a"
    8       4     format version (uint32), 1
    12      8     header length L (uint64)
    20      L     header: UTF-8 JSON, keys sorted, no whitespace
    20 + L  N·H·W the codes, uint8, frame by frame, row by row

The header holds ``frames``, ``height``, ``width``, ``times`` (seconds, as
JSON numbers, which round-trip float64 exactly), ``reflections``, ``seed``,
``scene`` (TOML text), ``sunset_version``, ``provenance`` (the versions of
sunset, Python, NumPy, Numba and colour-science that wrote it; readers
ignore it, and tapes without it read as before) and ``codes_sha256`` (a
checksum of the codes). There is no timestamp: the same tape gives the same
bytes.
"""

from __future__ import annotations

import hashlib
import json
import os
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..constants import TAPE_FORMAT_VERSION
from ..errors import SunsetError, require_finite, require_int_range

__all__ = ["Tape", "MAGIC", "tape_bytes", "parse_tape", "write_tape", "read_tape"]

#: The first eight bytes of every tape file.
MAGIC = b"SUNTAPE\x1a"

_PREFIX = struct.Struct("<8sIQ")


@dataclass(frozen=True, eq=False, repr=False)
class Tape:
    """The codes of a sequence of frames and how they were made.

    Attributes
    ----------
    scene : Scene
    codes : ndarray (N, H, W) uint8
        One frame of codes per time.
    times : ndarray (N,) float64
        Time of each frame, seconds.
    reflections : int
        Reflection mode the frames were rendered with (0, 1 or 2).
    seed : int
        Dither seed of :func:`sunset.tape.codes.encode`.
    version : str
        The sunset version that made the tape.
    provenance : dict
        The versions of what made it (:func:`sunset.provenance.provenance`;
        those of this session when None; empty for a tape written without it).
    """

    scene: object
    codes: np.ndarray
    times: np.ndarray
    reflections: int = 2
    seed: int = 0
    version: str = ""
    provenance: dict | None = None

    def __post_init__(self):
        from .. import __version__

        codes = np.ascontiguousarray(self.codes)
        if codes.dtype != np.uint8 or codes.ndim != 3:
            raise SunsetError(f"codes must be a uint8 array (frames, height, width), got {codes.dtype} {codes.shape}")
        cam = self.scene.camera
        if codes.shape[1:] != (cam.height, cam.width):
            raise SunsetError(f"codes frames {codes.shape[1:]} do not match the scene's camera "
                              f"{(cam.height, cam.width)}")
        times = np.asarray(self.times, dtype=np.float64).reshape(-1)
        if times.shape != (codes.shape[0],):
            raise SunsetError(f"times must have one entry per frame ({codes.shape[0]}), got {times.shape[0]}")
        require_finite("times", times)
        require_int_range("reflections", self.reflections, 0, 2)
        require_int_range("seed", self.seed, 0, 2**32 - 1)
        object.__setattr__(self, "codes", codes)
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "version", self.version or __version__)
        if self.provenance is None:
            from ..provenance import provenance

            object.__setattr__(self, "provenance", provenance())

    def __repr__(self) -> str:
        n, h, w = self.codes.shape
        return (f"Tape({n} frame{'s' * (n != 1)} of {w}×{h}, t {self.times[0]:g}–{self.times[-1]:g} s, "
                f"reflections={self.reflections}, seed={self.seed}, sunset {self.version})")

    def __len__(self) -> int:
        return int(self.codes.shape[0])

    @property
    def frames(self) -> int:
        """Number of frames N."""
        return len(self)

    def same_as(self, other: "Tape") -> bool:
        """True when both tapes hold the same codes, times, scene and settings."""
        return (self.scene == other.scene and self.reflections == other.reflections and self.seed == other.seed
                and self.version == other.version and np.array_equal(self.times, other.times)
                and self.codes.shape == other.codes.shape and np.array_equal(self.codes, other.codes))


def _header(tape: Tape) -> dict:
    n, h, w = tape.codes.shape
    return {
        "codes_sha256": hashlib.sha256(tape.codes.tobytes()).hexdigest(),
        "frames": n,
        "height": h,
        "reflections": int(tape.reflections),
        "scene": tape.scene.to_toml(),
        "seed": int(tape.seed),
        "sunset_version": tape.version,
        "provenance": dict(tape.provenance),
        "times": [float(t) for t in tape.times],
        "width": w,
    }


def tape_bytes(tape: Tape) -> bytes:
    """The tape file's bytes (format version 1); the same tape gives the same bytes."""
    header = json.dumps(_header(tape), sort_keys=True, separators=(",", ":"), ensure_ascii=False,
                        allow_nan=False).encode("utf-8")
    return _PREFIX.pack(MAGIC, TAPE_FORMAT_VERSION, len(header)) + header + tape.codes.tobytes()


def parse_tape(data: bytes, name: str = "tape") -> Tape:
    """Read a tape from its bytes; ``name`` (a path) starts every error message."""
    from ..model.scene import Scene

    if len(data) < _PREFIX.size or data[:8] != MAGIC:
        if len(data) < _PREFIX.size and MAGIC.startswith(data[:8]):
            raise SunsetError(f"{name}: truncated tape ({len(data)} bytes, shorter than its {_PREFIX.size}-byte prefix)")
        raise SunsetError(f"{name}: not a sunset tape (bad magic bytes)")
    _, version, hlen = _PREFIX.unpack_from(data)
    if version != TAPE_FORMAT_VERSION:
        raise SunsetError(f"{name}: tape format version {version} is not supported "
                          f"(this sunset reads version {TAPE_FORMAT_VERSION})")
    start = _PREFIX.size + hlen
    if len(data) < start:
        raise SunsetError(f"{name}: truncated tape (header of {hlen} bytes, file has {len(data) - _PREFIX.size})")
    try:
        head = json.loads(data[_PREFIX.size:start].decode("utf-8"))
        n, h, w = int(head["frames"]), int(head["height"]), int(head["width"])
        scene = Scene.from_toml(head["scene"])
        times = np.array(head["times"], dtype=np.float64)
        reflections, seed = int(head["reflections"]), int(head["seed"])
        version, digest = str(head["sunset_version"]), str(head["codes_sha256"])
        made_by = head.get("provenance", {})
        if not isinstance(made_by, dict):
            raise TypeError(f"provenance must be a table, got {made_by!r}")
    except SunsetError as exc:
        raise SunsetError(f"{name}: damaged tape header ({exc})") from None
    except (ValueError, KeyError, TypeError, UnicodeDecodeError) as exc:
        raise SunsetError(f"{name}: damaged tape header ({type(exc).__name__}: {exc})") from None
    size = n * h * w
    payload = data[start:]
    if len(payload) < size:
        raise SunsetError(f"{name}: truncated tape (expected {size} bytes of codes, found {len(payload)})")
    if len(payload) > size:
        raise SunsetError(f"{name}: damaged tape ({len(payload) - size} bytes after the codes)")
    if hashlib.sha256(payload).hexdigest() != digest:
        raise SunsetError(f"{name}: damaged tape (the codes do not match their checksum)")
    codes = np.frombuffer(payload, dtype=np.uint8).reshape(n, h, w).copy()
    try:
        return Tape(scene=scene, codes=codes, times=times, reflections=reflections, seed=seed, version=version,
                    provenance={str(k): str(v) for k, v in made_by.items()})
    except SunsetError as exc:
        raise SunsetError(f"{name}: damaged tape ({exc})") from None


def write_tape(path: str | os.PathLike, tape: Tape) -> Path:
    """Write ``tape`` to ``path`` atomically (temporary file, then rename)."""
    from ..io import write_bytes

    write_bytes(path, tape_bytes(tape))
    return Path(path)


def read_tape(path: str | os.PathLike) -> Tape:
    """Read a tape file; any problem raises :class:`SunsetError` naming the file."""
    path = Path(path)
    try:
        if path.exists() and not path.is_dir() and not path.is_file():
            raise SunsetError(f"{path}: not a regular file (a device or a pipe), not a tape file")
        data = path.read_bytes()
    except FileNotFoundError:
        raise SunsetError(f"{path}: no such tape file") from None
    except IsADirectoryError:
        raise SunsetError(f"{path}: is a directory, not a tape file") from None
    except OSError as exc:
        raise SunsetError(f"{path}: cannot read tape ({exc.strerror or exc})") from None
    return parse_tape(data, str(path))
