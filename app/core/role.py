"""A tab's place in the classroom, as a frozen value (told by :class:`app.services.classroom.Classroom`,
shown by the views)."""

from __future__ import annotations

from dataclasses import dataclass

from .poll import Seen

__all__ = ["Role"]


@dataclass(frozen=True)
class Role:
    """What one tab is in the classroom.

    Attributes:
        presenting: This tab is the presenter.
        following: This tab mirrors the presenter (its inputs are read-only).
        presenter: Whether any tab presents.
        followers: How many tabs follow (told to the presenter).
        asked: This tab presents and another tab asks it to hand over.
        waiting: This tab typed the token and waits for the presenter to hand over.
        note: A sentence for this tab ("the presenter has left", ...), "" when none.
        question: The room's question as this tab shows it (:mod:`app.core.poll`), or None.
    """

    presenting: bool = False
    following: bool = False
    presenter: bool = False
    followers: int = 0
    asked: bool = False
    waiting: bool = False
    note: str = ""
    question: Seen | None = None
