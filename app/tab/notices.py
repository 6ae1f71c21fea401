"""What one tab is told in words: short notices, failures, and notes while something is prepared.

Every notice goes to this tab only (viser's per-client notifications), is cut to a readable length,
and never raises: a tab that has gone, or a notification that cannot be sent, costs nothing.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Callable
from typing import Any

from kinematics.text import fill

from ..core.i18n import Translator, translations

__all__ = ["Notices"]

log = logging.getLogger(__name__)

_LONGEST = 300
"""Characters of a message shown (and logged) at most."""


class Notices:
    """The notices of one tab.

    Args:
        client: The tab's viser client (``add_notification``).
        closed: Whether the tab has gone (nothing is shown then).

    Attributes:
        errors: Number of failures shown to this tab.
        tr: The tab's language (the session keeps it current): callers take their words from it.
    """

    def __init__(self, client: Any, closed: Callable[[], bool]) -> None:
        self.client = client
        self.tr: Translator = translations()
        self._closed = closed
        self.errors = 0

    def notify(self, title: str, body: str, seconds: float = 8.0) -> None:
        """Show this tab a short notice (e.g. the symbolic worker was restarted)."""
        if self._closed():
            return
        with contextlib.suppress(Exception):
            self.client.add_notification(title, body[:_LONGEST], color="yellow", auto_close_seconds=seconds)

    def error(self, exc: BaseException) -> None:
        """Log ``exc`` and tell this tab, in words, that its last action failed."""
        self.errors += 1
        log.error("client %s: %s", self.client.client_id, str(exc)[:_LONGEST])
        with contextlib.suppress(Exception):
            self.client.add_notification(
                self.tr.gettext("That did not work"),
                f"{type(exc).__name__}: {_said(exc, self.tr)[:_LONGEST]}",
                color="red",
                auto_close_seconds=10.0,
            )

    def preparing(self, title: str, body: str) -> Callable[[], None]:
        """Show a note while something is prepared away from the drawing thread; returns its remover."""
        note = self.client.add_notification(title, body, loading=True, with_close_button=False)

        def remove() -> None:
            with contextlib.suppress(Exception):
                note.remove()

        return remove


def _said(exc: BaseException, tr: Translator) -> str:
    """``exc``'s message in ``tr``'s language when it is a :func:`kinematics.text.words` sentence (one of
    the catalogs'), else as it is (the library's English details). Its arguments are file names and
    pieces of a file, written as they are (no decimal comma put into ``$(optenv X 0.1)``)."""
    text = exc.args[0] if len(exc.args) == 1 else None
    msgid = getattr(text, "msgid", None)
    if not msgid:
        return str(exc)
    return fill(tr.gettext(msgid), **dict(getattr(text, "args", ())))
