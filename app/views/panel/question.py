"""The room's question in the panel: the presenter asks and sees the bars; each follower answers.

The presenter's box "Ask the room": which question (made by the lab from what is on screen, or the
teacher's own with its choices), **Ask the room**, then the bars (no names: how many answered each, and
how many of the room answered), **Close**, **Reveal the answer** and **Download the counts (CSV)**.

A follower's box "Question" opens at the top of the panel while a question is on (the arm stays in view):
the question, one button per choice (or a box for a number, read as the tab's language writes it), what
it answered (it may change it until the question closes), and after the reveal whether it was right.

While the room answers, what would give the answer away is hidden on every screen: the status line
(κ, det J and the singularity's words) for the "kind", "det" and "kappa" questions, and the arm's
lost-direction glyph for "kind" and "lost" (:data:`app.views.scene.HIDDEN_UNTIL_REVEALED`).
"""

from __future__ import annotations

import html
from collections.abc import Callable
from typing import Any

import viser

from ...core.commands import AnswerRoom, AskRoom, EndQuestion, RequestDownload
from ...core.i18n import N_, Translator
from ...core.poll import Seen
from ...core.questions import ASKABLE, Question
from ...core.role import Role
from ...core.words import kind_word
from ..fmt import number
from .common import Dispatch, bind_click

__all__ = [
    "QuestionPanel",
    "ASK_LABELS",
    "HIDES_STATUS",
    "HIDDEN_WORDS",
    "question_words",
    "bar_words",
    "bars_html",
]

ASK_LABELS = {
    "kind": N_("Is it singular? Which kind?"),
    "blowup": N_("Which joint's rate blows up first? (before Play)"),
    "lost": N_("Which direction is lost?"),
    "det": N_("What is det J here?"),
    "kappa": N_("What is κ here?"),
    "custom": N_("Your own question"),
}
"""The presenter's menu, one entry per :data:`app.core.questions.ASKABLE` kind."""
HIDES_STATUS = ("kind", "det", "kappa")
HIDDEN_WORDS = N_(
    "The room is answering: κ, det J and the kind of singularity show once the answer is revealed."
)
"""Questions whose answer the status line would say: it is hidden until the reveal."""
COUNTS = "counts.csv"
"""The download's label (:class:`RequestDownload`) and file name."""
MAX_BUTTONS = 6


def question_words(question: Question, tr: Translator) -> str:
    """The question as a tab shows it: the lab's in the tab's language, the teacher's as typed."""
    return question.prompt if question.kind == "custom" else tr.gettext(question.prompt)


def choice_words(question: Question, choice: str, tr: Translator) -> str:
    """A choice as a button says it."""
    if question.kind == "kind":
        return tr.gettext(N_("regular")) if choice == "regular" else (
            tr.gettext(N_("another kind")) if choice == "other" else kind_word(choice, tr)
        )  # fmt: skip
    return choice


def bar_words(question: Question, tr: Translator) -> tuple[str, ...]:
    """The bars' names in the tab's language."""
    if question.kind == "number":
        within = tr.gettext(N_("within ±{tolerance}")).format(tolerance=number(question.tolerance, 2, tr))
        return (within, tr.gettext(N_("below")), tr.gettext(N_("above")))
    return tuple(choice_words(question, c, tr) for c in question.choices)


def answer_words(question: Question, tr: Translator) -> str:
    """The right answer, said."""
    if question.kind == "number":
        return f"{'det J' if question.quantity == 'det' else 'κ'} = {number(question.value, 4, tr)}"
    if not question.right:
        return tr.gettext(N_("no right answer: the room's opinion"))
    right = [choice_words(question, c, tr) for c in question.choices if c in question.right]
    return tr.gettext(N_(" and ")).join(right)


def bars_html(seen: Seen, tr: Translator) -> str:
    """The bars (no names): one row per answer, its count and a bar as wide as its share; the right ones
    marked once revealed."""
    if seen.tally is None:
        return ""
    words = bar_words(seen.question, tr)
    total = max(seen.tally.answered, 1)
    rows = []
    for i, (w, n) in enumerate(zip(words, seen.tally.counts, strict=True)):
        right = seen.phase == "revealed" and (
            seen.tally.labels[i] in seen.question.right or seen.tally.labels[i] == "right"
        )
        width = round(100 * n / total)
        colour = "#2b8a3e" if right else "#868e96"
        mark = " ✓" if right else ""
        rows.append(
            f'<div style="display:flex;gap:6px;align-items:center;font-size:13px">'
            f'<span style="flex:0 0 38%;overflow-wrap:anywhere">{html.escape(w)}{mark}</span>'
            f'<span style="flex:1;background:#eee;height:12px"><span style="display:block;height:12px;'
            f'width:{width}%;background:{colour}"></span></span>'
            f'<span style="flex:0 0 2.5em;text-align:right">{n}</span></div>'
        )
    head = tr.ngettext("{n} of {room} tab answered", "{n} of {room} tabs answered", seen.room).format(
        n=seen.tally.answered, room=seen.room
    )
    return f'<div class="jl-note" style="font-size:13px">{html.escape(head)}</div>' + "".join(rows)


def _nothing() -> None:
    return None


class QuestionPanel:
    """The presenter's "Ask the room" box and a follower's "Question" box of one tab."""

    def __init__(
        self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator, prepare: Callable[[], None] = _nothing
    ) -> None:
        self.tr = tr
        self._prepare = prepare  # before "which joint blows up?": the motion panel's shown preset applied
        _ = tr.gettext
        self._dispatch = dispatch
        self._seen: Seen | None = None
        self._role = Role()
        # A follower's box: at the top, shown only while a question is on.
        self.box = gui.add_folder(_("Question"), order=0.4, visible=False)
        with self.box:
            self.text = gui.add_html("")
            self.buttons = [gui.add_button(str(i), visible=False) for i in range(MAX_BUTTONS)]
            for i, button in enumerate(self.buttons):
                button.on_click(self._chooser(i))
            self.typed = gui.add_text(_("Your answer"), initial_value="", visible=False)
            self.send = gui.add_button(_("Send"), visible=False, color="green")
            self.send.on_click(lambda _: self._send_typed())
            self.verdict = gui.add_html("")
        # The presenter's box.
        self.ask_box = gui.add_folder(_("Ask the room"), order=0.55, visible=False, expand_by_default=False)
        with self.ask_box:
            self.kind = gui.add_dropdown(_("Question"), tuple(_(ASK_LABELS[k]) for k in ASKABLE))
            self.own = gui.add_text(_("Your question"), initial_value="", visible=False)
            self.own_choices = gui.add_text(_("Choices, separated by ;"), initial_value="", visible=False)
            self.own_right = gui.add_text(
                _("Right choices (numbers, e.g. 2)"), initial_value="", visible=False
            )
            self.kind.on_update(lambda _: self._kind_changed())
            self.ask = gui.add_button(_("Ask the room"), color="blue")
            self.ask.on_click(lambda _: self._ask())
            self.bars = gui.add_html("")
            self.close = gui.add_button(_("Close"), visible=False)
            bind_click(self.close, dispatch, lambda: EndQuestion(False))
            self.reveal = gui.add_button(_("Reveal the answer"), visible=False, color="green")
            bind_click(self.reveal, dispatch, lambda: EndQuestion(True))
            self.counts = gui.add_button(_("Download the counts (CSV)"), visible=False)
            bind_click(self.counts, dispatch, lambda: RequestDownload(COUNTS))

    # ------------------------------------------------------------------ input
    def _kind_chosen(self) -> str:
        labels = [self.tr.gettext(ASK_LABELS[k]) for k in ASKABLE]
        value = self.kind.value
        return ASKABLE[labels.index(value)] if value in labels else "kind"  # checked where it enters

    def _kind_changed(self) -> None:
        own = self._kind_chosen() == "custom"
        for handle in (self.own, self.own_choices, self.own_right):
            handle.visible = own

    def _ask(self) -> None:
        kind = self._kind_chosen()
        if kind == "blowup":
            self._prepare()
        if kind != "custom":
            self._dispatch(AskRoom(kind))
            return
        choices = tuple(c.strip() for c in str(self.own_choices.value).split(";") if c.strip())
        right = tuple(int(x) - 1 for x in str(self.own_right.value).replace(",", " ").split() if x.isdigit())
        self._dispatch(AskRoom("custom", str(self.own.value), choices, right))

    def _chooser(self, i: int) -> Callable[[Any], None]:
        """The click of choice button ``i``: the answer to the round on screen."""

        def choose(_: Any) -> None:
            seen = self._seen
            if seen is not None and i < len(seen.question.choices):
                self._dispatch(AnswerRoom(seen.number, seen.question.choices[i]))

        return choose

    def _send_typed(self) -> None:
        if self._seen is not None:
            self._dispatch(AnswerRoom(self._seen.number, str(self.typed.value)))

    # ------------------------------------------------------------------ drawing
    def show(self, role: Role) -> None:
        """Put the role's question on screen (only what changed)."""
        seen = role.question
        if seen == self._seen and role.presenting == self._role.presenting:
            return
        self._seen, self._role = seen, role
        self.ask_box.visible = role.presenting
        follower = seen is not None and not seen.presenting and not role.presenting
        self.box.visible = follower
        if role.presenting:
            self._show_presenter(seen)
        if follower and seen is not None:
            self._show_follower(seen)

    def _show_presenter(self, seen: Seen | None) -> None:
        tr = self.tr
        on = seen is not None
        self.close.visible = on and seen is not None and seen.phase == "open"
        self.reveal.visible = on and seen is not None and seen.phase != "revealed"
        self.counts.visible = on
        if seen is None:
            self.bars.content = ""
            return
        said = html.escape(question_words(seen.question, tr))
        answer = ""
        if seen.phase == "revealed":
            answer = f"<div><b>{html.escape(tr.gettext(N_('Answer')))}</b>: "
            answer += f"{html.escape(answer_words(seen.question, tr))}</div>"
        self.bars.content = f'<div style="font-size:14px"><b>{said}</b></div>{bars_html(seen, tr)}{answer}'

    def _show_follower(self, seen: Seen) -> None:
        tr = self.tr
        _ = tr.gettext
        q = seen.question
        self.text.content = f'<div style="font-size:15px"><b>{html.escape(question_words(q, tr))}</b></div>'
        number_question = q.kind == "number"
        open_ = seen.phase == "open"
        words = bar_words(q, tr) if not number_question else ()
        for i, button in enumerate(self.buttons):
            shown = i < len(q.choices) and not number_question and seen.phase != "revealed"
            if button.visible != shown:
                button.visible = shown
            if shown:
                label = words[i] if q.kind != "lost" else q.choices[i]
                label = f"● {label}" if seen.mine == q.choices[i] else label
                if button.label != label:
                    button.label = label
                if button.disabled != (not open_):
                    button.disabled = not open_
        self.typed.visible = self.send.visible = number_question and seen.phase != "revealed"
        self.typed.disabled = self.send.disabled = not open_
        if seen.phase == "revealed":
            if seen.right is True:
                text = _("Right!") + " " + answer_words(q, tr)
            elif seen.right is False:
                text = _("Not this time: the answer is {answer}.").format(answer=answer_words(q, tr))
            else:
                text = _("The answer: {answer}.").format(answer=answer_words(q, tr))
            text = html.escape(text) + bars_html(seen, tr)
        elif seen.mine is not None:
            mine = seen.mine if not isinstance(seen.mine, float) else number(seen.mine, 6, tr)
            text = html.escape(
                _("Your answer: {answer}. You may change it until the question closes.").format(
                    answer=mine if q.kind != "kind" else choice_words(q, str(mine), tr)
                )
                if open_
                else _("Closed: your answer {answer} counts. The answer comes next.").format(answer=mine)
            )
        else:
            text = html.escape(_("Answer on your own first: the room sees only the counts, never names."))
            text = text if open_ else html.escape(_("Closed: the answer comes next."))
        self.verdict.content = f'<div class="jl-note" style="font-size:13.5px">{text}</div>'

    def remove(self) -> None:
        self.box.remove()
        self.ask_box.remove()
