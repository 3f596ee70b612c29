"""Writing files safely: atomically, deterministically, all or nothing.

Every file the package writes goes through :func:`atomic_write`: the bytes go
to a temporary file beside the target (``.sunset-<pid>-<random>.part<suffix>``),
which is flushed to disk and renamed over the target only when complete and
checked, so an error, a full disk or an interrupt never leaves a half-written
file and never destroys a good older one. Inside :func:`all_or_nothing` the
renames wait until every output of the command is complete: a command that
fails leaves no new file at all. A temporary file that a killed process left
behind (SIGKILL cannot be caught) is removed by the next write into that
folder.

The checks made before any work: :func:`check_writable` (a path that can be
created: not empty, not too long, its folder searchable and writable, not a
device, FIFO or folder) and :func:`check_distinct` (no two outputs of a
command, and no output and input, are the same file, also through symbolic or
hard links).
"""

from __future__ import annotations

import contextlib
import contextvars
import io
import os
import stat
import tempfile
import time
from pathlib import Path

import numpy as np

from .errors import SunsetError, shown
from .guard import check_stop as _check_stop

#: The name endings of the files this package writes, by kind.
PNG_SUFFIXES = (".png",)

#: Temporary files: ``.sunset-<pid>-<random>.part<suffix>`` beside the target.
_TEMP_PREFIX = ".sunset-"
_TEMP_MARK = ".part"

#: A temporary file whose process is gone is removed once it is this old, seconds.
_STALE_SECONDS = 60.0

_pending: contextvars.ContextVar[list | None] = contextvars.ContextVar("sunset_pending_outputs", default=None)



def _cannot(path, exc: OSError, verb: str = "write") -> SunsetError:
    return SunsetError(f"{shown(path)}: cannot {verb} ({exc.strerror or exc})")


def _name_max(folder: Path) -> int:
    try:
        return int(os.pathconf(folder, "PC_NAME_MAX"))
    except (OSError, ValueError):
        return 255


def check_writable(path: str | os.PathLike | None, suffixes: tuple[str, ...] = ()) -> Path:
    """Raise :class:`SunsetError` unless ``path`` can be created or replaced (and ends in one of ``suffixes``).

    Refused: an empty path, a wrong suffix, a name longer than the file
    system allows, a folder that does not exist or cannot be searched or
    written, and an existing target that is not a regular file (a folder, a
    device such as ``/dev/null``, a FIFO or a socket: replacing it by a
    rename would destroy it).
    """
    if isinstance(path, (str, os.PathLike)) and isinstance(os.fspath(path), str):
        pass
    else:
        raise SunsetError(f"the output path must be a path (text or a path object), got {shown(path)}")
    if not str(path).strip():
        raise SunsetError("the output path is empty")
    path = Path(path)
    if suffixes and path.suffix.lower() not in suffixes:
        raise SunsetError(f"output {shown(repr(str(path)))} must end in {' or '.join(suffixes)}")
    parent = path.parent if str(path.parent) else Path(".")
    try:
        if len(os.fsencode(str(path))) >= 4096:
            raise SunsetError(f"{shown(path)}: the path is too long")
        most = _name_max(parent) if parent.is_dir() else 255
        if len(os.fsencode(path.name)) > most:
            raise SunsetError(f"{shown(path)}: the file name is too long ({len(os.fsencode(path.name))} bytes, "
                              f"at most {most})")
        if path.is_dir():
            raise SunsetError(f"{shown(path)}: is a directory, not an output file")
        if not parent.is_dir():
            raise SunsetError(f"{shown(path)}: cannot write: directory {shown(parent)} does not exist")
        if os.path.lexists(path):
            try:
                mode = os.stat(path).st_mode
            except FileNotFoundError:       # a dangling symbolic link: the rename replaces the link
                mode = stat.S_IFREG
            if not stat.S_ISREG(mode):
                raise SunsetError(f"{shown(path)}: not a regular file (a device, a pipe or a socket): "
                                  f"refusing to replace it")
        if not os.access(parent, os.W_OK | os.X_OK):
            raise SunsetError(f"{shown(path)}: cannot write: directory {shown(parent)} is not writable")
    except OSError as exc:
        raise _cannot(path, exc) from None
    return path


def _identity(path) -> tuple:
    """What makes two paths the same file: (device, inode) if it exists, else (folder's device, inode, name)."""
    try:
        st = os.stat(path)
        return ("file", st.st_dev, st.st_ino)
    except OSError:
        pass
    p = Path(os.path.abspath(path))
    try:
        st = os.stat(p.parent)
        return ("new", st.st_dev, st.st_ino, p.name)
    except OSError:
        return ("path", str(p))


def check_distinct(outputs: dict[str, object], inputs: dict[str, object] | None = None) -> None:
    """Raise :class:`SunsetError` when two outputs, or an output and an input, are the same file.

    ``outputs`` and ``inputs`` map what the user calls each path (an option
    such as ``--tape``) to the path, or to None when not given. Sameness is
    decided by the file system (device and inode), so symbolic links and hard
    links are seen through; an output that does not exist yet is the same as
    another when both name one entry of one folder.
    """
    seen: list[tuple[str, tuple, bool]] = []
    for role, items in (("output", outputs), ("input", inputs or {})):
        for label, path in items.items():
            if path is None:
                continue
            ident = _identity(path)
            for other_label, other_ident, other_is_out in seen:
                if ident == other_ident:
                    what = "both outputs" if role == "output" and other_is_out else "an output and an input"
                    raise SunsetError(f"{other_label} and {label} are the same file ({shown(path)}): "
                                      f"{what} cannot share a file")
            seen.append((label, ident, role == "output"))


def _target(path: Path) -> Path:
    """Where the bytes for ``path`` go: through a symbolic link to the file it names."""
    if os.path.islink(path) and os.path.exists(path):
        return Path(os.path.realpath(path))
    return path


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:                          # someone else's process
        return True
    return True


def remove_stale_temporaries(folder: str | os.PathLike) -> list[Path]:
    """Remove this package's temporary files in ``folder`` whose writing process is gone; returns them.

    A process killed by SIGKILL cannot clean up; its ``.sunset-<pid>-…``
    files are removed here once the process no longer exists and the file
    has not changed for a minute.
    """
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        name = entry.name
        if not name.startswith(_TEMP_PREFIX) or _TEMP_MARK not in name:
            continue
        pid_text = name[len(_TEMP_PREFIX):].split("-", 1)[0]
        if not pid_text.isdigit() or _alive(int(pid_text)):
            continue
        try:
            st = entry.stat(follow_symlinks=False)
            if st.st_uid != os.getuid() or now - st.st_mtime <= _STALE_SECONDS:
                continue
            if stat.S_ISREG(st.st_mode):
                os.unlink(entry.path)
                removed.append(Path(entry.path))
            elif stat.S_ISDIR(st.st_mode):          # a folder of outputs staged together (sunset figures)
                import shutil

                shutil.rmtree(entry.path)
                removed.append(Path(entry.path))
        except OSError:
            continue
    return removed


def check_stop() -> None:
    """Raise the stop signal's exception if one was noted (:func:`sunset.guard.note_stop`): no output lands after it."""
    _check_stop()


def land_in(files, folder: str | os.PathLike) -> list[Path]:
    """Move complete ``files`` into ``folder`` under their own names (through symbolic links), in order.

    The files are flushed to disk first; each rename replaces its target at
    once. Used to land a staged set of outputs together (:func:`sunset.figures.make_figures`).
    """
    targets = [_target(Path(folder) / Path(f).name) for f in files]
    for f in files:
        _fsync(f)
    done = 0
    try:
        for f, target in zip(files, targets):
            os.replace(f, target)
            done += 1
    except OSError as exc:
        raise _cannot(targets[done], exc) from None
    return targets


def _fsync(path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _unlink(path) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, suffix: str | None = None):
    """Yield a temporary path beside ``path``; move it onto ``path`` when the body succeeds.

    The temporary file keeps the target's suffix (writers that choose a
    format by extension, such as imageio, still work). When the body
    returns, the file is flushed to disk (a full disk is found here at the
    latest) and renamed over the target, or, inside :func:`all_or_nothing`,
    when every output of the command is complete. If the body raises, or is
    interrupted, the temporary file is removed and the target is untouched.
    A symbolic link to a regular file is written through (the link stays).
    """
    path = check_writable(path)
    target = _target(path)
    remove_stale_temporaries(target.parent)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f"{_TEMP_PREFIX}{os.getpid()}-", suffix=_TEMP_MARK + (suffix or path.suffix),
                                   dir=target.parent)
        os.close(fd)
    except OSError as exc:
        raise _cannot(path, exc) from None
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o644)
        _fsync(tmp)
        _check_stop()
        pending = _pending.get()
        if pending is not None:
            pending.append((tmp, target))
        else:
            os.replace(tmp, target)
    except BaseException:
        _unlink(tmp)
        raise


@contextlib.contextmanager
def all_or_nothing():
    """Every :func:`atomic_write` inside the block lands together when it ends, or none does.

    The outputs stay under their temporary names until the block ends
    without an error; then they are renamed onto their targets in the order
    they were written. If the block raises (a failed encoder, a full disk,
    Ctrl-C), every temporary file is removed and no target is touched. Nested
    blocks join the outermost one.
    """
    if _pending.get() is not None:
        yield
        return
    pending: list[tuple[str, Path]] = []
    token = _pending.set(pending)
    try:
        yield
    except BaseException:
        for tmp, _ in pending:
            _unlink(tmp)
        raise
    finally:
        _pending.reset(token)
    done = 0
    try:
        _check_stop()
        for tmp, target in pending:
            os.replace(tmp, target)
            done += 1
    except BaseException as exc:
        for tmp, _ in pending[done:]:
            _unlink(tmp)
        if isinstance(exc, OSError):
            raise _cannot(pending[done][1], exc) from None
        raise


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically; every write is checked (a full disk is an error, not a short file)."""
    try:
        with atomic_write(path) as tmp:
            with open(tmp, "wb") as fh:
                written = fh.write(data)
            if written != len(data) or os.path.getsize(tmp) != len(data):
                raise OSError(0, f"short write ({os.path.getsize(tmp)} of {len(data)} bytes)")
    except OSError as exc:
        raise _cannot(path, exc) from None


def png_bytes(rgb: np.ndarray, metadata: dict[str, str] | None = None) -> bytes:
    """Encode an (H, W, 3) or (H, W) uint8 image as PNG with text metadata.

    Every PNG records what made it: ``Software`` and ``sunset:provenance``
    (the versions of :func:`sunset.provenance.provenance`) are added to
    ``metadata`` unless it has them (:func:`sunset.provenance.stamped`). The
    encoding is deterministic: no timestamp chunk, keys in the given order.
    """
    from PIL import Image, PngImagePlugin

    from .provenance import stamped

    arr = np.ascontiguousarray(rgb)
    if arr.dtype != np.uint8:
        raise TypeError(f"expected a uint8 image, got {arr.dtype}")
    info = PngImagePlugin.PngInfo()
    for key, value in stamped(metadata).items():    # values as sunset.escape.metadata_text writes them
        info.add_itxt(key, value)
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

    A figure with a layout engine (``layout="constrained"``) is laid out once,
    here, at ``dpi``, and then drawn once: ``savefig`` alone would draw it
    twice (a first draw with the rendering switched off, only to run the
    layout: every artist visited and every image resampled for nothing). The
    layout it runs is the same, at the same dpi, so the file is the same bytes
    (``tests/test_io.py`` compares the two); the figure gets its layout engine
    and dpi back afterwards.
    """
    from .provenance import stamped

    check_writable(path, PNG_SUFFIXES)
    buf = io.BytesIO()
    engine = fig.get_layout_engine()
    if engine is None:
        fig.savefig(buf, format="png", dpi=dpi, metadata=stamped())
    else:
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        old_dpi, old_canvas = fig.dpi, fig.canvas
        try:
            fig.dpi = dpi
            FigureCanvasAgg(fig)                 # the renderer the layout measures text with, at ``dpi``
            engine.execute(fig)
            fig.set_layout_engine(None)          # laid out: savefig draws once
            fig.savefig(buf, format="png", dpi=dpi, metadata=stamped())
        finally:
            fig.set_layout_engine(engine)
            fig.set_canvas(old_canvas)
            fig.dpi = old_dpi
    write_bytes(path, buf.getvalue())
    return Path(path)
