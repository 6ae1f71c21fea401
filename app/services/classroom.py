"""Classroom mode: one presenter tab, a room of tabs that follow it.

The server owns one :class:`Classroom` when it was started with a presenter token, which a tab types to
present (compared in constant time; wrong tries limited per connection, :data:`TOKEN_TRIES`, never per
address nor room-wide, so no tab locks another out: ``docs/security.md``). A right token typed while
another tab presents asks that tab, and presents only if it hands over (a reconnect key, which only the
presenter's browser has, takes over at once); the room is told. Every other tab follows by default: each
state the presenter commits, with its snapshot, is handed to the followers, which draw it without
computing it again; its camera and label placements follow too. A follower can explore on its own and
come back; when the presenter's tab closes, followers keep the last state and are told. Questions:
:mod:`app.services.question_desk`. The classroom calls the :class:`Member` a session provides, never viser.
"""

from __future__ import annotations

import hmac
import logging
import secrets
import threading
import time
from collections.abc import Callable
from dataclasses import replace

from ..core.i18n import N_
from ..core.role import Role
from ..core.snapshot import Snapshot
from ..core.state import LabState
from .member import Member
from .presenter_token import (
    MAX_TOKEN_LENGTH,
    RANDOM_TOKEN_BYTES,
    TOKEN_TRIES,
    presenter_link,
    random_token,
    token_weakness,
)
from .question_desk import QuestionDesk
from .scene_slot import SceneSlot

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
    "MAX_TOKEN_LENGTH",
    "ASKED",
    "WAITING",
    "KEPT",
    "HANDED_OVER",
    "HANDED_OVER_ROOM",
]

log = logging.getLogger(__name__)

WRONG_TOKEN = N_("that is not the presenter token")
TOO_MANY_TRIES = "this tab has typed {tries} wrong tokens: reload the page to try again"
"""Said in a tab's language by :meth:`app.tab.following.Following` (a plural of ``tries``)."""
TAKEN_OVER = N_("Another tab took over as presenter: this tab now follows it.")
# A hand-over: a right token typed while another tab presents asks that tab first.
ASKED = N_("Another tab typed the presenter token and asks to present.")
WAITING = N_("The presenting tab was asked to hand over: this tab presents as soon as it agrees.")
KEPT = N_("The presenting tab kept presenting.")
HANDED_OVER = N_("You handed over: this tab now follows the new presenter.")
HANDED_OVER_ROOM = N_("The presenter handed the lecture over to another tab.")
RESUME_GRACE = 120.0
"""A presenter whose tab closed (a reload, a lost connection) may come back this long [s] with its
reconnect key, and keeps its role and its state; the followers follow it again."""
PRESENTER_AWAY = N_(
    "The presenter's connection dropped: you keep what was shown, and follow again when it is back."
)


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
        self._asking: int | None = None  # the tab that typed the token and waits for the presenter
        self.questions = QuestionDesk(self, clock)

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
            if key == self._asking:  # the asking tab closed: its request is withdrawn
                self._asking = None
            if was_presenter:
                self._asking = None  # dropped: a right token now presents at once
                unsubscribe = self._stop_relay()
                self._resume_until = self._clock() + RESUME_GRACE  # it may come back with its key
        if unsubscribe is not None:  # never under our lock: it takes the session's
            unsubscribe()
        self._tell_all(PRESENTER_AWAY if was_presenter else "")

    # ---------------------------------------------------------------- the presenter
    def claim(self, key: int, token: str) -> str:
        """Make tab ``key`` the presenter if ``token`` is right.

        A right token while another tab presents and is connected asks that tab to hand over
        (:data:`WAITING` is returned; a newer request replaces an older one).

        Returns:
            "" when it now presents, :data:`WAITING` when the presenter was asked, else why not (wrong
            token, too many tries from this tab).
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
            presenter = self._presenter
            if presenter not in (None, key):
                self._asking = key
            else:
                self._resume_key, self._resume_until, self._last = secrets.token_urlsafe(24), None, None
        if presenter is not None and presenter != key:
            self._tell_all(personal={presenter: ASKED, key: WAITING})
            return WAITING
        self._present(key, None)
        return ""

    def answer(self, key: int, accept: bool) -> None:
        """The presenting tab ``key`` answers the request to hand over: the asking tab presents
        (``accept``) or is told the presenter kept presenting. Any other tab's answer changes nothing."""
        with self._lock:
            claimant = self._asking
            if key != self._presenter or claimant is None:
                return
            self._asking = None
            if accept:
                self._resume_key, self._resume_until, self._last = secrets.token_urlsafe(24), None, None
        if accept:
            self._present(claimant, None, handover=True)
        else:
            self._tell_all(personal={claimant: KEPT})

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
            last, self._resume_until, self._asking = self._last, None, None
        self._present(key, last)
        return last

    def resume_key(self, key: int) -> str:
        """The reconnect key of tab ``key`` if it presents (its page keeps it), else ""."""
        with self._lock:
            return self._resume_key if key == self._presenter else ""

    def _present(self, key: int, restore: tuple[LabState, Snapshot] | None, handover: bool = False) -> None:
        """Make tab ``key`` the presenter; relay what it shows (or ``restore``: what it showed before).
        ``handover``: the presenter agreed (it and the room are told so)."""
        with self._lock:
            member = self._members[key]
            replaced = self._presenter if self._presenter not in (key, None) else None
            previous = self._stop_relay()
            self._presenter = key
            self._alone.discard(key)
            if self._asking == key:
                self._asking = None
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
        self._tell_replaced(replaced, handover)

    def _tell_replaced(self, replaced: int | None, handover: bool) -> None:
        """Tell every tab its new role: the replaced presenter why, the room a hand-over."""
        said = HANDED_OVER if handover else TAKEN_OVER
        self._tell_all(
            HANDED_OVER_ROOM if handover else "", {replaced: said} if replaced is not None else None
        )

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
            self._asking = None
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
            asked, waiting = key == presenter and self._is_asked(), key == self._asking
        role = Role(
            presenting=key == presenter, following=key in followers, presenter=anyone, followers=count
        )
        return replace(role, asked=asked, waiting=waiting)

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

    def _is_asked(self) -> bool:
        """Whether this process's presenter has a request to hand over."""
        return self._asking is not None

    def _following_keys(self, but: int | None = None) -> list[int]:
        if not self._someone_presents():
            return []
        return [k for k in self._members if k not in (self._presenter, but) and k not in self._alone]

    # ---------------------------------------------------------------- relays
    def _relay(self, state: LabState, snapshot: Snapshot) -> None:
        """The presenter committed ``state``: every follower draws it with the presenter's snapshot and
        replays the presenter's scene messages (another look's: those the first of its look drew)."""
        with self._lock:
            targets = [self._members[k] for k in self._following_keys()]
            presenter = self._members.get(self._presenter) if self._presenter is not None else None
            self._last = (state, snapshot)
        scene, slot = presenter.scene_messages if presenter is not None else (), SceneSlot()
        for member in targets:
            member.mirror(state, snapshot, scene, slot)
            self.relayed += 1

    def camera(self, key: int, position: tuple, look_at: tuple, up: tuple) -> None:
        """The presenter's camera moved: the followers' cameras follow."""
        with self._lock:
            targets = [self._members[k] for k in self._following_keys()] if key == self._presenter else []
        for member in targets:
            member.mirror_camera(position, look_at, up)

    def labels(self, key: int, placed: object) -> None:
        """Tab ``key`` placed the labels of a drawing others replay: the followers showing it follow."""
        with self._lock:
            targets = [self._members[k] for k in self._following_keys(but=key)]
        for member in targets:
            member.mirror_labels(placed)

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
        """Tell every tab its role, with its own note in ``personal``, else ``note`` unless it presents."""
        personal = personal or {}
        with self._lock:  # computed and told in one go: two tells at once never leave a stale role last
            for key, member in list(self._members.items()):
                role = self.role(key)
                said = personal[key] if key in personal else note if not role.presenting else ""
                member.role_changed(Role(**{**role.__dict__, "note": said}))
