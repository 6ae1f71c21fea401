"""What the classroom (:mod:`app.services.classroom`) needs of a tab's session: its
:class:`~app.tab.following.Following` provides it."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from ..core.role import Role
from ..core.snapshot import Snapshot
from ..core.state import LabState

__all__ = ["Member"]


class Member(Protocol):
    """What the classroom needs of a tab's session."""

    def subscribe(self, fn: Callable[[LabState, Snapshot], None]) -> Callable[[], None]: ...

    def mirror(
        self, state: LabState, snapshot: Snapshot, scene: tuple = (), shared: object = None
    ) -> None: ...

    @property
    def scene_messages(self) -> tuple: ...

    def mirror_camera(self, position: tuple, look_at: tuple, up: tuple) -> None: ...

    def mirror_labels(self, placed: object) -> None: ...

    def mirror_tab(self, label: str) -> None: ...

    def role_changed(self, role: Role) -> None: ...

    @property
    def latest(self) -> tuple[LabState, Snapshot | None]: ...
