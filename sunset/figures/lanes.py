"""Both cores for one ``sunset figures`` run: two processes taking the figures from one queue.

The figures are cut into *units* (:data:`UNITS`): a figure alone, or the
figures that share what they compute (:mod:`sunset.figures.shared`: Figure 6's
frame is also behind ``fig6-rgb.png`` and ``quantisation.png``, and Figure 7
re-exposes its tape; the RGB figures share the light's tables), so that nothing
is computed twice. With two or more
workers (:func:`sunset.pipeline.workers.frame_workers`) and two or more units to
make, a second process is forked at the start of the run; it makes the first
unit (the film, the longest: its wave cycle, 192 exposures and the encoders)
while this process makes the second, and then each process takes the next
unit not yet taken, in :data:`UNITS`' order (longest first), until none is
left. The two lanes so end within about one small figure of each other,
however fast each figure has become, where a fixed split has to be re-measured
whenever one of them changes. Both processes write into the same hidden
folder. The files are made by the same functions either way, so they are the
same bytes (which process made what changes nothing); the run stays all or
nothing (:func:`sunset.figures._make_all` lands the files only when both lanes
are done, and an error in either lane, or Ctrl-C, lands nothing; a lane that
sees the other has failed takes no more units). The second process is forked
as soon as the run starts: what both lanes then load for themselves (matplotlib,
colour-science, the compiled kernels) is loaded by the two at once, on both
cores, where loading it before the fork would keep the other core idle for as
long (the lanes end together, so the run is shorter by half of it). Where
processes cannot be forked safely (no ``fork``, or Python 3.12+
with threads running) the run keeps one lane.
"""

from __future__ import annotations

import sys
import time

from ..errors import SunsetError
from ..guard import adopt_signals

__all__ = ["UNITS", "plan", "Queue", "SideLane"]

#: The units the lanes take up, in this order: longest first (CPU seconds of each on the
#: 2-core machine, 2026-12-02: the film 10-13, the RGB unit 9, the ripples 3, Figure 4 and
#: the reflections 1, the others under 1). A unit's figures are made by one process, in
#: registry order. The RGB unit holds every figure of the RGB back end: Figure 6's frame is
#: also behind ``fig6-rgb.png`` and ``quantisation.png`` (Figure 7 re-exposes its tape), and
#: the light of an hour (:class:`~sunset.light.lighting.Lighting`) starts from a table of the
#: sun's slant columns that a process builds once (about 1 s), which ``clouds-rgb.png`` then
#: finds built.
UNITS = (("film",), ("6", "7", "rgb", "quantisation", "clouds"), ("ripples",), ("4",), ("reflections",), ("3",),
         ("diagnostic",), ("1",), ("2",), ("5",))


def _can_fork() -> bool:
    import multiprocessing
    import threading

    if "fork" not in multiprocessing.get_all_start_methods():
        return False
    return sys.version_info < (3, 12) or threading.active_count() == 1


def plan(names: list[str], workers: int | None) -> tuple[list[list[str]], bool]:
    """(the units that hold ``names``, in the order they are taken up; whether two lanes make them).

    Each unit keeps only the asked figures of :data:`UNITS`' unit, in ``names``' order.
    """
    from ..pipeline.workers import frame_workers

    units = [[n for n in names if n in unit] for unit in UNITS]
    units = [u for u in units if u]
    two = len(units) > 1 and frame_workers(workers, 2) >= 2 and _can_fork()
    return units, two


class Queue:
    """The next unit to take, shared by the two processes (a counter in shared memory, under its lock).

    Units 0 and 1 are given out at the start (the second process makes unit 0, this one unit 1);
    :meth:`take` hands out the others, each once.
    """

    def __init__(self, count: int):
        import multiprocessing

        self.count = count
        self._next = multiprocessing.get_context("fork").Value("i", min(2, count))

    def take(self) -> int | None:
        """The next unit's index, or None when every unit has been taken."""
        with self._next.get_lock():
            k = self._next.value
            if k >= self.count:
                return None
            self._next.value = k + 1
            return k


class SideLane:
    """The second process: started with :meth:`start`, awaited with :meth:`results`, stopped with :meth:`stop`."""

    def __init__(self, units, queue: Queue, make):
        """``make(name)`` makes one figure and returns the files it wrote; the process makes ``units[0]``
        and then what it takes from ``queue``."""
        self.units = [list(u) for u in units]
        self.queue = queue
        self.make = make
        self.proc = None
        self.conn = None

    def start(self) -> "SideLane":
        import multiprocessing

        ctx = multiprocessing.get_context("fork")
        self.conn, child = ctx.Pipe(duplex=False)
        for stream in (sys.stdout, sys.stderr):          # nothing buffered is written twice
            try:
                stream.flush()
            except (OSError, ValueError, AttributeError):
                pass
        self.proc = ctx.Process(target=self._run, args=(child,), name="sunset-figures-side", daemon=False)
        self.proc.start()
        child.close()
        return self

    def _run(self, conn) -> None:                        # in the forked process
        import traceback

        adopt_signals()                                  # a stop from here on is reported to the parent
        try:
            done = []
            k = 0
            while k is not None:
                for name in self.units[k]:
                    start = time.perf_counter()
                    files = self.make(name)
                    done.append((name, [str(f) for f in files], time.perf_counter() - start))
                k = self.queue.take()
            conn.send(("ok", done))
        except SunsetError as exc:
            conn.send(("error", str(exc)))
        except KeyboardInterrupt:                        # a stop (Ctrl-C reaches both processes): a stop here too
            conn.send(("stop", ""))
        except BaseException as exc:                     # a bug, or a stop: reported by the parent
            conn.send(("crash", f"{type(exc).__name__}: {exc}\n{traceback.format_exc()}"))
        finally:
            conn.close()

    def finished(self) -> bool:
        """Whether the second process has sent its word (it took its last unit, or it failed)."""
        return self.conn.poll()

    def results(self) -> list[tuple[str, list[str], float]]:
        """Wait for the second process: (name, files, seconds) of each of its figures; its error raised here."""
        try:
            kind, payload = self.conn.recv()
        except EOFError:
            self.proc.join()
            names = ", ".join(n for u in self.units for n in u)
            raise SunsetError(f"figures {names}: the process making them ended without a word "
                              f"(exit status {self.proc.exitcode})") from None
        self.proc.join()
        if kind == "error":
            raise SunsetError(payload)
        if kind == "stop":
            raise KeyboardInterrupt
        if kind == "crash":
            raise RuntimeError(f"the figures' second process failed: {payload}")
        return payload

    def stop(self) -> None:
        """End the second process (if it still runs) and wait for it; safe to call more than once."""
        if self.proc is None:
            return
        if self.proc.is_alive():
            self.proc.terminate()                        # SIGTERM: under the command it cleans up as on Ctrl-C
            self.proc.join(10)
            if self.proc.is_alive():
                self.proc.kill()
        self.proc.join()
        self.conn.close()
        self.proc = None
