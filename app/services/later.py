"""Short calls due later, for every tab of the process on one thread (instead of a thread each).

A tab writes its page's address at most every 0.4 s (the last one always, so a call is left for
later) and beats every 2 s: with a ``threading.Timer`` each, a tab moving a slider started a thread
every other change (about 0.2 ms of CPU each). :func:`later` keeps the calls in one heap served by
one daemon thread, started on first use (and again in a forked child, which inherits no threads).
The calls must be short (queue a message, set a flag): they run one after another.
"""

from __future__ import annotations

import heapq
import itertools
import logging
import os
import threading
import time
from collections.abc import Callable

__all__ = ["later", "Later", "Call"]

log = logging.getLogger(__name__)


class Call:
    """One call due later; :meth:`cancel` drops it if it has not run yet."""

    __slots__ = ("fn", "cancelled")

    def __init__(self, fn: Callable[[], object]) -> None:
        self.fn, self.cancelled = fn, False

    def cancel(self) -> None:
        self.cancelled = True


class Later:
    """Calls due at a time, run in order on one thread (``clock``: monotonic seconds)."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self._clock = clock
        self._cond = threading.Condition()
        self._heap: list[tuple[float, int, Call]] = []
        self._order = itertools.count()
        self._pid = -1  # the process whose thread serves the heap

    def call(self, delay: float, fn: Callable[[], object]) -> Call:
        """Run ``fn()`` in ``delay`` seconds (or as soon after as the thread is free)."""
        call = Call(fn)
        with self._cond:
            if self._pid != os.getpid():  # first use, or a forked child: no thread serves the heap here
                self._pid, self._heap = os.getpid(), []
                threading.Thread(target=self._run, name="jacobian-lab-later", daemon=True).start()
            heapq.heappush(self._heap, (self._clock() + max(delay, 0.0), next(self._order), call))
            self._cond.notify()
        return call

    def _run(self) -> None:
        while True:
            with self._cond:
                while True:
                    wait = self._heap[0][0] - self._clock() if self._heap else None
                    if wait is not None and wait <= 0:
                        break
                    self._cond.wait(wait)
                _, _, call = heapq.heappop(self._heap)
            if not call.cancelled:
                try:
                    call.fn()
                except Exception:  # one call's failure must not stop the others
                    log.exception("a call made later failed")


_LATER = Later()


def later(delay: float, fn: Callable[[], object]) -> Call:
    """Run ``fn()`` in ``delay`` seconds on the process's one thread of calls made later."""
    return _LATER.call(delay, fn)
