"""A round of the room's question: open → closed → revealed, one answer per tab, counts without names.

Pure and frozen: every function returns a new :class:`Round`. A tab is a key (the worker and the tab's
id, never a name); its answer replaces its earlier one while the round is open. What a follower sends is
checked here, where it enters: a choice must be one of the question's ids, a number is read as the tab's
language writes numbers (:func:`app.core.numbers.parse_number`) and must be finite and within
:data:`NUMBER_BOUND`, a pointed direction must be three finite numbers, not zero. A refusal is
:class:`AnswerRefused` with a catalog sentence; the round is unchanged.

Counts (:class:`Tally`) are what the presenter sees: per choice, or for a number question how many typed
a value within the tolerance, below it or above it. Tallies of several workers add up exactly
(:func:`merge`): each worker counts its own tabs, and a tab lives in one worker. Nothing but counts
leaves a round (:func:`csv_text`, the teacher's download).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Literal

from .i18n import N_, Translator
from .numbers import NumberError, parse_number
from .questions import Question, direction_is_right

__all__ = [
    "AnswerRefused",
    "Phase",
    "Round",
    "Tally",
    "NUMBER_BOUND",
    "NUMBER_BINS",
    "open_round",
    "answer",
    "withdraw",
    "close",
    "reveal",
    "tally",
    "merge",
    "is_right",
    "csv_text",
    "Seen",
    "seen",
    "labels",
]

Phase = Literal["open", "closed", "revealed"]
NUMBER_BOUND = 1e12
"""Largest magnitude a typed det J or κ may have (a finite κ of a lab arm is far below)."""
NUMBER_BINS = ("right", "below", "above")
"""A number question's bars: within the tolerance, below it, above it."""
MAX_TABS = 2000
"""A round keeps at most this many answers (a room far larger than a lecture hall refuses the rest)."""


class AnswerRefused(ValueError):
    """An answer not taken; the message is a sentence for the tab (translated where raised)."""


Answer = str | float | tuple[float, float, float]


@dataclass(frozen=True)
class Round:
    """One question put to the room.

    Attributes:
        number: The round's number in this lecture (1, 2, …): an answer names it, so an answer to an
            earlier question is refused.
        question: What is asked.
        phase: ``"open"`` (answers taken), ``"closed"`` (counts final, no answer shown yet) or
            ``"revealed"`` (the right answer drawn and said; each tab told whether it was right).
        answers: Tab key → its answer (a choice id, a number, or a pointed direction), while open.
        verdicts: Once closed, tab key → whether its answer was right (None: a poll); the answers
            themselves are dropped when the question closes, only these and the counts stay.
        final: Once closed, the counts (the answers they came from are gone).
    """

    number: int
    question: Question
    phase: Phase = "open"
    answers: dict[str, Answer] = field(default_factory=dict, compare=False)
    verdicts: dict[str, bool | None] = field(default_factory=dict, compare=False)
    final: Tally | None = field(default=None, compare=False)


def open_round(number: int, question: Question) -> Round:
    """A new round, open, with no answers."""
    return Round(number, question)


def _refused(message: str, tr: Translator | None, **values: object) -> AnswerRefused:
    text = tr.gettext(message) if tr is not None else message
    return AnswerRefused(text.format(**values) if values else text)


def _checked(question: Question, value: object, tr: Translator | None) -> Answer:
    if question.kind == "number":
        try:
            return parse_number(value, bound=NUMBER_BOUND, tr=tr)
        except NumberError as e:
            raise AnswerRefused(str(e)) from None
    if question.kind == "lost" and isinstance(value, (list, tuple)):
        if len(value) != 3 or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in value
        ):
            raise _refused(N_("a pointed direction is three finite numbers"), tr)
        d = (float(value[0]), float(value[1]), float(value[2]))
        if math.hypot(*d) < 1e-12:
            raise _refused(N_("a pointed direction cannot be zero"), tr)
        return d
    if not isinstance(value, str) or value not in question.choices:
        raise _refused(N_("that is not one of the question's choices"), tr)
    return value


def answer(r: Round, tab: str, number: int, value: object, tr: Translator | None = None) -> Round:
    """``tab``'s answer to round ``number`` (replacing its earlier one), or :class:`AnswerRefused`.

    Refused: a round that is not this one (an earlier question), a round no longer open, a value that
    is not an answer to this question, and a new tab beyond :data:`MAX_TABS`.
    """
    if number != r.number:
        raise _refused(N_("that question is over: answer the one on screen"), tr)
    if r.phase != "open":
        raise _refused(N_("this question is closed: answers are no longer taken"), tr)
    checked = _checked(r.question, value, tr)
    if tab not in r.answers and len(r.answers) >= MAX_TABS:
        raise _refused(N_("the room is full: this question takes no more answers"), tr)
    return replace(r, answers={**r.answers, tab: checked})


def withdraw(r: Round, tab: str) -> Round:
    """The round without ``tab``'s answer (the tab closed while the question was open)."""
    if r.phase != "open" or tab not in r.answers:
        return r
    return replace(r, answers={k: v for k, v in r.answers.items() if k != tab})


def close(r: Round) -> Round:
    """No more answers; the counts are final. What each tab answered is dropped: only the counts and
    whether each tab was right stay (to tell it at the reveal)."""
    if r.phase != "open":
        return r
    verdicts = {tab: is_right(r.question, value) for tab, value in r.answers.items()}
    return replace(r, phase="closed", answers={}, verdicts=verdicts, final=tally(r))


def reveal(r: Round) -> Round:
    """The right answer shown (closing the round first if it was open)."""
    return replace(close(r), phase="revealed")


def _bin(question: Question, value: Answer) -> str:
    if question.kind == "number":
        x = float(value)  # type: ignore[arg-type]
        if abs(x - question.value) <= question.tolerance:
            return "right"
        return "below" if x < question.value else "above"
    if isinstance(value, tuple):  # a pointed direction: counted under the candidate it is nearest
        return _nearest(question, value)
    return str(value)


def _nearest(question: Question, d: tuple[float, float, float]) -> str:
    def cos(a: tuple[float, float, float]) -> float:
        dot = abs(sum(x * y for x, y in zip(a, d, strict=True)))
        return dot / max(math.hypot(*a) * math.hypot(*d), 1e-300)

    best = max(range(len(question.arrows)), key=lambda i: cos(question.arrows[i].direction))
    return question.choices[best]


@dataclass(frozen=True)
class Tally:
    """The bars: ``labels[i]`` answered by ``counts[i]`` tabs; ``answered`` tabs in all."""

    labels: tuple[str, ...]
    counts: tuple[int, ...]

    @property
    def answered(self) -> int:
        return sum(self.counts)


def labels(question: Question) -> tuple[str, ...]:
    """The bars a question's answers fall into."""
    return NUMBER_BINS if question.kind == "number" else question.choices


def tally(r: Round) -> Tally:
    """How the room answered: a count per bar (no names, no values)."""
    if r.final is not None:
        return r.final
    keys = labels(r.question)
    counts = dict.fromkeys(keys, 0)
    for value in r.answers.values():
        counts[_bin(r.question, value)] += 1
    return Tally(keys, tuple(counts[k] for k in keys))


def merge(tallies: list[Tally] | tuple[Tally, ...]) -> Tally:
    """The room's tally from each worker's (same bars; a tab is counted in its own worker only)."""
    if not tallies:
        raise ValueError("no tallies to merge")
    keys = tallies[0].labels
    if any(t.labels != keys for t in tallies):
        raise ValueError("tallies of different questions")
    return Tally(keys, tuple(sum(t.counts[i] for t in tallies) for i in range(len(keys))))


def is_right(question: Question, value: Answer) -> bool | None:
    """Whether an answer is right (``None`` for a custom question with no right answer: a poll)."""
    if question.kind == "number":
        return _bin(question, value) == "right"
    if question.kind == "custom" and not question.right:
        return None
    if isinstance(value, tuple):
        part = question.lost[0].part if question.lost else "translation"
        return direction_is_right(question.lost, part, value)
    return value in question.right


def _cell(text: str) -> str:
    """One CSV cell: quoted, quotes doubled, and a leading = + - @ made inert (spreadsheet formulas)."""
    if text[:1] in ("=", "+", "-", "@", "\t", "\r"):
        text = "'" + text
    return '"' + text.replace('"', '""') + '"'


def csv_text(question_words: str, t: Tally, bar_words: tuple[str, ...] | None = None) -> str:
    """The teacher's download: the question and the counts per bar, nothing else (no tab, no value)."""
    rows = [f"{_cell('question')},{_cell(question_words)}", f"{_cell('answer')},{_cell('count')}"]
    shown = bar_words or t.labels
    rows += [f"{_cell(w)},{n}" for w, n in zip(shown, t.counts, strict=True)]
    return "\r\n".join(rows) + "\r\n"


@dataclass(frozen=True)
class Seen:
    """What one tab shows of the room's question (carried in its :class:`~app.core.role.Role`).

    Attributes:
        number: The round's number (a follower's answer names it).
        question: What is asked.
        phase: Where the round is.
        presenting: This tab asked (it sees the bars live, and closes and reveals).
        mine: This tab's answer, or None (a follower that has not answered; the presenter).
        right: After the reveal, whether ``mine`` was right (None: no answer, or a poll).
        tally: The room's bars: live for the presenter, for everyone once revealed; else None.
        room: How many tabs could answer (the presenter's "12 of 30 answered").
    """

    number: int
    question: Question
    phase: Phase
    presenting: bool
    mine: Answer | None = None
    right: bool | None = None
    tally: Tally | None = None
    room: int = 0

    @property
    def masks(self) -> str:
        """What the screens hide until the reveal: the question's kind while it is not revealed, else ""."""
        return self.question.kind if self.phase != "revealed" else ""


def seen(r: Round, tab: str, presenting: bool, room_tally: Tally, room: int) -> Seen:
    """Round ``r`` as tab ``tab`` shows it (``room_tally``: the room's bars, from every worker)."""
    mine = None if presenting else r.answers.get(tab)
    right = r.verdicts.get(tab) if r.phase == "revealed" and not presenting else None
    bars = room_tally if presenting or r.phase == "revealed" else None
    return Seen(r.number, r.question, r.phase, presenting, mine, right, bars, room)
