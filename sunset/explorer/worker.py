"""The newest request wins: one render thread and a single slot for the request that waits.

A slider sends a value for every step it passes; rendering each would leave
the picture far behind the hand. :class:`Latest` keeps one slot: a request
replaces the one waiting there (which is never rendered), the thread takes
the slot's request when it is free, and a render that a newer request
overtook while it ran is finished (Python cannot interrupt it) but its
result is dropped. So at most one render runs and one waits, whatever the
number of requests, and the last result delivered is the newest request's.
"""

from __future__ import annotations

import threading
import traceback
from typing import Any, Callable

__all__ = ["Latest"]


class Latest:
    """Runs ``work(request)`` on a thread of its own for the newest request only.

    Parameters
    ----------
    work : callable
        ``work(request) -> result``; an exception it raises is the result's error.
    deliver : callable
        ``deliver(request, result, error)``, called on the render thread for
        a request that no newer one overtook (``error`` None on success,
        ``result`` None on failure).

    Attributes
    ----------
    rendered : list
        Every request that ``work`` was called with, in order.
    dropped : int
        Renders finished after a newer request came: their results were not delivered.
    """

    def __init__(self, work: Callable[[Any], Any], deliver: Callable[[Any, Any, BaseException | None], None]):
        self._work = work
        self._deliver = deliver
        self._cond = threading.Condition()
        self._slot: tuple[int, Any] | None = None
        self._newest = 0
        self._busy = False
        self._closed = False
        self._thread: threading.Thread | None = None
        self.rendered: list = []
        self.dropped = 0

    def submit(self, request: Any) -> int:
        """Put ``request`` in the slot (replacing a waiting one); its number, counted from 1."""
        with self._cond:
            if self._closed:
                raise RuntimeError("the explorer's render thread is closed")
            self._newest += 1
            self._slot = (self._newest, request)
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="sunset-explorer", daemon=True)
                self._thread.start()
            self._cond.notify_all()
            return self._newest

    def _run(self) -> None:
        while True:
            with self._cond:
                while self._slot is None and not self._closed:
                    self._cond.wait()
                if self._closed:
                    return
                number, request = self._slot
                self._slot = None
                self._busy = True
                self.rendered.append(request)
            result, error = None, None
            try:
                result = self._work(request)
            except Exception as exc:   # the error is the request's answer, shown by deliver
                error = exc
            try:
                with self._cond:
                    current = number == self._newest
                    if not current:
                        self.dropped += 1
                if current:
                    self._deliver(request, result, error)
            except Exception:   # pragma: no cover - a bug in deliver: said, and the thread goes on
                traceback.print_exc()
            finally:
                with self._cond:
                    self._busy = False
                    self._cond.notify_all()

    def wait(self, timeout: float | None = None) -> bool:
        """Block until no request waits and none is being rendered (and delivered); False on timeout."""
        with self._cond:
            return self._cond.wait_for(lambda: self._slot is None and not self._busy, timeout)

    @property
    def idle(self) -> bool:
        """No request waits and none is being rendered."""
        with self._cond:
            return self._slot is None and not self._busy

    def close(self) -> None:
        """Stop the thread once its current render is done; a waiting request is dropped."""
        with self._cond:
            self._closed = True
            self._slot = None
            self._cond.notify_all()
            thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join()
