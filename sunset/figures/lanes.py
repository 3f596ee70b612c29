"""Both cores for one ``sunset figures`` run: the film in a second process beside the other figures.

The film is the longest figure (its wave cycle, then 192 exposures and the
encoders), and it shares nothing with the others; nor do the ripples and the
direct-ray diagnostic, which go with it to even the two lanes out (measured:
the film about 26 s, the others together about 36 s, on the loaded 2-core
machine). With two or more workers (:func:`sunset.tape.cycle.frame_workers`)
and other figures to make, they are made by a process forked at the start of
the run, into the same hidden folder, while this process makes the others; the
run then waits for it. The sky's spectral data (colour-science's tables, which
both lanes use) is loaded before the fork, once. The
files are made by the same functions either way, so they are the same bytes;
the run stays all or nothing (:func:`sunset.figures._make_all` lands the
files only when both lanes are done, and an error in either lane, or Ctrl-C,
lands nothing). Where processes cannot be forked safely (no ``fork``, or
Python 3.12+ with threads running) the run keeps one lane.
"""

from __future__ import annotations

import sys
import time

from ..errors import SunsetError

__all__ = ["SIDE", "split", "SideLane"]

#: The figures the second process makes, in this order.
SIDE = ("film", "ripples", "diagnostic")


def _can_fork() -> bool:
    import multiprocessing
    import threading

    if "fork" not in multiprocessing.get_all_start_methods():
        return False
    return sys.version_info < (3, 12) or threading.active_count() == 1


def split(names: list[str], workers: int | None) -> tuple[list[str], list[str]]:
    """(figures made here, figures made by the second process); the second list is empty for one lane."""
    from ..tape.cycle import frame_workers

    side = [n for n in names if n in SIDE]
    here = [n for n in names if n not in SIDE]
    if not here:
        here, side = side[1:], side[:1]
    if not side or not here or frame_workers(workers, 2) < 2 or not _can_fork():
        return list(names), []
    return here, side


class SideLane:
    """The second process: started with :meth:`start`, awaited with :meth:`results`, stopped with :meth:`stop`."""

    def __init__(self, names, make):
        """``make(name)`` makes one figure and returns the files it wrote."""
        self.names = list(names)
        self.make = make
        self.proc = None
        self.conn = None

    def start(self) -> "SideLane":
        import multiprocessing

        from ..model.sky import spectral_data

        spectral_data()                                  # colour-science imported once, for both processes
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

        try:
            done = []
            for name in self.names:
                start = time.perf_counter()
                files = self.make(name)
                done.append((name, [str(f) for f in files], time.perf_counter() - start))
            conn.send(("ok", done))
        except SunsetError as exc:
            conn.send(("error", str(exc)))
        except BaseException as exc:                     # a bug, or a stop: reported by the parent
            conn.send(("crash", f"{type(exc).__name__}: {exc}\n{traceback.format_exc()}"))
        finally:
            conn.close()

    def results(self) -> list[tuple[str, list[str], float]]:
        """Wait for the second process: (name, files, seconds) of each of its figures; its error raised here."""
        try:
            kind, payload = self.conn.recv()
        except EOFError:
            self.proc.join()
            raise SunsetError(f"figures {', '.join(self.names)}: the process making them ended without a word "
                              f"(exit status {self.proc.exitcode})") from None
        self.proc.join()
        if kind == "error":
            raise SunsetError(payload)
        if kind == "crash":
            raise RuntimeError(f"figures {', '.join(self.names)} failed in the second process: {payload}")
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
