"""One visit of the renderer to a tab: the queued messages made into one state to commit.

The session's loop takes a tab's queue in one go (:func:`coalesced` first drops drag events that a
later one supersedes) and folds it into a :class:`Batch`: reduced actions move the state (and say
whether the arm jumped, so the camera may follow); a presenter's :class:`~app.core.commands.Mirror`
replaces it with the presenter's state, snapshot and scene messages; a refused input or a
:class:`~app.core.commands.Redraw` forces a draw of the state as it is.
"""

from __future__ import annotations

import threading
import time
from typing import Any

from ..core.actions import Action, DriveTool
from ..core.commands import Message, Mirror
from ..core.reducer import reduce
from ..core.state import LabState
from ..services.scene_slot import SceneSlot
from .camera import is_jump

__all__ = ["Batch", "coalesced", "VisitPace", "Queued", "MAX_REDRAWS_PER_SECOND"]


class Batch:
    """What one visit made of the queued messages: the state to commit and how to draw it.

    Attributes:
        state: The state after the messages taken so far.
        jump: Whether an action moved the arm far at once.
        force: Draw even if the state did not change.
        symbolic: A symbolic result still wanted arrived (drawn even without a commit).
    """

    def __init__(self, state: LabState) -> None:
        self.state, self.jump, self.force, self.symbolic = state, False, False, False
        self.question = False  # the room's question changed for this tab: its box is drawn
        self._mirror: Mirror | None = None  # the presenter's last state, drawn as it is
        self._replay: list | None = []  # the presenter's scene messages, in order (None: draw our own)
        self.lead: SceneSlot | None = None  # a relayed state's slot this tab's own drawing fills
        self.placed: list = []  # label placements in the drawing on screen, replayed once committed

    def take(self, action: Action) -> None:
        """Reduce ``action``."""
        before, self.state = self.state, reduce(self.state, action)
        self.jump = self.jump or is_jump(before, self.state, action)

    def take_mirror(self, mirror: Mirror, has_scene: bool, look: str = "") -> None:
        """Take the presenter's state (``has_scene``: this tab has a scene to replay messages into;
        ``look``: the tab's language and screen, :meth:`~app.tab.screen.Screen.look`, for a relayed
        state's shared scene)."""
        before = self.state
        self.state, self._mirror, self.jump = mirror.state, mirror, False  # the camera is the presenter's
        scene, self.lead = mirror.scene, None
        if not scene and isinstance(mirror.shared, SceneSlot):
            scene = mirror.shared.get(look, before)  # drawn by another follower over what we show
            if not scene and mirror.shared.wanted(look):
                self.lead = mirror.shared  # nobody has: our own drawing is left for the others
        if self._replay is not None and scene and has_scene:
            self._replay.extend(scene)
        else:
            self._replay = None

    def take_placed(self, placed: Any) -> None:
        """Labels placed again (:class:`app.tab.labels.Placement`) in the drawing of ``placed.state``: right
        after its scene messages if this batch replays them, else once the batch is committed."""
        if self._mirror is not None and self._mirror.state is placed.state and self._replay:
            self._replay.extend(placed.messages)
        else:
            self.placed.append(placed)

    def mirror_shared(self) -> object:
        """The relayed state's slot when the state to commit is the presenter's, else None."""
        if self._mirror is None or self._mirror.state is not self.state:
            return None
        return self._mirror.shared

    def mirrored(self) -> tuple[object, list | None]:
        """The presenter's snapshot and scene messages when the state to commit is the presenter's
        (else ``None``: the tab computes and draws its own)."""
        if self._mirror is None or self._mirror.state is not self.state:
            return None, None
        return self._mirror.snapshot, self._replay or None


def coalesced(messages: list[Message]) -> list[Message]:
    """``messages`` without drag events that a later one in the same batch supersedes (IK is solved
    once, for the latest pose of the handle)."""
    return [
        a
        for a, b in zip(messages, [*messages[1:], None], strict=True)
        if not (isinstance(a, DriveTool) and isinstance(b, DriveTool))
    ]


MAX_REDRAWS_PER_SECOND = 40.0
"""A tab is redrawn at most this often; faster input is coalesced (all of it is reduced, drawn once)."""
COST_SHARE = 4.0
"""After a visit that took t seconds of CPU (over :data:`COSTLY`), a tab waits COST_SHARE · t before
the next: a slider redraw of a few ms is not held back; rebuilding a large robot over and over takes
at most 1/(1 + COST_SHARE) of the renderer."""
COSTLY = 0.02
"""A visit taking more CPU than this [s] (a robot rebuilt, not a redraw) delays the tab's next."""


class VisitPace:
    """When a tab may be visited again: at most :data:`MAX_REDRAWS_PER_SECOND`, and a tab whose last
    visit was costly waits :data:`COST_SHARE` times that cost, so that no tab takes more than a fair
    share of the one renderer whatever its input asks for. Costs are the visiting thread's CPU time
    (not time spent waiting for other tabs)."""

    def __init__(self) -> None:
        self._last_redraw = 0.0
        self._cost = 0.0
        self._started = 0.0

    def start(self) -> None:
        self._started = time.thread_time()

    def finish(self) -> None:
        cost = time.thread_time() - self._started
        self._cost = min(cost, 1.0) if cost > COSTLY else 0.0

    def redrawn(self) -> None:
        self._last_redraw = time.monotonic()

    def next_visit(self) -> float:
        """[monotonic s]"""
        return self._last_redraw + max(1.0 / MAX_REDRAWS_PER_SECOND, COST_SHARE * self._cost)


class Queued:
    """What a tab's queue tells (the queue is :class:`~app.tab.session.ClientSession`'s)."""

    _queue_lock: threading.Lock
    _scheduled: bool
    _queue: list
    client: Any

    @property
    def pending(self) -> bool:
        """Whether messages of this tab wait for, or are in, the renderer's visit."""
        with self._queue_lock:
            return self._scheduled

    @property
    def queued(self) -> int:
        """How many messages wait to be taken."""
        with self._queue_lock:
            return len(self._queue)

    def settle(self, timeout: float = 10.0) -> None:
        """Wait until every dispatched message has been drawn (for tests and scripts).

        Raises:
            TimeoutError: messages are still queued after ``timeout`` seconds.
        """
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with self._queue_lock:
                if not self._scheduled and not self._queue:
                    return
            time.sleep(0.005)
        raise TimeoutError(f"client {self.client.client_id}: actions still queued after {timeout} s")
