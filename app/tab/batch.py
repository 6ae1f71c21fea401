"""One visit of the renderer to a tab: the queued messages made into one state to commit.

The session's loop takes a tab's queue in one go (:func:`coalesced` first drops drag events that a
later one supersedes) and folds it into a :class:`Batch`: reduced actions move the state (and say
whether the arm jumped, so the camera may follow); a presenter's :class:`~app.core.commands.Mirror`
replaces it with the presenter's state, snapshot and scene messages; a refused input or a
:class:`~app.core.commands.Redraw` forces a draw of the state as it is.
"""

from __future__ import annotations

from ..core.actions import Action, DriveTool
from ..core.commands import Message, Mirror
from ..core.reducer import reduce
from ..core.state import LabState
from .camera import is_jump

__all__ = ["Batch", "coalesced"]


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
        self._mirror: Mirror | None = None  # the presenter's last state, drawn as it is
        self._replay: list | None = []  # the presenter's scene messages, in order (None: draw our own)

    def take(self, action: Action) -> None:
        """Reduce ``action``."""
        before, self.state = self.state, reduce(self.state, action)
        self.jump = self.jump or is_jump(before, self.state, action)

    def take_mirror(self, mirror: Mirror, has_scene: bool) -> None:
        """Take the presenter's state (``has_scene``: this tab has a scene to replay messages into)."""
        self.state, self._mirror, self.jump = mirror.state, mirror, False  # the camera is the presenter's
        if self._replay is not None and mirror.scene and has_scene:
            self._replay.extend(mirror.scene)
        else:
            self._replay = None

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
