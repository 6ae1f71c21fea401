"""The classroom controls of one tab (shown when the server runs with a presenter token).

A text input "Presenter token", masked like a password (typing the token makes this tab the presenter:
no other click; the presenter link ``serve`` prints, ``…/?presenter=TOKEN``, fills it in and drops the
token from the address bar, so it is never typed or shown where the room can read it), one
button that says what it does next ("Explore on my own", "Follow the presenter", "Stop presenting")
and a line saying what the tab is: presenting (and how many tabs follow), following (read-only),
or exploring alone. When another tab typed the token, the presenter's box unfolds with the request and
two buttons, "Hand over" and "Keep presenting"; the asking tab says it waits (its token box hidden).
"""

from __future__ import annotations

import html
import json

import viser

from ...core.commands import (
    AnswerHandover,
    ClaimPresenter,
    Command,
    ExploreAlone,
    FollowPresenter,
    StopPresenting,
)
from ...core.i18n import LANGUAGES, N_, Translator, translations
from ...core.role import Role
from .common import Dispatch, bind, bind_click, sync_value

__all__ = ["ClassroomPanel", "compact_title", "token_js", "classroom_words_js", "CLASSROOM"]

CLASSROOM = N_("Classroom")
"""The box's title; presenting or following, "<title> · <role>" (the layout script folds it)."""

_TOKEN_JS = """(() => {
  const uuid = %s;
  // The presenter link (…/?presenter=TOKEN; a fragment would stop viser's websocket): taken from the
  // address, or from the page script that took it first, and never left in the address bar.
  const fields = new URLSearchParams(location.search);
  if (fields.get("presenter")) window.__jacobianLabPresenter = fields.get("presenter");
  if (fields.has("presenter")) {
    fields.delete("presenter");
    const rest = fields.toString();
    history.replaceState(null, "", location.pathname + (rest ? "?" + rest : ""));
  }
  // The panel is built again when the page's language arrives (?lang=, the browser's languages): only
  // the newest box's script fills the token in; an older box that took it and went hands it back.
  window.__jacobianLabTokenBox = uuid;
  let filled = "";
  // viser gives the text input a generated id (its label is for the handle's uuid), and React may
  // render a new input (a folded and unfolded box): mask whatever input is there, for the page's life.
  setInterval(() => {
    const newest = window.__jacobianLabTokenBox === uuid;
    const label = document.querySelector(`label[for="${uuid}"]`);
    const row = label && label.closest(".mantine-Flex-root");
    const input = row && row.querySelector("input");
    if (!input) {
      if (filled && !newest) {
        window.__jacobianLabPresenter = filled;
        filled = "";
      }
      return;
    }
    if (input.type !== "password") {
      input.type = "password";
      input.autocomplete = "off";
      input.spellcheck = false;
      input.style.setProperty("-webkit-text-security", "disc");
    }
    const token = window.__jacobianLabPresenter;
    if (newest && token && !filled) {
      filled = token;
      window.__jacobianLabPresenter = null;
      const set = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
      set.call(input, token);
      input.dispatchEvent(new Event("input", {bubbles: true}));
    }
  }, 250);
})();"""


def classroom_words_js() -> str:
    """A page script naming the box's title in every language (the layout script folds the box whose
    title starts "<title> ·"; a page speaks one language at a time, and may change)."""
    words = sorted({translations(lang.code).gettext(CLASSROOM) for lang in LANGUAGES})
    return f"window.__jacobianLabClassroomWords = {json.dumps(words)};"


def token_js(uuid: str) -> str:
    """A page script masking the token input (DOM id ``uuid``) and filling it from the presenter link."""
    return _TOKEN_JS % json.dumps(uuid)


class ClassroomPanel:
    """Presenter token, follow / explore alone, and the tab's role in words."""

    def __init__(
        self, gui: viser.GuiApi, dispatch: Dispatch, order: float, tr: Translator | None = None
    ) -> None:
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.role = Role()
        self._shown: Role | None = None
        self.root = gui.add_folder(_(CLASSROOM), order=order)
        with self.root:
            self.status = gui.add_html("")
            self.token = gui.add_text(
                _("Presenter token"),
                initial_value="",
                hint=_("The server's token: this tab then presents."),
            )
            bind(self.token, dispatch, lambda v: ClaimPresenter(str(v)) if str(v).strip() else None)
            # A request to hand over (shown to the presenter only while another tab asks).
            self.hand_over = gui.add_button(_("Hand over"), visible=False, color="green")
            bind_click(self.hand_over, dispatch, lambda: AnswerHandover(True))
            self.keep = gui.add_button(_("Keep presenting"), visible=False)
            bind_click(self.keep, dispatch, lambda: AnswerHandover(False))
            self.button = gui.add_button(_("Explore on my own"), visible=False)
            self.button.on_click(lambda _: dispatch(self._next()))

    def _next(self) -> Command:
        r = self.role
        if r.presenting:
            return StopPresenting()
        if r.following:
            return ExploreAlone()
        return FollowPresenter()

    def show(self, role: Role) -> None:
        """Put ``role`` on screen (only what changed)."""
        self.role = role
        if role == self._shown:
            return
        self._shown = role
        tr = self.tr
        _ = tr.gettext
        if role.presenting and role.asked:
            text = "<b>{}</b>".format(
                html.escape(_("Another tab typed the presenter token and asks to present."))
            )
            label = _("Stop presenting")
        elif role.presenting:
            n = role.followers
            text = tr.ngettext(
                "<b>You are presenting</b>: {n} tab follows.",
                "<b>You are presenting</b>: {n} tabs follow.",
                n,
            ).format(n=n)
            label = _("Stop presenting")
        elif role.waiting:
            text = html.escape(
                _("The presenting tab was asked to hand over: this tab presents as soon as it agrees.")
            )
            label = ""
        elif role.following:
            text = _("<b>Following the presenter</b>: your inputs are read-only.")
            label = _("Explore on my own")
        elif role.presenter:
            text = _("<b>Exploring on your own</b>; a presenter is on.")
            label = _("Follow the presenter")
        else:
            text = _("No presenter yet: tabs follow the presenter once one is on.")
            label = ""
        self.status.content = f'<div class="jl-note" style="font-size:13.5px">{text}</div>'
        # Presenting or following, the box folds to its one title line (app.views.panel.layout's script
        # folds a folder whose title starts "Classroom ·"; a click on it opens it again).
        self.root.label = compact_title(role, tr)
        self.button.visible = bool(label)
        if label:
            self.button.label = label
        self.hand_over.visible = self.keep.visible = role.presenting and role.asked
        self.token.visible = not role.presenting and not role.waiting
        if role.presenting or role.waiting:
            sync_value(self.token, "")

    def remove(self) -> None:
        self.root.remove()


def compact_title(role: Role, tr: Translator | None = None) -> str:
    """The box's title: "Classroom", or one line saying the role once the tab presents or follows
    ("<title> · <role>": the layout script folds the box on that separator), or, while another tab asks
    the presenter to hand over, "<title> — <request>" (the layout script unfolds it)."""
    tr = tr or translations()
    title = tr.gettext(CLASSROOM)
    if role.presenting and role.asked:
        return f"{title} — " + tr.gettext("another tab asks to present")
    if role.presenting:
        n = role.followers
        what = tr.ngettext("presenting: {n} tab follows", "presenting: {n} tabs follow", n).format(n=n)
        return f"{title} · {what}"
    if role.following:
        return f"{title} · " + tr.gettext("following the presenter (read-only)")
    return title
