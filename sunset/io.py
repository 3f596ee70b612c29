"""Writing files safely: atomically, deterministically, with provenance.

Every file the package writes goes through :func:`atomic_write`: the bytes go
to a temporary file beside the target, which is renamed over the target only
when complete, so an error or an interrupt never leaves a half-written file.
"""

from __future__ import annotations

import contextlib
import io
import os
import tempfile
from pathlib import Path

import numpy as np

from .errors import SunsetError

#: The name endings of the files this package writes, by kind.
PNG_SUFFIXES = (".png",)


def check_writable(path: str | os.PathLike, suffixes: tuple[str, ...] = ()) -> Path:
    """Raise :class:`SunsetError` unless ``path`` can be created or replaced (and ends in one of ``suffixes``)."""
    if not str(path).strip():
        raise SunsetError("the output path is empty")
    path = Path(path)
    if suffixes and path.suffix.lower() not in suffixes:
        raise SunsetError(f"output {str(path)!r} must end in {' or '.join(suffixes)}")
    parent = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise SunsetError(f"{path}: is a directory, not an output file")
    if not parent.is_dir():
        raise SunsetError(f"{path}: cannot write: directory {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise SunsetError(f"{path}: cannot write: directory {parent} is not writable")
    return path


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, suffix: str | None = None):
    """Yield a temporary path beside ``path``; rename it onto ``path`` on success.

    The temporary file keeps the target's suffix (so writers that choose a
    format by extension, such as imageio, still work) and is removed if the
    body raises.
    """
    path = check_writable(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix or path.suffix, dir=path.parent or ".")
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically."""
    try:
        with atomic_write(path) as tmp:
            tmp.write_bytes(data)
    except OSError as exc:
        raise SunsetError(f"{path}: cannot write ({exc.strerror or exc})") from None


def png_bytes(rgb: np.ndarray, metadata: dict[str, str] | None = None) -> bytes:
    """Encode an (H, W, 3) or (H, W) uint8 image as PNG with text metadata.

    The encoding is deterministic: no timestamp chunk, keys in the given order.
    """
    from PIL import Image, PngImagePlugin

    arr = np.ascontiguousarray(rgb)
    if arr.dtype != np.uint8:
        raise TypeError(f"expected a uint8 image, got {arr.dtype}")
    info = PngImagePlugin.PngInfo()
    for key, value in (metadata or {}).items():
        info.add_itxt(key, str(value))
    buf = io.BytesIO()
    Image.fromarray(arr).save(buf, format="PNG", pnginfo=info, optimize=False, compress_level=6)
    return buf.getvalue()


def save_png(path: str | os.PathLike, rgb: np.ndarray, metadata: dict[str, str] | None = None) -> Path:
    """Write an image as PNG atomically, with text metadata (see :func:`png_bytes`)."""
    check_writable(path, PNG_SUFFIXES)
    write_bytes(path, png_bytes(rgb, metadata))
    return Path(path)


def save_matplotlib(fig, path: str | os.PathLike, dpi: int = 120) -> Path:
    """Save a matplotlib figure as PNG atomically and deterministically.

    Figures are made with ``matplotlib.figure.Figure`` rather than pyplot, so
    nothing global (the backend, pyplot's list of open figures) is touched and
    nothing needs closing. The PNG records the versions that made it
    (``sunset:provenance``, as every PNG of the package), and not matplotlib's
    own ``Software`` line.
    """
    from . import __version__
    from .provenance import provenance_json

    check_writable(path, PNG_SUFFIXES)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi,
                metadata={"Software": f"sunset {__version__}", "sunset:provenance": provenance_json()})
    write_bytes(path, buf.getvalue())
    return Path(path)
