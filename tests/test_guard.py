"""sunset.guard: a stop signal in a process forked by the command never runs the parent's code in the child."""

import os
import signal
import time

import pytest

from sunset.guard import Interrupted, adopt_signals, signals_stop_the_command

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")

#: What the child's last resort exits with when a stop unwound it to its own ``finally``.
UNWOUND = 7


def _child_status(adopt: bool) -> int:
    """Fork under the command's handlers; the child sends itself SIGTERM; its exit status."""
    with signals_stop_the_command():
        pid = os.fork()
        if pid == 0:                                       # the child: nothing here may reach pytest's stack
            try:
                if adopt:
                    adopt_signals()
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(5)                              # the handler runs here
            except Interrupted:
                os._exit(UNWOUND)
            finally:
                os._exit(0)
        _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status)


def test_a_stop_right_after_a_fork_ends_the_child_at_once():
    # Without the owner check the child raises Interrupted and unwinds into its finally (exit 7 or 0).
    assert _child_status(adopt=False) == 128 + signal.SIGTERM


def test_a_child_that_adopted_the_signals_raises_as_the_command_does():
    assert _child_status(adopt=True) == UNWOUND


def test_the_command_itself_still_raises():
    with signals_stop_the_command():
        with pytest.raises(Interrupted):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)
