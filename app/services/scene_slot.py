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
