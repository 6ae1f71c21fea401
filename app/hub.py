"""Work that spans tabs: a server-owned hub that relays one tab's state to others.

The seam a presenter mode builds on. A session publishes every committed
state to its subscribers; the hub subscribes to a *leader* and hands each
new state to its *followers* as a :class:`~app.actions.ReplaceState`, so
one change costs one reduce per follower and nothing else is shared.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Protocol

from .actions import Action, ReplaceState
from .state import LabState

__all__ = ["Hub", "Publisher"]


class Publisher(Protocol):
    """What the hub needs of a session."""

    def subscribe(self, fn: Callable[[LabState], None]) -> Callable[[], None]: ...

    def dispatch(self, action: Action) -> None: ...


class Hub:
    """Relays a leader tab's states to follower tabs."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._followers: dict[int, Callable[[Action], None]] = {}
        self._unsubscribe: Callable[[], None] | None = None
        self.relayed = 0

    def lead(self, leader: Publisher) -> None:
        """Make ``leader`` the tab everybody follows (replacing any previous leader)."""
        with self._lock:
            if self._unsubscribe is not None:
                self._unsubscribe()
            self._unsubscribe = leader.subscribe(self._relay)

    def follow(self, key: int, dispatch: Callable[[Action], None]) -> None:
        """Start relaying the leader's states to ``dispatch`` (a follower tab's)."""
        with self._lock:
            self._followers[key] = dispatch

    def leave(self, key: int) -> None:
        """Stop relaying to follower ``key`` (it explores alone, or it closed)."""
        with self._lock:
            self._followers.pop(key, None)

    def followers(self) -> int:
        """How many tabs follow."""
        with self._lock:
            return len(self._followers)

    def _relay(self, state: LabState) -> None:
        with self._lock:
            targets = list(self._followers.values())
        for dispatch in targets:
            dispatch(ReplaceState(state))
            self.relayed += 1
