"""The one switch between the NumPy reference kernels and their Numba twins.

Every hot step of the vector stage and of the coding is written twice. The
NumPy version is the reference: whole-array operations in the manner of the
Cray's vector loops, written for a reader, what the book shows and what the
tests hold the renderer to. Its twin, in a ``*_numba`` module beside it, is
the renderer: the same algorithm one element at a time with everything in
registers, with the C library's float64 functions and its own float32 sine
and cosine (:mod:`sunset.vector.sincos_numba`). The two are two arithmetic
paths, not one: they agree within the tolerances that chapter 10 measures
and the tests state (geometry to a few float32 roundings, the 8-bit codes
the same on all but a few pixels in a million), and each is
byte-deterministic on its own.

A stage marks its reference kernel with :func:`twin`; that is the only place
where the choice is made::

    @twin("sunset.vector.heightfield_numba")
    def sea_scan(u, g, zeta0, dzeta, n_pixels, best_u, best_surf) -> int:
        ...  # the NumPy reference

Calling ``sea_scan`` runs the function of the same name in the twin module
when the compiled kernels are on (:func:`enabled`), and the reference
otherwise. The twin modules import their stages, never the other way round,
and are loaded only when first used.

The compiled kernels are on when Numba can be imported and the environment
variable ``SUNSET_COMPILED`` is not ``0``; :func:`use_compiled` switches them
for a block of code (the tests run both paths).

Both cores inside one frame
---------------------------
The stages of a frame cut their work into strips (columns for the scan
lines, rows for everything after them) whose pixels do not depend on one
another, and :func:`run_strips` hands the strips to a small pool of threads.
The compiled kernels release the GIL and NumPy's whole-array operations do
too, so the threads run on all cores; every pixel is computed by the same
operations whichever strip it falls in, so the frame is byte-identical for
any number of threads (tests). The number of threads is ``$SUNSET_THREADS``,
else the CPUs this process may use, and never more than those;
:func:`use_threads` sets it for a block of code.
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import os
import threading

from .guard import env_count

env_count("NUMBA_NUM_THREADS")  # Numba's own check raises a ValueError at import (0), or ignores a word

try:  # pragma: no cover - exercised by whichever environment runs the tests
    import numba as _numba
except ImportError:  # pragma: no cover
    _numba = None

__all__ = ["AVAILABLE", "enabled", "use_compiled", "jit", "twin", "AGREE_DIRECTION", "AGREE_POINT", "AGREE_NORMAL", "AGREE_RAY",
           "AGREE_FINAL_NORMAL", "AGREE_GEOMETRY_SHARE", "AGREE_CODES", "threads", "use_threads", "strips",
           "row_strips", "run_strips", "keep_freed_memory"]

#: True when Numba is importable (the compiled kernels exist).
AVAILABLE = _numba is not None

def _default_threads() -> int:
    """``$SUNSET_THREADS``, else the usable CPUs; capped by them (:func:`sunset.guard.env_count`: a bad count raises)."""
    from .guard import usable_cpus

    return env_count("SUNSET_THREADS") or usable_cpus()


_state = {"on": AVAILABLE and os.environ.get("SUNSET_COMPILED", "1") != "0", "threads": None,
          "pool": None, "pool_size": 0}
_pool_lock = threading.Lock()


def enabled() -> bool:
    """Whether the renderer uses the compiled kernels now."""
    return _state["on"]


@contextlib.contextmanager
def use_compiled(flag: bool):
    """Use (True) or avoid (False) the compiled kernels inside a ``with`` block.

    Asking for them where Numba is missing leaves the NumPy path on.
    """
    old = _state["on"]
    _state["on"] = bool(flag) and AVAILABLE
    try:
        yield _state["on"]
    finally:
        _state["on"] = old


def _private_cache_dir() -> bool:
    """Point Numba's cache at a private folder in the temporary directory; False if there is none.

    Used when neither the package's folder nor the user's cache folder is
    writable (a read-only install run with no writable HOME). The folder must
    belong to this user and be closed to others: compiled code is loaded from
    it.
    """
    import stat
    import tempfile

    if _numba.config.CACHE_DIR:               # the user chose a folder (NUMBA_CACHE_DIR), and it failed
        return False
    path = os.path.join(tempfile.gettempdir(), f"sunset-numba-cache-{os.getuid()}")
    try:
        os.makedirs(path, mode=0o700, exist_ok=True)
        st = os.lstat(path)
    except OSError:
        return False
    if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid() or st.st_mode & 0o077:
        return False
    _numba.config.CACHE_DIR = path
    return True


def jit(fn):
    """Compile with NumPy's float semantics (x/0 gives ±inf or NaN, no exception), cached on disk.

    The cache goes beside the module, else in the user's cache folder (Numba's
    choice), else in a private folder in the temporary directory; where none
    is writable the kernels are compiled on every run, never refused.
    """
    if _numba is None:
        return fn
    options = {"nogil": True, "error_model": "numpy"}
    try:
        return _numba.njit(cache=True, **options)(fn)
    except RuntimeError:                      # "cannot cache function ...: no locator available"
        pass
    if _private_cache_dir():
        try:
            return _numba.njit(cache=True, **options)(fn)
        except RuntimeError:
            pass
    return _numba.njit(cache=False, **options)(fn)


def twin(module: str):
    """Mark a NumPy reference kernel whose Numba twin is the function of the same name in ``module``.

    Returns a decorator. The decorated function dispatches on :func:`enabled`
    at every call; the reference stays reachable as ``.reference`` and the
    twin as ``.compiled()`` (the tests compare the two).
    """
    def decorate(reference):
        name = reference.__name__

        def compiled():
            return getattr(importlib.import_module(module), name)

        @functools.wraps(reference)
        def kernel(*args, **kwargs):
            if _state["on"]:
                return _compiled_or_fall_back(reference, compiled, args, kwargs)
            _say_why_numpy()
            return reference(*args, **kwargs)

        kernel.reference = reference
        kernel.compiled = compiled
        return kernel
    return decorate


# --------------------------------------------------------------------------- how closely the two paths agree
# Measured over every packaged scene at 1024² (chapter 10, :mod:`sunset.bench.agreement`) and held by the
# tests. Geometry is compared where both paths' rays meet the same surfaces, relative for hit points and
# distances, absolute for unit vectors and cosines: the directions on every pixel, the other fields on all
# but a share 1 − AGREE_GEOMETRY_SHARE of the pixels (a ray that grazes a wave moves its hit by more than a
# rounding, and on short waves far away a hit moved by a rounding sees another slope).

# agreement-begin
#: The direct rays' unit directions: the same IEEE operations on both
#: paths, the same numbers (measured).
AGREE_DIRECTION = 0.0
#: Hit points and distances along the direct rays, relative.
AGREE_POINT = 4e-7
#: The unit normals of the direct hits.
AGREE_NORMAL = 4e-6
#: The reflected rays (after one or two bounces), and the rays leaving
#: the sea and their cosines of incidence.
AGREE_RAY = 2e-5
#: The unit normals of the islands where the reflected rays end.
AGREE_FINAL_NORMAL = 8e-4
#: The least share of a frame's compared pixels within the tolerances
#: of points, normals and rays.
AGREE_GEOMETRY_SHARE = 0.9999
#: The least share of a frame's pixels whose 8-bit code is the same on both paths.
AGREE_CODES = 0.9999
# agreement-end


# --------------------------------------------------------------------------- strips on threads
def threads() -> int:
    """How many threads a frame's stages use now (read from the environment on first use)."""
    if _state["threads"] is None:
        _state["threads"] = _default_threads()
    return _state["threads"]


@contextlib.contextmanager
def use_threads(n: int):
    """Run the frame's stages on ``n`` threads (1: in the calling thread alone) inside a ``with`` block."""
    old = _state["threads"]
    _state["threads"] = max(1, int(n))
    try:
        yield _state["threads"]
    finally:
        _state["threads"] = old


def strips(n_items: int, max_items: int | None = None, per_thread: int = 4) -> list[tuple[int, int]]:
    """Cut ``range(n_items)`` into contiguous (start, stop) strips for :func:`run_strips`.

    About ``per_thread`` strips per thread (so that a slow strip does not
    leave a core idle), none longer than ``max_items``; one strip when one
    thread runs.
    """
    if n_items <= 0:
        return []
    count = 1 if threads() == 1 else threads() * per_thread
    if max_items:
        count = max(count, -(-n_items // max(1, int(max_items))))
    count = min(count, n_items)
    edges = [n_items * i // count for i in range(count + 1)]
    return [(a, b) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def row_strips(height: int, width: int) -> list[tuple[int, int]]:
    """:func:`strips` of the rows of a picture, each at most ``STRIP_PIXELS`` pixels (and at least one row)."""
    from .constants import STRIP_PIXELS

    return strips(height, max(1, STRIP_PIXELS // max(1, width)))


def _pool():
    from concurrent.futures import ThreadPoolExecutor

    with _pool_lock:
        if _state["pool"] is None or _state["pool_size"] != threads():
            if _state["pool"] is not None:
                _state["pool"].shutdown(wait=True)
            _state["pool"] = ThreadPoolExecutor(max_workers=threads(), thread_name_prefix="sunset")
            _state["pool_size"] = threads()
        return _state["pool"]


def _forget_pool() -> None:  # a forked child has none of its parent's threads
    _state["pool"] = None
    _state["pool_size"] = 0


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


def run_strips(fn, parts) -> list:
    """``[fn(start, stop) for start, stop in parts]``, strips shared out to threads.

    Results in order.

    With one thread, or one strip, or when called from one of the pool's own
    threads, the strips run here, one after the other.
    """
    parts = list(parts)
    nested = threading.current_thread().name.startswith("sunset")
    if threads() == 1 or len(parts) <= 1 or nested:
        return [fn(a, b) for a, b in parts]
    pool = _pool()
    futures = [pool.submit(fn, a, b) for a, b in parts]
    return [f.result() for f in futures]


# --------------------------------------------------------------------------- the allocator
#: The largest block the C allocator keeps for reuse under :func:`keep_freed_memory`, bytes.
KEEP_BLOCK_BYTES = 1 << 30


def keep_freed_memory() -> bool:
    """Let the C library's allocator keep freed large blocks for the next frame; True where it was done.

    glibc hands every block over 32 MiB straight back to the system when it is
    freed, and the next frame's arrays of the same size are then faulted in
    again page by page, which on a virtual machine costs more than the
    arithmetic that fills them (a 2048 × 2048 frame's arrays are 48 MiB and
    more). Raising the allocator's mmap and trim thresholds
    (``mallopt(M_MMAP_THRESHOLD)``, ``mallopt(M_TRIM_THRESHOLD)``) to
    :data:`KEEP_BLOCK_BYTES` makes it reuse them instead: the results are the
    same bytes, the process keeps its peak memory until it exits. The
    ``sunset`` command and the benchmark call it when they start (a 1024²
    frame of the 8-bit path faulted about 3900 pages in per frame without
    it, 80 with it); ``SUNSET_KEEP_MEMORY=0`` turns it off. A no-op off glibc.
    """
    if os.environ.get("SUNSET_KEEP_MEMORY", "1") == "0":
        return False
    try:
        import ctypes

        libc = ctypes.CDLL("libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):       # pragma: no cover - not glibc
        return False
    m_trim_threshold, m_mmap_threshold = -1, -3
    return bool(mallopt(m_mmap_threshold, KEEP_BLOCK_BYTES)) and bool(mallopt(m_trim_threshold, KEEP_BLOCK_BYTES))


# --------------------------------------------------------------------------- which path ran: said, and recorded
__all__ += ["path", "fallbacks"]


def _shared_page():
    """A page shared with the processes this one forks later (a run's lanes and workers), so that what one of
    them says on stderr is said once per run and every output's provenance sees every fallback."""
    import mmap

    try:
        return mmap.mmap(-1, 1 << 14)
    except (OSError, ValueError):              # pragma: no cover - no anonymous shared memory: this process only
        return bytearray(1 << 14)


_record = _shared_page()           # byte 0: the NumPy path was announced; then "family\treason\n" entries
_record_lock = threading.Lock()
_fallen: dict[str, str] = {}       # this process's fallbacks (also where the shared page is full)


def _why_numpy() -> str | None:
    """Why the whole run takes the NumPy kernels (the environment's reason), or None."""
    if not AVAILABLE:
        return "numba missing"
    if os.environ.get("SUNSET_COMPILED", "1") == "0":
        return "SUNSET_COMPILED=0"
    return None


def _say(line: str) -> None:
    import sys

    print(f"sunset: {line}", file=sys.stderr, flush=True)


def _say_why_numpy() -> None:
    """Where Numba is missing, say once per run that the NumPy kernels run (``SUNSET_COMPILED=0``, the user's
    own choice, and a test's :func:`use_compiled` say nothing; both are recorded by :func:`path`)."""
    if _record[0] or AVAILABLE:
        return
    with _record_lock:
        if not _record[0]:
            _record[0] = 1
            _say("Numba is not installed: the NumPy kernels run (the same pictures within the tests' tolerances, "
                 "several times slower)")


def fallbacks() -> dict[str, str]:
    """The kernel families (``light.kernel``, ...) whose compiled kernels failed in this run, and why."""
    if not _record[1] and not _fallen:
        return {}
    text = bytes(_record[1:]).split(b"\0", 1)[0].decode("utf-8", "replace")
    return {**dict(line.split("\t", 1) for line in text.splitlines() if "\t" in line), **_fallen}


def _fall_back(family: str, exc: BaseException) -> None:
    """Record that ``family`` runs its NumPy kernels from now on, and say so once per run."""
    reason = f"compilation failed: {type(exc).__name__}"
    with _record_lock:
        if family in fallbacks():
            return
        end = 1 + bytes(_record[1:]).find(b"\0")
        entry = f"{family}\t{reason}\n".encode()
        if 0 < end and end + len(entry) < len(_record):
            _record[end:end + len(entry)] = entry
        _fallen[family] = reason
    _say(f"the compiled kernels of {family} could not be compiled ({type(exc).__name__}: "
         f"{str(exc).strip().splitlines()[0][:120] if str(exc).strip() else 'no message'}); "
         "their NumPy kernels run instead, more slowly")


def _family(reference) -> str:
    return reference.__module__.removeprefix("sunset.")


def _compiled_or_fall_back(reference, compiled, args, kwargs):
    """The twin's result; where it cannot be loaded or compiled, the reference's, said and recorded once."""
    family = _family(reference)
    if not (_record[1] or _fallen) or family not in fallbacks():
        try:
            fn = compiled()
            return fn(*args, **kwargs)
        except ImportError as exc:
            _fall_back(family, exc)
        except Exception as exc:        # Numba's compile errors; a kernel's own errors pass on unchanged
            if _numba is None or not isinstance(exc, _numba.core.errors.NumbaError):
                raise
            _fall_back(family, exc)
    return reference(*args, **kwargs)


def path() -> str:
    """The path the kernels took in this run, for ``sunset info``, the bench and every output's provenance.

    ``"compiled"``; ``"numpy (numba missing)"``, ``"numpy (SUNSET_COMPILED=0)"`` or ``"numpy (switched off)"``
    (:func:`use_compiled`); or ``"mixed: compiled, numpy for light.kernel (compilation failed: TypingError)"``
    when some families fell back (:func:`fallbacks`).
    """
    if not _state["on"]:
        return f"numpy ({_why_numpy() or 'switched off'})"
    fell = fallbacks()
    if not fell:
        return "compiled"
    return "mixed: compiled, numpy for " + "; ".join(f"{k} ({v})" for k, v in sorted(fell.items()))
