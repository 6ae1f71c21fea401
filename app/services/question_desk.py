"""The room's question as one process keeps it (or one worker of several, with the room's hub).

Peer instruction in presenter mode: the presenting tab asks (:meth:`QuestionDesk.ask`, a question the lab
made from what it shows, :mod:`app.core.questions`); every tab of the room is told (its
:class:`~app.core.poll.Seen`, through :meth:`Member.question_changed`) and a follower answers once,
changing its answer until the question closes (:meth:`QuestionDesk.answer`, checked by
:func:`app.core.poll.answer`: earlier rounds, closed questions, forged choices and out-of-range numbers are
refused in words; a tab that answers more than :data:`ANSWERS_PER_SECOND` times a second is told to slow
down). The presenter sees the bars (never who answered what) and how many of the room answered, at most
every :data:`TALLY_EVERY` seconds however fast answers come; it closes the question and reveals the answer,
and each follower is told whether it was right. Nothing is kept once the next question opens or the
presenter stops, except what the teacher downloads (:meth:`QuestionDesk.csv`: counts only).

A room of several workers (``serve --workers N --presenter``): the presenter's worker sends each change of
the round to the hub (``question``: its number, phase and the question as data), which passes it to
every other worker; each worker counts its own tabs' answers (a tab lives in one worker, so nothing is
counted twice) and sends its bars (``tally``) at most every :data:`TALLY_EVERY` seconds; the presenter's
worker adds the latest bars of each worker to its own (:func:`app.core.poll.merge`): exact.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

from ..core import poll
from ..core.i18n import N_, Translator
from ..core.poll import AnswerRefused, Round, Seen, Tally
from ..core.question_wire import from_wire, to_wire
from ..core.questions import Question, QuestionError
from .ratelimit import TokenBucket

if TYPE_CHECKING:
    from .classroom import Classroom

__all__ = ["QuestionDesk", "Asked", "TALLY_EVERY", "ANSWERS_PER_SECOND", "NOT_PRESENTING", "TOO_FAST"]

TALLY_EVERY = 0.25
"""The presenter's bars, and a worker's bars to the hub, at most this often [s]."""
ANSWERS_PER_SECOND = 4.0
"""A tab's answers beyond this rate (a burst of 8 allowed) are refused: the room keeps its speed."""
NOT_PRESENTING = N_("only the presenting tab asks, closes and reveals questions")
TOO_FAST = N_("too many answers at once: wait a moment and answer again")
NO_QUESTION = N_("no question is open")


class Asked(Protocol):
    """What the desk needs of a tab: :class:`app.tab.following.Following` provides it."""

    def question_changed(self, seen: Seen | None) -> None: ...


class QuestionDesk:
    """The room's current question, its answers in this process, and who is told what.

    Args:
        classroom: The classroom (who presents; how many follow).
        clock: Monotonic clock [s].
    """

    def __init__(self, classroom: Classroom, clock: Callable[[], float] = time.monotonic) -> None:
        self._classroom = classroom
        self._clock = clock
        self._lock = threading.RLock()
        self._tabs: dict[int, Asked] = {}
        self._buckets: dict[int, TokenBucket] = {}
        self.round: Round | None = None
        self._number = 0
        self._remote: dict[int, Tally] = {}  # the other workers' bars of this round (at the presenter's)
        self._shown: dict[int, Seen | None] = {}
        self._due: threading.Timer | None = None
        self._sent_tally: Tally | None = None
        self.send: Callable[[dict[str, Any]], None] | None = None  # to the room's hub (several workers)
        self.worker = 0

    # ------------------------------------------------------------------ tabs
    def join(self, key: int, tab: Asked) -> None:
        """A tab arrived: it sees the open question, if any."""
        with self._lock:
            self._tabs[key] = tab
            self._buckets[key] = TokenBucket(ANSWERS_PER_SECOND, 8, self._clock)
        self._tell([key])

    def leave(self, key: int) -> None:
        """A tab closed: its answer to an open question is withdrawn."""
        with self._lock:
            self._tabs.pop(key, None)
            self._buckets.pop(key, None)
            self._shown.pop(key, None)
            if self.round is not None:
                self.round = poll.withdraw(self.round, str(key))
        self._changed()

    @property
    def next_number(self) -> int:
        """The number the next round will have (its candidate arrows are drawn from it)."""
        with self._lock:
            return self._number + 1

    def _presenting(self, key: int) -> bool:
        return self._classroom.role(key).presenting

    # ------------------------------------------------------------------ the presenter
    def ask(self, key: int, question: Question) -> str:
        """Tab ``key`` asks ``question``: a new round, open, told to every tab. "" or why not."""
        if not self._presenting(key):
            return NOT_PRESENTING
        with self._lock:
            self._number += 1
            self.round = poll.open_round(self._number, question)
            self._remote = {}
            self._sent_tally = None
        self._broadcast()
        self._tell()
        return ""

    def end(self, key: int, reveal: bool) -> str:
        """Tab ``key`` closes the question (counts final) or reveals its answer. "" or why not."""
        if not self._presenting(key):
            return NOT_PRESENTING
        with self._lock:
            if self.round is None:
                return NO_QUESTION
            self.round = poll.reveal(self.round) if reveal else poll.close(self.round)
        self._broadcast()
        self._tell()
        return ""

    def csv(self, key: int, words: Callable[[Question], tuple[str, tuple[str, ...]]]) -> str | None:
        """The round's counts as CSV for the presenter (``words``: the question and its bars in the tab's
        language), or None when it does not present or no question was asked."""
        if not self._presenting(key):
            return None
        with self._lock:
            if self.round is None:
                return None
            question, bars = words(self.round.question)
            return poll.csv_text(question, self._room_tally(), bars)

    # ------------------------------------------------------------------ a follower
    def answer(self, key: int, number: int, value: object, tr: Translator | None = None) -> str:
        """Tab ``key``'s answer to round ``number``: "" when taken, else why not (in ``tr``'s language)."""
        _ = tr.gettext if tr is not None else str
        with self._lock:
            if self.round is None:
                return _(NO_QUESTION)
            if self._presenting(key):
                return _(N_("the presenting tab does not answer its own question"))
            bucket = self._buckets.get(key)
            if bucket is None or not bucket.take():
                return _(TOO_FAST)
            try:
                self.round = poll.answer(self.round, str(key), number, value, tr)
            except AnswerRefused as e:
                return str(e)
        self._tell([key])
        self._changed()
        return ""

    # ------------------------------------------------------------------ the room's hub
    def _broadcast(self) -> None:
        """A worker of several: the round's change goes to the other workers."""
        with self._lock:
            r = self.round
        if self.send is not None and r is not None:
            self.send(
                {"op": "question", "round": r.number, "phase": r.phase, "question": to_wire(r.question)}
            )

    def from_hub(self, message: dict[str, Any]) -> None:
        """The hub's ``question`` (the presenter's worker changed the round) or ``tally`` (another
        worker's bars, at the presenter's worker). A malformed message is dropped."""
        op = message.get("op")
        try:
            if op == "question":
                number, phase = int(message["round"]), message["phase"]
                if phase not in ("open", "closed", "revealed"):
                    return
                question = from_wire(message["question"])
                with self._lock:
                    if self.round is None or self.round.number != number:
                        self.round = poll.open_round(number, question)
                        self._number = max(self._number, number)
                    if phase != "open":  # this worker's answers become counts and verdicts
                        self.round = (
                            poll.reveal(self.round) if phase == "revealed" else poll.close(self.round)
                        )
                self._tell()
            elif op == "tally":
                counts = message["counts"]
                with self._lock:
                    r = self.round
                    if r is None or int(message["round"]) != r.number:
                        return
                    bars = poll.labels(r.question)
                    if not (isinstance(counts, list) and len(counts) == len(bars)):
                        return
                    if not all(isinstance(n, int) and 0 <= n <= poll.MAX_TABS for n in counts):
                        return
                    self._remote[int(message["worker"])] = Tally(bars, tuple(counts))
                self._changed()
        except (KeyError, TypeError, ValueError, QuestionError):
            return

    # ------------------------------------------------------------------ telling
    def _room_tally(self) -> Tally:
        assert self.round is not None
        return poll.merge([poll.tally(self.round), *self._remote.values()])

    def _changed(self) -> None:
        """Answers changed: the presenter's bars (here) or the hub's (another worker), at most every
        TALLY_EVERY seconds (a timer, never the answering tab's thread waiting)."""
        with self._lock:
            if self._due is not None or self.round is None:
                return
            self._due = threading.Timer(TALLY_EVERY, self._flush)
            self._due.daemon = True
            self._due.start()

    def _flush(self) -> None:
        with self._lock:
            self._due = None
            r = self.round
            if r is None:
                return
            mine = poll.tally(r)
            send = self.send is not None and mine != self._sent_tally
            self._sent_tally = mine
        if send and self.send is not None:
            self.send({"op": "tally", "round": r.number, "counts": list(mine.counts)})
        with self._lock:  # new bars: only a presenting tab shows them before the reveal
            revealed = r.phase == "revealed"
            keys = [k for k, v in self._shown.items() if revealed or (v is not None and v.presenting)]
        self._tell(keys)

    def flush(self) -> None:
        """Send what is due now (tests, and a presenter's reveal)."""
        with self._lock:
            if self._due is not None:
                self._due.cancel()
        self._flush()

    def _tell(self, keys: list[int] | None = None) -> None:
        """Each tab (of ``keys``) whose view of the round changed is told it."""
        with self._lock:
            r = self.round
            tabs = [(k, t) for k, t in self._tabs.items() if keys is None or k in keys]
            room_tally = self._room_tally() if r is not None else None
        room = self._classroom.followers()
        for key, tab in tabs:
            presenting = self._presenting(key)
            view = (
                None
                if r is None or room_tally is None
                else poll.seen(r, str(key), presenting, room_tally, room)
            )
            with self._lock:
                if self._shown.get(key) == view and key in self._shown:
                    continue
                self._shown[key] = view
            tab.question_changed(view)
