"""The full garbage collection run while the server is quiet, not on a room's first move after it fills.

Python collects its oldest generation only when objects are allocated, and then walks every object
alive. A tab leaves some thousands of long-lived objects (its widgets, handles, views), so a room's joins
make a full collection due that waits through the quiet moment and falls on the presenter's next move:
every follower's frame waits for it. Measured with 30 followers in one process: 89-148 ms on the first
move; in ``bench/bench_classroom.py`` the maximum latency was 650-1330 ms at 150-300 followers while the
95th percentile was 100-280 ms.

:class:`QuietCollector` is told when a tab joins or leaves (:meth:`QuietCollector.changed`). Once no tab
has joined or left, and no tab has been drawn, for ``settle`` seconds, it collects everything
(``gc.collect()``) and then freezes what is left (``gc.freeze()``): the open tabs' objects are left out
of later full collections, which walk only what was made since. Before each collection it unfreezes
(``gc.unfreeze()``), so a closed tab's objects, and the views a tab replaced, are freed then even if they
hold each other in a cycle. Besides joins and leaves, it collects every ``every`` seconds in which tabs
were drawn (a tab choosing another robot replaces its panel), at the next quiet moment.

Only for the server's own processes (``serve``): a notebook's kernel keeps its user's objects out of
freezing.
"""

from __future__ import annotations

import gc
import logging
import threading
import time
from collections.abc import Callable

from .later import Call, later

__all__ = ["QuietCollector"]

log = logging.getLogger(__name__)


class QuietCollector:
    """Collects and freezes the heap when tabs have settled and nothing was drawn for ``settle`` s.

    Args:
        activity: A count that grows while tabs are drawn (the renderer's visits).
        settle: Seconds without a join, a leave or a drawing before a collection.
        every: Seconds of drawing after which a collection is due again without a join or leave.
        clock: Monotonic seconds; ``schedule(delay, fn)`` runs ``fn`` later (tests pass their own).
    """

    def __init__(
        self,
        activity: Callable[[], int],
        settle: float = 2.0,
        every: float = 60.0,
        clock: Callable[[], float] = time.monotonic,
        schedule: Callable[[float, Callable[[], object]], Call] = later,
    ) -> None:
        self._activity, self.settle, self.every = activity, settle, every
        self._clock, self._schedule = clock, schedule
        self._lock = threading.Lock()
        self._changed_at: float | None = None  # the last join or leave not yet collected
        self._collected_at = clock()
        self._seen = (activity(), clock())  # the activity count and when it last moved
        self._call: Call | None = None
        self._closed = False
        self.collections = 0
        """How many quiet collections ran (for tests and benches)."""
        self._arm()  # looks every ``settle`` s from now on

    def changed(self) -> None:
        """A tab joined or left: collect at the next quiet moment."""
        with self._lock:
            self._changed_at = self._clock()
            self._arm()

    def close(self) -> None:
        """Stop collecting and give the frozen objects back to the collector."""
        with self._lock:
            self._closed = True
            if self._call is not None:
                self._call.cancel()
                self._call = None
        gc.unfreeze()

    def _arm(self) -> None:
        if self._call is None and not self._closed:
            self._call = self._schedule(self.settle, self._check)

    def _check(self) -> None:
        """Every ``settle`` s: collect if due and quiet, else look again later."""
        with self._lock:
            self._call = None
            if self._closed:
                return
            now, count = self._clock(), self._activity()
            if count != self._seen[0]:
                self._seen = (count, now)
            quiet = now - self._seen[1] >= self.settle and (
                self._changed_at is None or now - self._changed_at >= self.settle
            )
            drawn = self._seen[1] > self._collected_at
            due = self._changed_at is not None or (drawn and now - self._collected_at >= self.every)
            if not (due and quiet):
                self._arm()
                return
            self._changed_at, self._collected_at = None, now
            self._arm()  # the periodic look goes on
        start = time.perf_counter()
        gc.unfreeze()
        found = gc.collect()
        gc.freeze()
        self.collections += 1
        log.debug(
            "quiet collection: %d unreachable, %d frozen, %.0f ms",
            found, gc.get_freeze_count(), (time.perf_counter() - start) * 1e3,
        )  # fmt: skip
