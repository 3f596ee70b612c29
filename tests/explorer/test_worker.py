"""The newest request wins (sunset.explorer.worker.Latest), with a slow fake renderer held at a gate."""

import threading

import pytest

from sunset.errors import SunsetError
from sunset.explorer.worker import Latest


class Gated:
    """A renderer that waits at a gate for the requests it is told to hold."""

    def __init__(self, hold=()):
        self.hold = set(hold)
        self.started = {r: threading.Event() for r in self.hold}
        self.gate = threading.Event()
        self.delivered = []

    def work(self, request):
        if request in self.hold:
            self.started[request].set()
            assert self.gate.wait(30), "the test never opened the gate"
        if request == "bad":
            raise SunsetError("bad request")
        return request * 2

    def deliver(self, request, result, error):
        self.delivered.append((request, result, None if error is None else str(error)))


def test_a_render_overtaken_while_it_runs_is_dropped_and_only_the_newest_waiting_request_runs():
    fake = Gated(hold={1})
    latest = Latest(fake.work, fake.deliver)
    assert latest.submit(1) == 1
    assert fake.started[1].wait(30)            # request 1 is being rendered
    for r in (2, 3, 4):                        # a slider passing three more values meanwhile
        latest.submit(r)
    assert not latest.wait(0.05)               # still busy at the gate
    fake.gate.set()
    assert latest.wait(30)
    assert latest.rendered == [1, 4]           # 2 and 3 were replaced in the slot, never rendered
    assert fake.delivered == [(4, 8, None)]    # 1 finished, but 4 had come: dropped
    assert latest.dropped == 1
    latest.close()


def test_every_request_is_delivered_when_none_overtakes_it():
    fake = Gated()
    latest = Latest(fake.work, fake.deliver)
    for r in (1, 2, 3):
        latest.submit(r)
        assert latest.wait(30)
    assert fake.delivered == [(1, 2, None), (2, 4, None), (3, 6, None)] and latest.dropped == 0
    assert latest.idle
    latest.close()


def test_an_error_is_the_answer_and_the_thread_goes_on():
    fake = Gated()
    latest = Latest(fake.work, fake.deliver)
    latest.submit("bad")
    assert latest.wait(30)
    latest.submit(5)
    assert latest.wait(30)
    assert fake.delivered == [("bad", None, "bad request"), (5, 10, None)]
    latest.close()


def test_an_overtaken_error_is_dropped_too():
    fake = Gated(hold={"bad"})
    latest = Latest(fake.work, fake.deliver)
    latest.submit("bad")
    assert fake.started["bad"].wait(30)
    latest.submit(7)
    fake.gate.set()
    assert latest.wait(30)
    assert fake.delivered == [(7, 14, None)]
    latest.close()


def test_close_stops_the_thread_and_refuses_more():
    fake = Gated()
    latest = Latest(fake.work, fake.deliver)
    latest.submit(1)
    latest.wait(30)
    thread = latest._thread
    latest.close()
    assert not thread.is_alive()
    with pytest.raises(RuntimeError, match="closed"):
        latest.submit(2)
