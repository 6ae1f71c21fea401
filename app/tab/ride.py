"""One follower's frame for a relayed state, sent to the followers that showed the same before it.

In a worker, followers that show the same state, look, open tab and panel (:meth:`Riding.ride_key`: the
panels' digest, :mod:`app.viser_adapter.panel_ledger`) join the relayed state's
:class:`~app.services.scene_slot.SceneSlot` under that key (:meth:`app.tab.following.Following.mirror`).
The first is queued the state as before and draws it; its frame (its GUI updates and scene messages,
:class:`RideFrame`) is then sent as it is to the others that waited (:meth:`Riding.take_ride`: one entry
in each one's buffer, its elements set to match, no visit of the renderer, no panel drawn); one that
changed meanwhile is queued the state and draws its own.
"""

from __future__ import annotations

import contextlib
import logging
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..core.role import Role
from ..core.snapshot import Snapshot
from ..core.state import LabState
from ..services.scene_slot import SceneSlot
from ..viser_adapter import (
    SharedFrame,
    capture_frame,
    gui_digest,
    panel_after,
    panel_ledger_installed,
    ridden_frame,
    send_ridden,
)

__all__ = ["RideFrame", "Riding"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class RideFrame:
    """One follower's draw of ``state`` over ``base``, for the followers of ``key``.

    Attributes:
        slot: The relayed state's slot.
        key: What the followers it is for showed before (:meth:`~app.tab.session.ClientSession.ride_key`).
        base: The state shown before.
        state, snapshot: The state drawn and its snapshot.
        role: The drawing tab's classroom role (a follower of another role draws its own).
        frame: Its GUI updates and scene messages (:func:`~app.viser_adapter.ridden_frame`).
        look, live, hint: What its screen kept of the draw (:class:`~app.tab.screen.Screen`).
        panel: Its panel's digest after the draw, and the parts of the elements it updated
            (:func:`~app.viser_adapter.panel_after`).
    """

    slot: SceneSlot
    key: tuple
    base: LabState
    state: LabState
    snapshot: Snapshot
    role: Role
    frame: tuple[SharedFrame, ...]
    look: str
    live: str
    hint: str
    panel: tuple[int, dict[str, int]]


class Riding:
    """The riding side of :class:`~app.tab.session.ClientSession` (its attributes, declared here)."""

    client: Any
    lock: threading.RLock
    _queue_lock: threading.Lock
    _scheduled: bool
    _closed: bool
    state: LabState
    snapshot: Snapshot | None
    language: str
    _wanted_language: str
    redraws: int
    following: Any
    screen: Any
    page: Any
    recorder: Any
    symbols: Any
    pace: Any
    ticker: Any
    subscribers: Any
    _leading: list[tuple[SceneSlot, tuple]]
    _ridden: RideFrame | None
    rides: int

    if TYPE_CHECKING:  # the session's own (declared for the checker only)

        @property
        def role(self) -> Role: ...

        def dispatch(self, message: Any) -> None: ...

    def ride_key(self) -> tuple | None:
        """What a follower's frame for the next relayed state depends on: the state it shows, its look
        (:meth:`~app.tab.screen.Screen.look`), its open tab, whose scene its browser shows, and what its panel
        shows (:func:`~app.viser_adapter.gui_digest`); followers of one key can be sent one frame. None
        when this tab draws its own (it presents or explores, something waits in its queue, it records, its
        language changes)."""
        if self._closed or not self.following.following or not panel_ledger_installed():
            return None
        with self._queue_lock:
            if self._scheduled:
                return None
        return self._ride_parts()

    def _ride_parts(self, look: str | None = None) -> tuple | None:
        """The key of :meth:`ride_key` (``look``: taken as this tab's, not worked out again)."""
        screen = self.screen
        if screen.scene is None or self.recorder.recording or self._wanted_language != self.language:
            return None
        look = screen.look() if look is None else look
        return id(self.state), look, self.page.tab, screen.foreign, gui_digest(self.client)

    def leads(self, slot: SceneSlot, key: tuple) -> None:
        """This tab is the first of ``key`` to draw ``slot``'s state: its frame goes to the others."""
        with self._queue_lock:
            self._leading.append((slot, key))

    def _send_rides(self, leading: list[tuple[SceneSlot, tuple]]) -> None:
        """The followers that waited for this visit's frames: each is sent it, or, if it changed
        meanwhile (or this visit drew something else), is queued the state to draw its own."""
        ridden, self._ridden = self._ridden, None
        for slot, key in leading:
            frame = ridden if ridden is not None and ridden.slot is slot and ridden.key == key else None
            for rider, mirror in slot.finish(key):
                try:
                    if frame is not None and rider.take_ride(frame):
                        continue
                except Exception:  # never leave a follower without the state
                    log.exception("a follower could not take another's frame")
                rider.dispatch(mirror)

    def take_ride(self, ride: RideFrame) -> bool:
        """Show ``ride`` (a follower's frame for a state, drawn over what this tab shows: ride_key), as if
        this tab had drawn it; False, with nothing done, when this tab no longer shows the same."""
        if not self.lock.acquire(blocking=False):
            return False
        try:
            if self.state is not ride.base or self.role != ride.role or not self.following.following:
                return False
            with self._queue_lock:
                if self._scheduled or self._closed:
                    return False
            # Its look changes only with a message (queued: then it draws its own) or with its canvas,
            # whose next frame is drawn for the new one: the look is not worked out again per tab here.
            if self._ride_parts(look=ride.key[1]) != ride.key:
                return False
            if not send_ridden(self.client, ride.frame, ride.panel):
                return False
            old = self.state
            self.symbols.update(ride.state, old)
            self.screen.rode(ride.state, ride.look, ride.live, ride.hint)
            # Its page's address is not rewritten while it rides (a follower's reload follows the
            # presenter anyway): its window is then the same as every other rider's, compressed once.
            self.state, self.snapshot = ride.state, ride.snapshot
            self.redraws += 1
            self.rides += 1
            self.pace.redrawn()
            self.ticker.stop()
            self.subscribers.tell(ride.state, ride.snapshot)
            return True
        finally:
            self.lock.release()

    def _capture_ride(self, ride: tuple[SceneSlot, tuple] | None) -> contextlib.AbstractContextManager[list]:
        """What a draw queues, collected when it is ``ride``'s frame (else nothing is)."""
        return capture_frame(self.client) if ride is not None else contextlib.nullcontext([])

    def _let_go(self) -> None:
        """The tab has gone: those that wait for its frames draw their own."""
        with self._queue_lock:
            leading, self._leading = self._leading, []
        self._send_rides(leading)

    def _keep_ride(
        self, ride: tuple[SceneSlot, tuple], old: LabState, state: LabState, snap: Snapshot, captured: list
    ) -> None:
        """Keep this draw's frame (``captured``: what it queued) for the followers of ``ride``'s key."""
        frame = ridden_frame(captured)
        if frame is not None:
            self._ridden = RideFrame(
                ride[0], ride[1], old, state, snap, self.role, frame,
                self.screen.scene_messages.look, self.screen.live, self.screen.hint,
                panel_after(self.client, [m for part in frame for m in part.messages]),
            )  # fmt: skip
