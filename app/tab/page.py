"""One tab's page between connections: its address (robot, q, open tab), a presenter's reconnect
key, the open tab followed, and a heartbeat so that a lost connection is said in words.

:meth:`PageLink.take` reads the page's report (hostile input, :mod:`app.core.page_state`): on a
(re)connection it gives a presenter its role back (:meth:`app.services.classroom.Classroom.resume`)
or restores the address's robot and q; later it relays the tab the user opened when the tab
presents. :meth:`PageLink.update` writes the robot and q into the address after a commit (at most
every :data:`ADDRESS_EVERY` seconds, the last one always): while commits keep coming the write rides
in a commit's own frame; the last one is written :data:`TRAILING` s after it is due if no commit
wrote it by then. The page script is
:mod:`app.views.panel.page`.
"""

from __future__ import annotations

import json
import logging
import threading
import time
from collections.abc import Callable
from typing import Any

from ..core.actions import SetConfiguration
from ..core.commands import ChooseRobot, Message
from ..core.i18n import DEFAULT, LANGUAGES, Translator, is_language, negotiate, translations
from ..core.page_state import PageError, PageReport, checked_q, page_address, parse_report
from ..core.state import LabState
from ..services.later import Call, later
from ..views.panel import TAB_LABELS
from ..viser_adapter import run_javascript

__all__ = ["PageLink", "ADDRESS_EVERY", "BEAT_EVERY", "TAB_KEYS", "address_language"]

ADDRESS_EVERY = 0.4
"""The page's address is rewritten at most this often [s] (a dragged slider commits 30 times a second)."""
TRAILING = 0.25
"""A wanted address no commit has written is written this long [s] after it became due (a slider
moved every 200 ms writes it from its commits, in the frame the redraw is sent in anyway)."""
BEAT_EVERY = 2.0
"""The server tells the page it is there this often [s]; the page says "connection lost" after 7 s."""

log = logging.getLogger(__name__)

TAB_KEYS: dict[str, str] = {
    translations(lang.code).gettext(label): label for lang in LANGUAGES for label in TAB_LABELS
}
"""A tab's label in any language → its English label, the key the tab, its address and the classroom
keep (a follower in Spanish opens the tab a presenter in Portuguese opened)."""


class PageLink:
    """The page side of one tab.

    Args:
        client: The tab's viser client.
        dispatch: The session's way in.
        names: The robots this tab can show (names of its catalogue).
        load: Loads a robot of the catalogue by name.
        notify: Tells the tab something in words (title, body).
        closed: Whether the tab has gone.
        languages: Called with the address's language (``?lang=``, "" for none) and the browser's
            languages when the page (re)connects.

    Attributes:
        tr: The tab's language (the labels of its tabs in the page).
        lang: The language the tab chose itself (address or Language menu), kept in the address
            ("" when it speaks its browser's or the room's).
    """

    def __init__(
        self,
        client: Any,
        dispatch: Callable[[Message], None],
        names: Callable[[], list[str]],
        load: Callable[[str], Any],
        notify: Callable[[str, str], None],
        closed: Callable[[], bool],
        languages: Callable[[str, tuple[str, ...]], None] = lambda lang, browser: None,
    ) -> None:
        self.client, self._dispatch, self._names, self._load = client, dispatch, names, load
        self._languages = languages
        self.tr: Translator = translations()
        self.lang = ""
        self._notify, self._closed = notify, closed
        self.following: Any = None  # the tab's Following, set by the session
        self.address = ""  # the last address written into the page
        self.tab = ""  # the tab the page has open (as last reported)
        self.window: tuple[float, float, bool] | None = None  # its window (width, height, touch)
        self._wanted = ""
        self._written_at = 0.0
        self._loaded = False  # the address is written only once the page has told its own
        self._timer: Call | None = None
        self._lock = threading.Lock()
        self._beat()

    # ------------------------------------------------------------------ the page's report
    def take(self, text: str) -> None:
        """Read one report of the page and act on it (nothing trusted, every refusal in words)."""
        try:
            report = parse_report(text, tuple(TAB_KEYS))
        except PageError as exc:
            self._notify(self.tr.gettext("The page's address was not used"), str(exc))
            return
        if report.kind == "view":
            self.window = report.window or self.window
            return
        if report.tab:
            self.tab = TAB_KEYS[report.tab]
        elif report.kind == "load":
            self.tab = TAB_LABELS[0]  # a page opens on the first tab unless its address names one
        if report.kind == "tab":
            if self.following is not None:
                self.following.tab_opened(self.tab)
            return
        with self._lock:
            self._loaded = True
        self._languages(report.lang, report.browser)
        if (
            report.tab
        ):  # an address may name the tab in another language (a shared link): open it in this one's
            self.show_tab(self.tab)
        if report.resume and self.following is not None and self.following.resume(report.resume):
            return  # the presenter is back, with the state it showed
        if not self._restore(report):
            self._dispatch_address()  # else the restored state's commit writes it

    def _dispatch_address(self) -> None:
        """Write the wanted address now that the page has told its own (restores come after)."""
        with self._lock:
            pending = self._wanted and self._wanted != self.address and self._timer is None
        if pending:
            self._write()

    def _restore(self, report: PageReport) -> bool:
        """Dispatch the address's robot and q; True when something was dispatched."""
        if not report.robot:
            return False
        if report.robot not in self._names():
            _ = self.tr.gettext
            self._notify(
                _("The page's address was not used"),
                _(
                    "there is no robot “{robot}” in this lab (an upload or a Build-tab robot lives only "
                    "as long as its tab)"
                ).format(robot=report.robot[:60]),
            )
            return False
        self._dispatch(ChooseRobot(report.robot))
        if report.q is not None:
            try:
                q = checked_q(self._load(report.robot), report.q)
            except PageError as exc:
                self._notify(self.tr.gettext("The address's joint values were not used"), str(exc))
            else:
                self._dispatch(SetConfiguration(q))
        return True

    # ------------------------------------------------------------------ server → page
    def update(self, state: LabState) -> None:
        """Keep ``state``'s robot and q in the page's address (throttled; the last one always written)."""
        address = page_address(state.robot_name, list(state.q), self.lang)
        with self._lock:
            self._wanted = address
            if address == self.address or not self._loaded:
                return
            wait = self._written_at + ADDRESS_EVERY - time.monotonic()
            if wait > 0:
                if self._timer is None:
                    self._timer = later(wait + TRAILING, self._trailing)
                return
        self._write()

    def _trailing(self) -> None:
        """Write the wanted address unless a commit did; if one is still too recent, wait again."""
        with self._lock:
            self._timer = None
            if self._wanted == self.address:
                return
            wait = self._written_at + ADDRESS_EVERY - time.monotonic()
            if wait > 0:
                self._timer = later(wait + TRAILING, self._trailing)
                return
        self._write()

    def _write(self) -> None:
        with self._lock:
            if self._timer is not None:
                self._timer.cancel()
            self._timer = None
            address, self.address, self._written_at = self._wanted, self._wanted, time.monotonic()
        self._run(f"window.__jacobianLabPage && window.__jacobianLabPage.address({json.dumps(address)});")

    def remember(self, key: str) -> None:
        """Keep (or forget, ``""``) the presenter's reconnect key in the page's local storage."""
        self._run(f"window.__jacobianLabPage && window.__jacobianLabPage.remember({json.dumps(key)});")

    def show_tab(self, label: str) -> None:
        """Open the tab ``label`` in the page (a follower follows the presenter's)."""
        if label in TAB_LABELS:
            shown = json.dumps(self.tr.gettext(label))
            self._run(f"window.__jacobianLabPage && window.__jacobianLabPage.showTab({shown});")

    def _beat(self) -> None:
        if self._closed():
            return
        self._run("window.__jacobianLabBeat = Date.now();")
        later(BEAT_EVERY, self._beat)

    def _run(self, source: str) -> None:
        if self._closed():
            return
        try:
            run_javascript(self.client, source)
        except Exception:  # a tab that went away mid-send: nothing to tell
            log.debug("page script not sent to client %s", getattr(self.client, "client_id", "?"))

    def close(self) -> None:
        with self._lock:
            if self._timer is not None:
                self._timer.cancel()
                self._timer = None


def address_language(lang: str) -> tuple[str, tuple[str, str] | None]:
    """The language a page's address asks for (``?lang=``, non-empty) and, for one this lab does not speak,
    the notice (title, body) saying so: it is English then, said in English."""
    code = lang if is_language(lang) else negotiate([lang], default="")
    if code:
        return code, None
    return DEFAULT, (
        "Language not available",
        f"This lab does not speak “{lang[:40]}”: it speaks English here. "
        "Available: ?lang=en (English), pt (Português), es (Español), pl (Polski).",
    )
