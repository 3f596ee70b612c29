"""The tape: the 8-bit frames of one wave cycle, with what made them.

The Cray wrote one magnetic tape per film sequence: the codes of every frame
of one cycle of the periodic wave motion, which the film recorder then read
again and again through changing colour tables. A :class:`Tape` is that
tape, plus what a reader needs to reproduce it: the scene (as TOML), the
times, the reflection mode, the dither seed and the package version.

File format (version 2)
-----------------------
All integers little-endian::

    offset        size   content
    0             8      magic b"SUNTAPE\\x1a"
    8             4      format version (uint32), 2
    12            8      header length L (uint64), at most MAX_TAPE_HEADER_BYTES
    20            L      header: UTF-8 JSON, keys sorted, no whitespace
    20 + L        N·H·W  the codes, uint8, frame by frame, row by row
    20 + L + NHW  32     SHA-256 of every byte before it

The header holds ``frames``, ``height``, ``width``, ``times`` (seconds, as
JSON numbers, which round-trip float64 exactly), ``reflections``, ``seed``,
``scene`` (the scene's TOML text: never a path), ``sunset_version`` and
``provenance`` (the versions of sunset, Python, NumPy, Numba and
colour-science that wrote it; readers ignore it).
The checksum covers the whole file, header included: one flipped bit
anywhere is found. There is no timestamp: the same tape gives the same bytes.
A tape is read as a stream, with its size checked against the header before
the codes are read, so a damaged or hostile tape never costs more memory than
its codes (at most MAX_TAPE_BYTES).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..constants import MAX_TAPE_BYTES, MAX_TAPE_HEADER_BYTES, TAPE_FORMAT_VERSION
from ..errors import SunsetError, require_int_range, require_time, shown

__all__ = ["Tape", "MAGIC", "tape_bytes", "parse_tape", "read_tape_stream", "write_tape", "read_tape"]

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
        Dither seed of the codes (:func:`sunset.tape.codes.dither`).
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
        require_time("times", times)
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


_DIGEST_SIZE = 32
_CHUNK = 1 << 24


def _header(tape: Tape) -> dict:
    n, h, w = tape.codes.shape
    return {
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


def _head_bytes(tape: Tape) -> bytes:
    header = json.dumps(_header(tape), sort_keys=True, separators=(",", ":"), ensure_ascii=False,
                        allow_nan=False).encode("utf-8")
    return _PREFIX.pack(MAGIC, TAPE_FORMAT_VERSION, len(header)) + header


def tape_bytes(tape: Tape) -> bytes:
    """The tape file's bytes (format version 2); the same tape gives the same bytes."""
    body = _head_bytes(tape) + tape.codes.tobytes()
    return body + hashlib.sha256(body).digest()


def _read_exactly(fh, count: int, name: str, what: str) -> bytes:
    data = fh.read(count)
    if len(data) != count:
        raise SunsetError(f"{name}: truncated tape ({what})")
    return data


#: The keys of a header, every one required but ``provenance``.
_HEADER_KEYS = frozenset({"frames", "height", "width", "times", "reflections", "seed", "scene", "sunset_version",
                          "provenance"})


def _times(value, frames: int) -> np.ndarray:
    """The header's ``times``: a flat list of exactly ``frames`` finite JSON numbers, as strictly as the checksum.

    Not a number nested in a list, not text, not a truth value, not a list of
    another length (NumPy would read ``[[0.5]]``, ``["0.5"]`` or ``[true]``).
    """
    if not isinstance(value, list):
        raise SunsetError(f"times must be a list of {frames} numbers, got {shown(value)}")
    if len(value) != frames:
        raise SunsetError(f"times must hold one number per frame ({frames}), got {len(value)}")
    for k, t in enumerate(value):
        if isinstance(t, bool) or not isinstance(t, (int, float)):
            raise SunsetError(f"times[{k}] must be a finite number, got {shown(t)}")
        require_time(f"times[{k}]", t)             # finite, within the sea's clock (an int past float64 too)
    return np.array(value, dtype=np.float64)


def _header_fields(head, name: str):
    from ..model.scene import scene_from_text

    if not isinstance(head, dict):
        raise SunsetError(f"{name}: damaged tape header (not a JSON object)")
    try:
        unknown = sorted(set(head) - _HEADER_KEYS)
        if unknown:
            raise SunsetError(f"unknown key {shown(unknown[0])} (a version {TAPE_FORMAT_VERSION} header holds "
                              f"{', '.join(sorted(_HEADER_KEYS))})")
        dims = [head["frames"], head["height"], head["width"]]
        for key, v in zip(("frames", "height", "width"), dims):
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise SunsetError(f"{key} must be a positive integer, got {shown(v)}")
        n, h, w = dims
        if n * h * w > MAX_TAPE_BYTES:           # before the times, whose list would be as long as n
            raise SunsetError(f"{shown(n)} frames of {shown(w)}x{shown(h)} is more than the "
                              f"{MAX_TAPE_BYTES / 2**30:g} GiB a tape may hold")
        if not isinstance(head["scene"], str):
            raise SunsetError("scene must be TOML text")
        times = _times(head["times"], n)
        reflections, seed = head["reflections"], head["seed"]
        for key, v in (("reflections", reflections), ("seed", seed)):
            if isinstance(v, bool) or not isinstance(v, int):
                raise SunsetError(f"{key} must be an integer, got {shown(v)}")
        version = head["sunset_version"]
        if not isinstance(version, str):
            raise SunsetError(f"sunset_version must be text, got {shown(version)}")
        made_by = head.get("provenance", {})
        if not isinstance(made_by, dict) or not all(isinstance(v, str) for v in made_by.values()):
            raise SunsetError(f"provenance must be a table of texts, got {shown(made_by)}")
    except SunsetError as exc:
        raise SunsetError(f"{name}: damaged tape header ({exc})") from None
    except (ValueError, KeyError, TypeError, OverflowError) as exc:
        raise SunsetError(f"{name}: damaged tape header ({type(exc).__name__}: {shown(str(exc))})") from None
    return dims, head["scene"], times, reflections, seed, version, made_by, scene_from_text


def read_tape_stream(fh, name: str = "tape", size: int | None = None) -> Tape:
    """Read a tape from a binary stream of ``size`` bytes; ``name`` (a path) starts every error message.

    The prefix and the header are read first and checked (the header's
    length, its JSON, its dimensions against the file's size and against
    MAX_TAPE_BYTES); then the codes are read into their array in chunks while
    the checksum of the whole file is computed, and compared with the one at
    its end.
    """
    prefix = fh.read(_PREFIX.size)
    if len(prefix) < _PREFIX.size or prefix[:8] != MAGIC:
        if len(prefix) < _PREFIX.size and MAGIC.startswith(prefix[:8]):
            raise SunsetError(f"{name}: truncated tape ({len(prefix)} bytes, shorter than its "
                              f"{_PREFIX.size}-byte prefix)")
        raise SunsetError(f"{name}: not a sunset tape (bad magic bytes)")
    _, version, hlen = _PREFIX.unpack(prefix)
    if version != TAPE_FORMAT_VERSION:
        raise SunsetError(f"{name}: tape format version {version} is not supported "
                          f"(this sunset reads version {TAPE_FORMAT_VERSION}; render the tape again)")
    if hlen > MAX_TAPE_HEADER_BYTES:
        raise SunsetError(f"{name}: damaged tape header ({hlen} bytes, at most {MAX_TAPE_HEADER_BYTES})")
    if size is not None and size < _PREFIX.size + hlen:
        raise SunsetError(f"{name}: truncated tape (header of {hlen} bytes, file has {size - _PREFIX.size})")
    raw = _read_exactly(fh, hlen, name, f"header of {hlen} bytes")
    digest = hashlib.sha256(prefix)
    digest.update(raw)
    try:
        head = json.loads(raw.decode("utf-8"))
    except RecursionError:
        raise SunsetError(f"{name}: damaged tape header (nested too deep)") from None
    except (ValueError, UnicodeDecodeError) as exc:
        raise SunsetError(f"{name}: damaged tape header ({type(exc).__name__}: {shown(str(exc))})") from None
    (n, h, w), scene_text, times, reflections, seed, version, made_by, scene_from_text = \
        _header_fields(head, name)
    count = n * h * w
    if count > MAX_TAPE_BYTES:
        raise SunsetError(f"{name}: damaged tape ({n} frames of {w}x{h} is more than the "
                          f"{MAX_TAPE_BYTES / 2**30:g} GiB a tape may hold)")
    if size is not None:
        expected = _PREFIX.size + hlen + count + _DIGEST_SIZE
        if size < expected:
            raise SunsetError(f"{name}: truncated tape (expected {count} bytes of codes and a "
                              f"{_DIGEST_SIZE}-byte checksum, found {size - _PREFIX.size - hlen})")
        if size > expected:
            raise SunsetError(f"{name}: damaged tape ({size - expected} bytes after the codes)")
    codes = np.empty(count, dtype=np.uint8)
    view = memoryview(codes)
    done = 0
    while done < count:
        got = fh.readinto(view[done:done + _CHUNK])
        if not got:
            raise SunsetError(f"{name}: truncated tape (expected {count} bytes of codes, found {done})")
        digest.update(view[done:done + got])
        done += got
    stored = fh.read(_DIGEST_SIZE + 1)
    if len(stored) < _DIGEST_SIZE:
        raise SunsetError(f"{name}: truncated tape (its checksum is cut off)")
    if len(stored) > _DIGEST_SIZE:
        raise SunsetError(f"{name}: damaged tape (bytes after the codes)")
    if digest.digest() != stored:
        raise SunsetError(f"{name}: damaged tape (the file does not match its checksum)")
    try:
        scene = scene_from_text(scene_text)
        return Tape(scene=scene, codes=codes.reshape(n, h, w), times=times, reflections=reflections, seed=seed,
                    version=version, provenance={str(k): str(v) for k, v in made_by.items()})
    except SunsetError as exc:
        raise SunsetError(f"{name}: damaged tape ({exc})") from None


def parse_tape(data: bytes, name: str = "tape") -> Tape:
    """Read a tape from its bytes; ``name`` (a path) starts every error message."""
    return read_tape_stream(io.BytesIO(data), name, len(data))


def write_tape(path: str | os.PathLike, tape: Tape) -> Path:
    """Write ``tape`` to ``path`` atomically (temporary file, then rename), every write checked."""
    from ..io import atomic_write, _cannot

    head = _head_bytes(tape)
    digest = hashlib.sha256(head)
    codes = memoryview(tape.codes.reshape(-1))
    try:
        with atomic_write(path) as tmp, open(tmp, "wb") as fh:
            fh.write(head)
            for i in range(0, len(codes), _CHUNK):
                digest.update(codes[i:i + _CHUNK])
                fh.write(codes[i:i + _CHUNK])
            fh.write(digest.digest())
            fh.flush()
            expected = len(head) + len(codes) + _DIGEST_SIZE
            if os.fstat(fh.fileno()).st_size != expected:
                raise OSError(0, "short write")
    except OSError as exc:
        raise _cannot(path, exc) from None
    return Path(path)


def read_tape(path: str | os.PathLike) -> Tape:
    """Read a tape file; any problem raises :class:`SunsetError` naming the file."""
    path = Path(path)
    name = shown(path)
    try:
        if path.exists() and not path.is_dir() and not path.is_file():
            raise SunsetError(f"{name}: not a regular file (a device or a pipe), not a tape file")
        with open(path, "rb") as fh:
            return read_tape_stream(fh, name, os.fstat(fh.fileno()).st_size)
    except FileNotFoundError:
        raise SunsetError(f"{name}: no such tape file") from None
    except IsADirectoryError:
        raise SunsetError(f"{name}: is a directory, not a tape file") from None
    except OSError as exc:
        raise SunsetError(f"{name}: cannot read tape ({exc.strerror or exc})") from None
