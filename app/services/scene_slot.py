"""The scene of one relayed state, drawn by one follower of a worker and replayed to the others.

In a worker that does not hold the presenter (``serve --workers N --presenter``), the presenter's states
arrive as data and no tab of the worker has drawn them. The worker's classroom hands every follower the
state, its snapshot (computed once) and one :class:`SceneSlot`. The first follower to draw the state
draws its own scene and leaves the scene messages it sent in the slot, with the state its browser showed
before (its *base*) and its look (:meth:`app.tab.screen.Screen.look`: its language and the screen its
labels were placed for); every other follower whose browser shows that same base state, with that look,
replays them (re-addressed, :func:`app.viser_adapter.replay_scene`) instead of drawing
the scene again. A follower that shows something else (it joined late, it came back from exploring)
draws its own.

A follower's whole frame (its GUI updates and its scene) is shared too: followers that show the same
state, look, open tab and panel (:meth:`~app.tab.session.ClientSession.ride_key`: their panels' digest,
:mod:`app.viser_adapter.panel_ledger`) :meth:`join` the slot under that key; the first draws, the others
wait, and once it has drawn each of them is sent its frame as it is (no visit of the renderer, no panel
drawn: :meth:`~app.tab.session.ClientSession.take_ride`), or, if it changed meanwhile, draws its own.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence

__all__ = ["SceneSlot"]


class SceneSlot:
    """The scene messages of one state's first drawing, per look (empty until a follower draws it)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._made: dict[str, tuple[object, tuple]] = {}
        self._riders: dict[tuple, list | None] = {}  # per key: who waits for its lead's frame (None: sent)

    def get(self, look: str, base: object) -> tuple:
        """The scene messages drawn for ``look`` over ``base`` (the state shown before), or
        ``()``."""
        with self._lock:
            made = self._made.get(look)
        return made[1] if made is not None and made[0] is base else ()

    def wanted(self, look: str) -> bool:
        """Whether nobody has drawn it in ``look`` yet."""
        with self._lock:
            return look not in self._made

    def fill(self, look: str, base: object, messages: Sequence) -> None:
        """Keep the scene messages drawn in ``look`` over ``base`` (the first drawing only)."""
        if not messages:
            return
        with self._lock:
            self._made.setdefault(look, (base, tuple(messages)))

    # ---------------------------------------------------------------- a follower's whole frame, for others
    def join(self, key: tuple, rider: object) -> bool:
        """``rider`` shows what ``key`` says (its state, look, open tab and panel:
        ``ClientSession.ride_key``) before this state: True when it is the first of that key (it draws,
        and its frame is kept for the others: :meth:`finish`), False when it waits for that frame."""
        with self._lock:
            waiting = self._riders.get(key)
            if waiting is None:  # the first (or the frame of that key has gone out: draw your own)
                if key not in self._riders:
                    self._riders[key] = []
                return True
            waiting.append(rider)
            return False

    def finish(self, key: tuple) -> list:
        """The lead of ``key`` has drawn (or given up): the riders that waited for its frame."""
        with self._lock:
            waiting = self._riders.get(key) or []
            self._riders[key] = None
            return waiting
