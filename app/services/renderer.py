"""One thread that reduces and redraws every tab, in turn: the server's only drawing thread.

viser runs each GUI callback on one of 32 pool threads. If each of them
reduced, computed and drew its tab itself, sixty tabs would be sixty threads
fighting over the interpreter lock, each slowed by the others' switches.
Instead a callback only queues its action (:meth:`app.tab.session.ClientSession.dispatch`)
and asks the :class:`Renderer` to visit that tab; the renderer visits tabs
round-robin, and each visit reduces *everything* the tab queued since the
last one and draws once. A tab is visited at most ``max_rate`` times per
second; faster input is coalesced, and while one tab floods, the others keep
their turns.
"""

from __future__ import annotations

import collections
import logging
import threading
import time
from typing import Protocol

__all__ = ["Renderer", "Visitable"]

log = logging.getLogger(__name__)


class Visitable(Protocol):
    """What the renderer needs of a tab."""

    def next_visit(self) -> float:
        """The monotonic time [s] before which the tab should not be redrawn again."""
        ...

    def visit(self) -> bool:
        """Reduce the queued actions and redraw once; True if more actions arrived meanwhile."""
        ...


class Renderer:
    """Visits tabs with queued actions, one at a time, round-robin.

    Args:
        name: Thread name.
    """

    def __init__(self, name: str = "jacobian-lab-renderer") -> None:
        self._ready: collections.deque[Visitable] = collections.deque()
        self._cond = threading.Condition()
        self._closed = False
        self.visits = 0
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def schedule(self, tab: Visitable) -> None:
        """Visit ``tab`` soon (the caller guarantees a tab is scheduled at most once at a time)."""
        with self._cond:
            if self._closed:
                return
            self._ready.append(tab)
            self._cond.notify()

    def close(self) -> None:
        """Stop the thread (queued visits are dropped)."""
        with self._cond:
            self._closed = True
            self._ready.clear()
            self._cond.notify_all()
        if self._thread is not threading.current_thread():
            self._thread.join(5.0)

    def _next(self) -> Visitable | None:
        """The first tab that is due, waiting as long as none is; None when closed."""
        with self._cond:
            while True:
                if self._closed:
                    return None
                if not self._ready:
                    self._cond.wait()
                    continue
                now = time.monotonic()
                for _ in range(len(self._ready)):
                    tab = self._ready.popleft()
                    if tab.next_visit() <= now:
                        return tab
                    self._ready.append(tab)  # too soon after its last redraw: others first
                wait = min(tab.next_visit() for tab in self._ready) - now
                self._cond.wait(max(wait, 0.0005))

    def _run(self) -> None:
        while True:
            tab = self._next()
            if tab is None:
                return
            try:
                more = tab.visit()
            except Exception:  # a tab's failure must never stop the others' redraws
                log.exception("a tab's redraw failed")
                more = False
            self.visits += 1
            if more:
                self.schedule(tab)
