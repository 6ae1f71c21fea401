"""Garbage collections run while the server is quiet, not on a room's first move after it fills.

Python collects its oldest generation only when objects are allocated, and then walks every object
alive. A tab leaves some thousands of long-lived objects (its widgets, handles, views), so a room's joins
make a full collection due that waits through the quiet moment and falls on the presenter's next move:
every follower's frame waits for it. Measured with 30 followers in one process: 89-148 ms on the first
move; in ``bench/bench_classroom.py`` the maximum latency was 650-1330 ms at 150-300 followers while the
95th percentile was 100-280 ms.

:class:`QuietCollector` is told when a tab joins or leaves. Once nothing has been drawn, and no tab
has joined or left, for ``settle`` seconds (0.5) after joins, it collects what is not frozen yet (the new
tabs' objects: cheap) and freezes it (``gc.freeze()``): the open tabs' objects are left out of later
collections, which walk only what was made since. A leave makes a full collection due, run once quiet for
``settle_full`` seconds (2): the frozen objects unfrozen (``gc.unfreeze()``), everything collected (a
closed tab's objects are freed then even if they hold each other in a cycle), then frozen again. A
minute of drawing makes one due too (a tab choosing another robot replaces its panel).

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
    """Collects and freezes the heap at the server's quiet moments.

    After a join, once nothing was drawn and no tab joined or left for ``settle`` s: a collection of what
    is not frozen yet (the new tabs' objects; cheap) and a freeze. After a leave, or after ``every`` s of
    drawing, once quiet for ``settle_full`` s: the frozen objects unfrozen, everything collected (a
    closed tab's cycles freed) and frozen again.

    Args:
        activity: A count that grows while tabs are drawn (the renderer's visits).
        settle, settle_full: Quiet seconds before a collection of the new objects, of everything.
        every: Seconds of drawing after which a full collection is due without a leave.
        clock: Monotonic seconds; ``schedule(delay, fn)`` runs ``fn`` later (tests pass their own).
    """

    def __init__(
        self,
        activity: Callable[[], int],
        settle: float = 0.5,
        settle_full: float = 2.0,
        every: float = 60.0,
        clock: Callable[[], float] = time.monotonic,
        schedule: Callable[[float, Callable[[], object]], Call] = later,
    ) -> None:
        self._activity, self.settle, self.settle_full, self.every = activity, settle, settle_full, every
        self._clock, self._schedule = clock, schedule
        self._lock = threading.Lock()
        self._joined = self._left = False  # a join, a leave not yet collected
        self._changed_at = self._full_at = clock()  # the last join or leave; the last full collection
        self._seen = (activity(), clock())  # the activity count and when it last moved
        self._call: Call | None = None
        self._closed = False
        self.collections = {"new": 0, "full": 0}
        """How many quiet collections of each kind ran (for tests and benches)."""
        self._arm()  # looks every ``settle`` s from now on

    def joined(self) -> None:
        """A tab joined: collect and freeze its objects at the next quiet moment."""
        with self._lock:
            self._joined, self._changed_at = True, self._clock()

    def left(self) -> None:
        """A tab left: collect everything at the next quiet moment (its objects may hold each other)."""
        with self._lock:
            self._left, self._changed_at = True, self._clock()

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
        """Every ``settle`` s: collect what is due if it has been quiet long enough."""
        with self._lock:
            self._call = None
            if self._closed:
                return
            now, count = self._clock(), self._activity()
            if count != self._seen[0]:
                self._seen = (count, now)
            quiet = now - max(self._seen[1], self._changed_at)
            drawn = self._seen[1] > self._full_at
            full = self._left or (drawn and now - self._full_at >= self.every)
            kind = (
                "full"
                if full and quiet >= self.settle_full
                else "new"
                if self._joined and quiet >= self.settle
                else ""
            )
            if kind == "full":
                self._joined = self._left = False
                self._full_at = now
            elif kind == "new":
                self._joined = False
            self._arm()
        if kind:
            self._collect(kind)

    def _collect(self, kind: str) -> None:
        start = time.perf_counter()
        if kind == "full":
            gc.unfreeze()
        found = gc.collect()
        gc.freeze()
        self.collections[kind] += 1
        log.debug(
            "quiet collection (%s): %d unreachable, %d frozen, %.0f ms",
            kind, found, gc.get_freeze_count(), (time.perf_counter() - start) * 1e3,
        )  # fmt: skip
