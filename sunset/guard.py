"""What the command line does so that no error, signal or odd install turns into a traceback.

* :func:`signals_stop_the_command`: Ctrl-C, SIGTERM and SIGHUP become exceptions
  (``KeyboardInterrupt``, :class:`Interrupted`), so the atomic writer removes
  its temporary files on the way out; the stop is also noted
  (:func:`note_stop`, which :mod:`sunset.io` reads), so that a stop whose
  exception Python swallowed (in an at-fork hook or a destructor) still keeps
  every output from landing, and is reported once (:func:`check_stop`), not as an "Exception ignored" trace.
  A process forked by the command inherits the handler: until it takes the
  handler on (:func:`adopt_signals`) a stop signal ends it at once, so that
  the exception can never unwind the parent's copied stack in the child.
* :func:`one_line`: an error message as one short line.
* :func:`silenced_stdout`: after standard output failed (``sunset scene >
  /dev/full``), Python's own flush at exit must not report it again.
* :func:`config_fallback`: a read-only install with no writable HOME gets a
  private matplotlib folder instead of two lines of warnings on every command.
* :func:`env_count`, :func:`check_environment`: the thread and process counts
  of the environment (``SUNSET_THREADS``, ``SUNSET_WORKERS``,
  ``NUMBA_NUM_THREADS``) are positive whole numbers in ASCII digits, and a
  count is capped by the CPUs this process may use (:func:`usable_cpus`);
  anything else is a one-line error, never silently ignored.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys

__all__ = ["MAX_MESSAGE", "Interrupted", "signals_stop_the_command", "note_stop", "check_stop", "one_line",
           "silenced_stdout", "config_fallback", "adopt_signals", "usable_cpus", "env_count", "check_environment", "COUNT_VARIABLES"]

#: The longest error line the command prints, characters.
MAX_MESSAGE = 400

#: The signals that stop a command (with exit status 128 + the signal's number).
STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


class Interrupted(BaseException):
    """A signal (SIGTERM, SIGHUP) turned into an exception, so that temporary files are removed on the way out."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


#: A stop signal (Ctrl-C, SIGTERM) noted by the command line's handler. Its
#: exception can be swallowed where Python ignores errors (an at-fork hook of
#: a subprocess, a destructor): no output lands once one is noted (:mod:`sunset.io`).
_stop: list[BaseException] = []


def note_stop(exc: BaseException | None) -> None:
    """Record (or, with None, forget) a stop signal's exception: every later commit of an output raises it."""
    _stop.clear()
    if exc is not None:
        _stop.append(exc)


#: The process whose stop signals raise (the command's, or a forked one that adopted them); empty: any.
_owner: list[int] = []


def adopt_signals() -> None:
    """In a process forked by the command, at the start of its own work: its stop signals raise here too."""
    _owner[:] = [os.getpid()]


def _on_signal(signum, frame):
    exc = KeyboardInterrupt() if signum == signal.SIGINT else Interrupted(signum)
    note_stop(exc)                       # should the exception be swallowed, no output lands all the same
    if _owner and _owner[0] != os.getpid():
        # a child forked a moment ago (before its own handlers or its target ran): raising here
        # would unwind the parent's stack, copied by the fork, and run the parent's code twice
        os._exit(128 + signum)
    raise exc


def check_stop() -> None:
    """Raise the noted stop, if a signal came whose exception was swallowed (:func:`note_stop`)."""
    if _stop:
        raise _stop[0]


@contextlib.contextmanager
def signals_stop_the_command():
    """Inside the block the stop signals raise; afterwards the old handlers and hooks are back."""
    import threading

    handlers = {}
    owner = list(_owner)
    if threading.current_thread() is threading.main_thread():
        adopt_signals()
        for sig in STOP_SIGNALS:
            handlers[sig] = signal.signal(sig, _on_signal)
    hook = sys.unraisablehook

    def quiet_stops(unraisable):         # a stop swallowed by Python is reported once, by main, not as a trace
        if not issubclass(unraisable.exc_type, (KeyboardInterrupt, Interrupted)):
            hook(unraisable)

    sys.unraisablehook = quiet_stops
    try:
        yield
    finally:
        sys.unraisablehook = hook
        for sig, old in handlers.items():
            signal.signal(sig, old)
        _owner[:] = owner
        note_stop(None)


def one_line(message) -> str:
    """An error message as one line of at most MAX_MESSAGE characters."""
    text = " ".join(str(message).split())
    if len(text) > MAX_MESSAGE:
        text = text[:MAX_MESSAGE - 5] + " ..."
    return text


class silenced_stdout:
    """Point stdout at /dev/null, so that Python's flush at exit does not report the same error again."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            os.close(devnull)
        except (OSError, ValueError, AttributeError):
            pass
        sys.stdout = open(os.devnull, "w")
        return False


def config_fallback() -> None:
    """Give matplotlib (imported by colour-science) a private config folder when HOME's is not writable."""
    import stat
    import tempfile

    if "MPLCONFIGDIR" in os.environ:
        return
    probe = os.environ.get("XDG_CONFIG_HOME") or os.path.join(os.path.expanduser("~"), ".config")
    while not os.path.exists(probe) and os.path.dirname(probe) != probe:
        probe = os.path.dirname(probe)
    if os.access(probe, os.W_OK | os.X_OK):
        return
    path = os.path.join(tempfile.gettempdir(), f"sunset-matplotlib-{os.getuid()}")
    try:
        os.makedirs(path, mode=0o700, exist_ok=True)
        st = os.lstat(path)
    except OSError:
        return
    if stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o077:
        os.environ["MPLCONFIGDIR"] = path


# --------------------------------------------------------------------------- counts from the environment
#: The environment variables that hold a count of threads or processes.
COUNT_VARIABLES = ("SUNSET_THREADS", "SUNSET_WORKERS", "NUMBA_NUM_THREADS")


def usable_cpus() -> int:
    """The CPUs this process may run on (its affinity mask, ``os.sched_getaffinity``, where the platform has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - platforms without affinity masks
        return os.cpu_count() or 1


def env_count(name: str, cap: bool = True) -> int | None:
    """The count in environment variable ``name``: None when unset or blank, else a whole number >= 1.

    Only ASCII digits are read (``int`` would also take ``"٣"`` or ``"1_0"``);
    a sign, a fraction, a word, non-ASCII digits or 0 raise
    :class:`~sunset.errors.SunsetError` naming the variable. With ``cap``
    the count is at most :func:`usable_cpus` (more threads or processes than
    CPUs buy nothing and cost memory: ``SUNSET_THREADS=1000000`` is the CPU
    count).
    """
    from .errors import SunsetError, shown

    text = os.environ.get(name)
    if text is None or not text.strip():
        return None
    word = text.strip()
    if not (word.isascii() and word.isdigit()) or not word.strip("0"):
        raise SunsetError(f"{name} must be a whole number of at least 1 (ASCII digits), got {shown(text)}")
    most = usable_cpus() if cap else 1 << 30
    return most if len(word) > 9 else min(int(word), most)


def check_environment() -> None:
    """Raise :class:`~sunset.errors.SunsetError` for a bad count in :data:`COUNT_VARIABLES` or a bad ``SUNSET_COMPILED``.

    The command line calls it before any work; the package checks each
    variable again where it reads it (``NUMBA_NUM_THREADS`` before Numba is
    imported: Numba raises a ``ValueError`` of its own at import for 0 and
    ignores a word).
    """
    from .errors import SunsetError, shown

    for name in COUNT_VARIABLES:
        env_count(name)
    compiled = os.environ.get("SUNSET_COMPILED")
    if compiled is not None and compiled.strip() not in ("", "0", "1"):
        raise SunsetError(f"SUNSET_COMPILED must be 0 or 1, got {shown(compiled)}")
