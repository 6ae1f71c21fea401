"""Classroom mode: one presenter tab, a room of tabs that follow it.

The server owns one :class:`Classroom` when it was started with a presenter token. A tab becomes the
presenter by typing the token (compared in constant time). Wrong tokens are limited per connection
(:data:`TOKEN_TRIES`), never per address nor for the whole room, so no tab can lock another out: a wrong
guess never refuses the right token typed in another tab (``docs/security.md`` has the arithmetic that
keeps guessing hopeless). A presenter that another tab replaces is told.
Every other tab follows by default: each state the presenter's tab commits, with the snapshot it
computed, is handed to the followers, which draw it without computing it again (one computation per
presenter change, not one per follower). The presenter's camera is relayed too. A follower can leave
("explore on my own") and come back; when the presenter's tab closes, followers keep the last state
and are told.

The classroom never touches viser: it calls the small :class:`Member` interface a session provides.
"""

from __future__ import annotations

import hmac
import logging
import math
import secrets
import threading
import time
import urllib.parse
from collections.abc import Callable
from typing import Protocol

from ..core.i18n import N_
from ..core.role import Role
from ..core.snapshot import Snapshot
from ..core.state import LabState

__all__ = [
    "Classroom",
    "Member",
    "presenter_link",
    "random_token",
    "token_weakness",
    "TOKEN_TRIES",
    "RANDOM_TOKEN_BYTES",
    "RESUME_GRACE",
    "PRESENTER_AWAY",
    "WRONG_TOKEN",
    "TOO_MANY_TRIES",
]

log = logging.getLogger(__name__)

TOKEN_TRIES = 5
"""Wrong tokens one connection (a tab, until it reloads) may type; its later tries are refused unread.
Counted per connection only: no address, and no room-wide count, so no tab can lock another out."""
RANDOM_TOKEN_BYTES = 16
"""Random bytes of the token ``--presenter`` alone makes: 128 bits, out of reach of guessing at any rate."""
STRONG_BITS = 64
"""A token given by hand with less estimated randomness than this [bits] is warned about."""
WRONG_TOKEN = N_("that is not the presenter token")
TOO_MANY_TRIES = "this tab has typed {tries} wrong tokens: reload the page to try again"
"""Said in a tab's language by :meth:`app.tab.following.Following` (a plural of ``tries``)."""
TAKEN_OVER = N_("Another tab took over as presenter: this tab now follows it.")
MAX_TOKEN_LENGTH = 200
RESUME_GRACE = 120.0
"""A presenter whose tab closed (a reload, a lost connection) may come back this long [s] with its
reconnect key, and keeps its role and its state; the followers follow it again."""
PRESENTER_AWAY = N_(
    "The presenter's connection dropped: you keep what was shown, and follow again when it is back."
)


def random_token() -> str:
    """A fresh presenter token: 128 random bits in 22 URL-safe characters (never typed on the projector:
    ``serve`` prints a presenter link that fills it in)."""
    return secrets.token_urlsafe(RANDOM_TOKEN_BYTES)


def presenter_link(url: str, token: str) -> str:
    """The presenter link ``serve`` prints, for the lab at ``url`` (``http://host:port``), by every path
    (one process or workers): ``url/?presenter=TOKEN``. In the query, never the fragment: viser's page
    opens its websocket at its own address minus the query, and a WebSocket address with a fragment is
    refused (the page would never connect). The page's script drops it from the address bar."""
    return f"{url.rstrip('/')}/?presenter={urllib.parse.quote(token, safe='')}"


def token_weakness(token: str) -> str:
    """Why ``token`` is easy to guess (short, or little randomness for its characters), or ``""``.

    The estimate is generous (length × log₂ of the character classes used): a dictionary word with a
    digit (``lecture-7``) is weak; :func:`random_token`'s are strong.
    """
    pool = sum(
        size
        for size, present in (
            (26, any(c.islower() for c in token)),
            (26, any(c.isupper() for c in token)),
            (10, any(c.isdigit() for c in token)),
            (33, any(not c.isalnum() for c in token)),
        )
        if present
    )
    bits = len(token) * math.log2(max(pool, 2))
    if len(token) < 12 or bits < STRONG_BITS:
        return (
            f"the presenter token {len(token)} characters long is easy to guess (about {bits:.0f} bits; "
            f"use at least {STRONG_BITS}, or --presenter alone for a random one)"
        )
    return ""


class Member(Protocol):
    """What the classroom needs of a tab's session."""

    def subscribe(self, fn: Callable[[LabState, Snapshot], None]) -> Callable[[], None]: ...

    def mirror(
        self, state: LabState, snapshot: Snapshot, scene: tuple = (), shared: object = None
    ) -> None: ...

    @property
    def scene_messages(self) -> tuple: ...

    def mirror_camera(self, position: tuple, look_at: tuple, up: tuple) -> None: ...

    def mirror_tab(self, label: str) -> None: ...

    def role_changed(self, role: Role) -> None: ...

    @property
    def latest(self) -> tuple[LabState, Snapshot | None]: ...


class Classroom:
    """The presenter and the followers of one server.

    Args:
        token: The presenter token (the server's ``--presenter-token``).
        clock: Monotonic clock [s] (a fake one in tests of the reconnect grace).
        address_of: A tab's network address, for the log of wrong tokens (its key is used when
            ``None``, or when unknown).
    """

    def __init__(
        self,
        token: str,
        clock: Callable[[], float] = time.monotonic,
        address_of: Callable[[int], str] | None = None,
    ) -> None:
        if not token or len(token) > MAX_TOKEN_LENGTH:
            raise ValueError(f"a presenter token needs 1 to {MAX_TOKEN_LENGTH} characters")
        self._token = token.encode("utf-8")
        self._clock = clock
        self._lock = threading.RLock()
        self._members: dict[int, Member] = {}
        self._alone: set[int] = set()  # tabs exploring on their own
        self._wrong: dict[int, int] = {}  # wrong tokens of each connected tab (forgotten when it closes)
        self._presenter: int | None = None
        self._unsubscribe: Callable[[], None] | None = None
        self._address_of = address_of
        self.relayed = 0
        # Reconnection: a random key per presenter (never the token), the last state it showed, and
        # until when a closed presenter may come back; the tab it has open.
        self._resume_key = ""
        self._resume_until: float | None = None
        self._last: tuple[LabState, Snapshot] | None = None
        self._tab = ""

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
            if self._tab:
                member.mirror_tab(self._tab)
        self._tell_all()

    def closed(self, key: int) -> None:
        """A tab closed: forget it; if it presented, the followers keep the last state and are told."""
        unsubscribe = None
        with self._lock:
            self._members.pop(key, None)
            self._alone.discard(key)
            self._wrong.pop(key, None)
            was_presenter = key == self._presenter
            if was_presenter:
                unsubscribe = self._stop_relay()
                self._resume_until = self._clock() + RESUME_GRACE  # it may come back with its key
        if unsubscribe is not None:  # never under our lock: it takes the session's
            unsubscribe()
        self._tell_all(PRESENTER_AWAY if was_presenter else "")

    # ---------------------------------------------------------------- the presenter
    def claim(self, key: int, token: str) -> str:
        """Make tab ``key`` the presenter if ``token`` is right.

        Returns:
            "" when it now presents, else why not (wrong token, too many tries from this tab).
        """
        why = self._spent(key)
        if why:
            return why
        given = token.encode("utf-8")[: MAX_TOKEN_LENGTH * 4]
        if not hmac.compare_digest(given, self._token):
            return self._wrong_try(key)
        with self._lock:
            if key not in self._members:
                return N_("this tab is not connected")
            self._resume_key, self._resume_until, self._last = secrets.token_urlsafe(24), None, None
        self._present(key, None)
        return ""

    def resume(self, key: int, resume_key: str) -> tuple[LabState, Snapshot] | None | bool:
        """Tab ``key`` comes back with the presenter's reconnect key (a reload, a lost connection, a new
        tab of the same browser): it presents again, without the token, if the key is the current one
        and the presenter is still connected or closed less than :data:`RESUME_GRACE` ago.

        Returns:
            False when refused; else the state and snapshot the presenter last showed, for the tab to
            take over (``None`` when there is none).
        """
        with self._lock:
            current = self._resume_key
            fresh = self._presenter is not None or (
                self._resume_until is not None and self._clock() <= self._resume_until
            )
            ok = bool(current) and fresh and hmac.compare_digest(resume_key.encode(), current.encode())
            if not ok or key not in self._members:
                return False
            last, self._resume_until = self._last, None
        self._present(key, last)
        return last

    def resume_key(self, key: int) -> str:
        """The reconnect key of tab ``key`` if it presents (its page keeps it), else ""."""
        with self._lock:
            return self._resume_key if key == self._presenter else ""

    def _present(self, key: int, restore: tuple[LabState, Snapshot] | None) -> None:
        """Make tab ``key`` the presenter; relay what it shows (or ``restore``: what it showed before)."""
        with self._lock:
            member = self._members[key]
            replaced = self._presenter if self._presenter not in (key, None) else None
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
        if restore is not None:
            member.mirror(*restore)  # the tab takes over the state; its commit is relayed
        else:
            state, snap = member.latest
            if snap is not None:
                self._relay(state, snap)
        self._tell_all(personal={replaced: TAKEN_OVER} if replaced is not None else None)

    def address(self, key: int) -> str:
        """The network address of tab ``key``, for the log (never what tries are counted by)."""
        address = self._address_of(key) if self._address_of is not None else ""
        return address or f"tab {key}"

    def wrong_tries(self, key: int) -> int:
        """Wrong tokens tab ``key`` typed on its connection."""
        with self._lock:
            return self._wrong.get(key, 0)

    def _spent(self, key: int) -> str:
        """Why tab ``key`` may not try a token any more (it typed :data:`TOKEN_TRIES` wrong ones), or ""."""
        tries = self.wrong_tries(key)
        return TOO_MANY_TRIES.format(tries=tries) if tries >= TOKEN_TRIES else ""

    def _wrong_try(self, key: int) -> str:
        """Tab ``key`` typed a wrong token: count it for its connection (only), log it, say so."""
        with self._lock:
            tries = self._wrong.get(key, 0) + 1
            if key in self._members:  # a closed tab's count would never be forgotten
                self._wrong[key] = tries
        address = self.address(key)
        log.warning("wrong presenter token from tab %d at %s (%d of %d)", key, address, tries, TOKEN_TRIES)
        return WRONG_TOKEN

    def resign(self, key: int) -> None:
        """The presenter stops presenting (followers keep the last state)."""
        with self._lock:
            if key != self._presenter:
                return
            unsubscribe = self._stop_relay()
            self._resume_key, self._resume_until, self._last, self._tab = "", None, None, ""
        if unsubscribe is not None:
            unsubscribe()
        self._tell_all(N_("The presenter stopped presenting: explore on your own."))

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
            if self._tab:
                member.mirror_tab(self._tab)
        self._tell_all()

    def role(self, key: int) -> Role:
        """What tab ``key`` is now."""
        with self._lock:
            presenter = self._presenter
            followers = self._following_keys()
            anyone = self._someone_presents()
            count = self._room_followers(len(followers))
        following = key in followers
        return Role(presenting=key == presenter, following=following, presenter=anyone, followers=count)

    def followers(self) -> int:
        """How many tabs follow the presenter (in the whole room)."""
        with self._lock:
            return self._room_followers(len(self._following_keys()))

    # The seam of a room spread over several processes (:mod:`app.services.classroom_relay`): whether
    # a tab presents (here or elsewhere), and the room's followers given this process's.
    def _someone_presents(self) -> bool:
        return self._presenter is not None

    def _room_followers(self, here: int) -> int:
        return here

    def _following_keys(self) -> list[int]:
        if not self._someone_presents():
            return []
        return [k for k in self._members if k != self._presenter and k not in self._alone]

    # ---------------------------------------------------------------- relays
    def _relay(self, state: LabState, snapshot: Snapshot) -> None:
        """The presenter committed ``state``: every follower draws it (no computation per follower:
        the presenter's snapshot, and the scene messages of the presenter's redraw replayed)."""
        with self._lock:
            targets = [self._members[k] for k in self._following_keys()]
            presenter = self._members.get(self._presenter) if self._presenter is not None else None
            self._last = (state, snapshot)
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

    def tab(self, key: int, label: str) -> None:
        """The presenter opened the tab ``label``: the followers open it too."""
        with self._lock:
            if key != self._presenter:
                return
            self._tab = label
            targets = [self._members[k] for k in self._following_keys()]
        for member in targets:
            member.mirror_tab(label)

    def _tell_all(self, note: str = "", personal: dict[int, str] | None = None) -> None:
        """Tell every tab its role, with ``note`` (or its own note in ``personal``) unless it presents."""
        with self._lock:
            members = list(self._members.items())
        for key, member in members:
            role = self.role(key)
            said = (personal or {}).get(key, note)
            member.role_changed(Role(**{**role.__dict__, "note": said if not role.presenting else ""}))
