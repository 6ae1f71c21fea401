"""Who hears of a tab's every commit (the classroom relaying a presenter, a recorder): a list that
is safe to change from any thread while commits are told."""

from __future__ import annotations

import contextlib
import logging
import threading
from collections.abc import Callable

from ..core.snapshot import Snapshot
from ..core.state import LabState

__all__ = ["Subscribers"]

log = logging.getLogger(__name__)

Listener = Callable[[LabState, Snapshot], None]


class Subscribers:
    """``fn(state, snapshot)`` callbacks told after each commit of one tab (``key`` names it in logs)."""

    def __init__(self, key: int) -> None:
        self._key = key
        self._lock = threading.Lock()
        self._fns: list[Listener] = []

    def add(self, fn: Listener) -> Callable[[], None]:
        """Tell ``fn`` of every commit from now on; returns the function that stops it."""
        with self._lock:
            self._fns.append(fn)

        def unsubscribe() -> None:
            with self._lock, contextlib.suppress(ValueError):
                self._fns.remove(fn)

        return unsubscribe

    def tell(self, state: LabState, snap: Snapshot) -> None:
        """Tell every subscriber; one that fails is logged and the others are still told."""
        with self._lock:
            fns = list(self._fns)
        for fn in fns:
            try:
                fn(state, snap)
            except Exception:
                log.exception("a subscriber of client %s failed", self._key)

    def clear(self) -> None:
        with self._lock:
            self._fns.clear()
