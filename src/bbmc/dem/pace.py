"""Kernel calls short enough for Ctrl-C to stop a run at once.

Python acts on a signal (Ctrl-C sends SIGINT) only between bytecodes, and a numba kernel is one call: a
kernel that runs for a minute hears Ctrl-C after a minute. So the engine's long loops, the cycles and
the contact search's block pairs, run in calls of about `CALL_SECONDS` each, the size of each call set
from the time per unit of work (a cycle, a block pair) of the call before. The split changes no number:
each loop keeps all its state in its arrays, so the same work gives the same numbers, bit for bit,
however it is cut.

Between two calls, a thread can also be told to stop (`stopped_when`): a sweep's task on a dask worker
ends this way once its client has cancelled it, instead of running its batch to the end in vain.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

CALL_SECONDS = 0.05  # a kernel call's target wall time [s]: Ctrl-C is acted on within about this


@dataclass
class Pace:
    """How many units of work (cycles, block pairs) the next kernel call does: one at first, then what
    fits in `CALL_SECONDS` at the rate of the last call, but at most twice the size asked of it (one
    call that was fast, e.g. with few contacts yet, is not trusted far)."""

    units: int = 1

    def take(self, left: int) -> int:
        """The size of the next call, `left` units being left to do; raises `RunStoppedError` if this
        thread has been told to stop (`stopped_when`)."""
        stop = getattr(_thread, "stop", None)
        if stop is not None and stop():
            raise RunStoppedError("stopped between two kernel calls")
        return min(left, self.units)

    def timed(self, units: int, seconds: float) -> None:
        """Learn from a call that did `units` units of work in `seconds` [s]."""
        if units <= 0:
            return
        fitting = int(CALL_SECONDS * units / seconds) if seconds > 0 else 2 * self.units
        self.units = max(1, min(2 * self.units, fitting))


class RunStoppedError(Exception):
    """A run ended between two kernel calls because its thread was told to stop (`stopped_when`)."""


_thread = threading.local()


@contextmanager
def stopped_when(stop: Callable[[], bool]) -> Iterator[None]:
    """In the block, this thread's engine runs end with `RunStoppedError` at the first kernel call
    after `stop()` is true (it is asked before every call: it must be cheap)."""
    before = getattr(_thread, "stop", None)
    _thread.stop = stop
    try:
        yield
    finally:
        _thread.stop = before
