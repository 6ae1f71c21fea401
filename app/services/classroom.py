"""Classroom mode: one presenter tab, a room of tabs that follow it.

The server owns one :class:`Classroom` when it was started with a presenter token. A tab becomes the
presenter by typing the token (compared in constant time; wrong tokens are rate-limited per tab).
Every other tab follows by default: each state the presenter's tab commits, with the snapshot it
computed, is handed to the followers, which draw it without computing it again (one computation per
presenter change, not one per follower). The presenter's camera is relayed too. A follower can leave
("explore on my own") and come back; when the presenter's tab closes, followers keep the last state
and are told.

The classroom never touches viser: it calls the small :class:`Member` interface a session provides.
"""

from __future__ import annotations

import hmac
import secrets
import threading
import time
from collections.abc import Callable
from typing import Protocol

from ..core.role import Role
from ..core.snapshot import Snapshot
from ..core.state import LabState

__all__ = ["Classroom", "Member", "random_token", "TOKEN_TRIES", "TOKEN_WINDOW"]

TOKEN_TRIES = 5
"""Wrong tokens a tab may type per :data:`TOKEN_WINDOW` seconds; more are refused unread."""
TOKEN_WINDOW = 60.0
MAX_TOKEN_LENGTH = 200
PRESENTER_LEFT = "The presenter has left: you keep what was shown and can explore on your own."


def random_token() -> str:
    """A fresh presenter token: four short words' worth of randomness, easy to read out in a room."""
    return secrets.token_urlsafe(9)


class Member(Protocol):
    """What the classroom needs of a tab's session."""

    def subscribe(self, fn: Callable[[LabState, Snapshot], None]) -> Callable[[], None]: ...

    def mirror(self, state: LabState, snapshot: Snapshot, scene: tuple = ()) -> None: ...

    @property
    def scene_messages(self) -> tuple: ...

    def mirror_camera(self, position: tuple, look_at: tuple, up: tuple) -> None: ...

    def role_changed(self, role: Role) -> None: ...

    @property
    def latest(self) -> tuple[LabState, Snapshot | None]: ...


class Classroom:
    """The presenter and the followers of one server.

    Args:
        token: The presenter token (the server's ``--presenter-token``).
        clock: Monotonic clock [s] (a fake one in tests of the rate limit).
    """

    def __init__(self, token: str, clock: Callable[[], float] = time.monotonic) -> None:
        if not token or len(token) > MAX_TOKEN_LENGTH:
            raise ValueError(f"a presenter token needs 1 to {MAX_TOKEN_LENGTH} characters")
        self._token = token.encode("utf-8")
        self._clock = clock
        self._lock = threading.RLock()
        self._members: dict[int, Member] = {}
        self._alone: set[int] = set()  # tabs exploring on their own
        self._presenter: int | None = None
        self._unsubscribe: Callable[[], None] | None = None
        self._tries: dict[int, list[float]] = {}
        self.relayed = 0

    # ---------------------------------------------------------------- membership
    def join(self, key: int, member: Member) -> None:
        """A tab arrived: it follows the presenter, if there is one, from now on."""
        with self._lock:
            self._members[key] = member
            presenter = self._members.get(self._presenter) if self._presenter is not None else None
        if presenter is not None:
            state, snap = presenter.latest
            if snap is not None:
                member.mirror(state, snap)
        self._tell_all()

    def closed(self, key: int) -> None:
        """A tab closed: forget it; if it presented, the followers keep the last state and are told."""
        unsubscribe = None
        with self._lock:
            self._members.pop(key, None)
            self._alone.discard(key)
            self._tries.pop(key, None)
            was_presenter = key == self._presenter
            if was_presenter:
                unsubscribe = self._stop_relay()
        if unsubscribe is not None:  # never under our lock: it takes the session's
            unsubscribe()
        self._tell_all(PRESENTER_LEFT if was_presenter else "")

    # ---------------------------------------------------------------- the presenter
    def claim(self, key: int, token: str) -> str:
        """Make tab ``key`` the presenter if ``token`` is right.

        Returns:
            "" when it now presents, else why not (wrong token, too many tries).
        """
        now = self._clock()
        with self._lock:
            tries = [t for t in self._tries.get(key, []) if now - t < TOKEN_WINDOW]
            if len(tries) >= TOKEN_TRIES:
                wait = TOKEN_WINDOW - (now - tries[0])
                self._tries[key] = tries
                return f"too many wrong tokens: try again in {max(1, round(wait))} s"
            given = token.encode("utf-8")[: MAX_TOKEN_LENGTH * 4]
            if not hmac.compare_digest(given, self._token):
                tries.append(now)
                self._tries[key] = tries
                return "that is not the presenter token"
            self._tries.pop(key, None)
            member = self._members.get(key)
            if member is None:
                return "this tab is not connected"
            previous = self._stop_relay()
            self._presenter = key
            self._alone.discard(key)
        # Sessions' locks are taken outside ours only: a presenter's redraw holds its session's lock
        # and then asks for ours (to relay), so the other order would deadlock.
        if previous is not None:
            previous()
        unsubscribe: Callable[[], None] | None = member.subscribe(self._relay)
        with self._lock:
            if self._presenter == key and self._unsubscribe is None:
                self._unsubscribe, unsubscribe = unsubscribe, None
        if unsubscribe is not None:  # it was replaced meanwhile
            unsubscribe()
        state, snap = member.latest
        if snap is not None:
            self._relay(state, snap)
        self._tell_all()
        return ""

    def wrong_tries(self, key: int) -> int:
        """Wrong tokens tab ``key`` typed within the last :data:`TOKEN_WINDOW` seconds."""
        now = self._clock()
        with self._lock:
            return sum(1 for t in self._tries.get(key, []) if now - t < TOKEN_WINDOW)

    def resign(self, key: int) -> None:
        """The presenter stops presenting (followers keep the last state)."""
        with self._lock:
            if key != self._presenter:
                return
            unsubscribe = self._stop_relay()
        if unsubscribe is not None:
            unsubscribe()
        self._tell_all("The presenter stopped presenting: explore on your own.")

    def _stop_relay(self) -> Callable[[], None] | None:
        """No presenter any more (under our lock); returns the unsubscribe to call after releasing it."""
        unsubscribe, self._unsubscribe, self._presenter = self._unsubscribe, None, None
        return unsubscribe

    # ---------------------------------------------------------------- following
    def explore_alone(self, key: int) -> None:
        """Tab ``key`` stops following (its inputs are its own again)."""
        with self._lock:
            if key in self._members and key != self._presenter:
                self._alone.add(key)
        self._tell_all()

    def follow(self, key: int) -> None:
        """Tab ``key`` follows the presenter again (and jumps to what it shows)."""
        with self._lock:
            self._alone.discard(key)
            member = self._members.get(key)
            presenter = self._members.get(self._presenter) if self._presenter is not None else None
        if member is not None and presenter is not None:
            state, snap = presenter.latest
            if snap is not None:
                member.mirror(state, snap)
        self._tell_all()

    def role(self, key: int) -> Role:
        """What tab ``key`` is now."""
        with self._lock:
            presenter = self._presenter
            followers = self._following_keys()
        return Role(
            presenting=key == presenter,
            following=key in followers,
            presenter=presenter is not None,
            followers=len(followers),
        )

    def followers(self) -> int:
        """How many tabs follow the presenter."""
        with self._lock:
            return len(self._following_keys())

    def _following_keys(self) -> list[int]:
        if self._presenter is None:
            return []
        return [k for k in self._members if k != self._presenter and k not in self._alone]

    # ---------------------------------------------------------------- relays
    def _relay(self, state: LabState, snapshot: Snapshot) -> None:
        """The presenter committed ``state``: every follower draws it (no computation per follower:
        the presenter's snapshot, and the scene messages of the presenter's redraw replayed)."""
        with self._lock:
            targets = [self._members[k] for k in self._following_keys()]
            presenter = self._members.get(self._presenter) if self._presenter is not None else None
        scene = presenter.scene_messages if presenter is not None else ()
        for member in targets:
            member.mirror(state, snapshot, scene)
            self.relayed += 1

    def camera(self, key: int, position: tuple, look_at: tuple, up: tuple) -> None:
        """The presenter's camera moved: the followers' cameras follow."""
        with self._lock:
            if key != self._presenter:
                return
            targets = [self._members[k] for k in self._following_keys()]
        for member in targets:
            member.mirror_camera(position, look_at, up)

    def _tell_all(self, note: str = "") -> None:
        with self._lock:
            members = list(self._members.items())
        for key, member in members:
            role = self.role(key)
            member.role_changed(Role(**{**role.__dict__, "note": note if not role.presenting else ""}))
