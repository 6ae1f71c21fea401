"""A round of the room's question: one answer per tab, exact counts across workers, hostile answers refused."""

from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest

import robots
from app.core import poll
from app.core import questions as Q
from app.core.i18n import translations


def _kind_round(number: int = 1) -> poll.Round:
    robot = robots.load("puma560")
    c = next(c for c in robot.configurations if c.name == "wrist_singular")
    return poll.open_round(number, Q.kind_question(robot, c.q, c.name))


def test_one_answer_per_tab_the_last_one_counts() -> None:
    r = _kind_round()
    r = poll.answer(r, "w0/t1", 1, "elbow")
    r = poll.answer(r, "w0/t1", 1, "wrist")
    r = poll.answer(r, "w0/t2", 1, "wrist")
    t = poll.tally(r)
    assert t.answered == 2
    assert dict(zip(t.labels, t.counts, strict=True))["wrist"] == 2
    assert poll.is_right(r.question, "wrist") and not poll.is_right(r.question, "elbow")
    assert poll.tally(poll.withdraw(r, "w0/t2")).answered == 1


def test_sixty_tabs_on_two_workers_counted_once_each() -> None:
    """Each worker keeps its own round; the room's bars are their sum, equal to counting every tab's last
    answer directly (tabs change their minds up to three times)."""
    rng = np.random.default_rng(5)
    question = _kind_round().question
    workers = [poll.open_round(1, question), poll.open_round(1, question)]
    last: dict[str, str] = {}
    for tab in range(60):
        w = tab % 2
        key = f"w{w}/t{tab}"
        for _ in range(int(rng.integers(1, 4))):
            choice = str(rng.choice(question.choices))
            workers[w] = poll.answer(workers[w], key, 1, choice)
            last[key] = choice
    room = poll.merge([poll.tally(x) for x in workers])
    assert room.answered == 60
    for label, n in zip(room.labels, room.counts, strict=True):
        assert n == sum(1 for v in last.values() if v == label)


@pytest.mark.parametrize(
    "value,why",
    [
        ("wristt", "not one of"),
        (None, "not one of"),
        (3, "not one of"),
        ({"__class__": 1}, "not one of"),
        ("<script>", "not one of"),
    ],
)
def test_forged_choices_refused_in_words(value: object, why: str) -> None:
    r = _kind_round()
    with pytest.raises(poll.AnswerRefused, match=why):
        poll.answer(r, "t", 1, value)


def test_closed_and_earlier_questions_refused() -> None:
    r = poll.answer(_kind_round(2), "t1", 2, "wrist")
    with pytest.raises(poll.AnswerRefused, match="over"):
        poll.answer(r, "t2", 1, "wrist")
    closed = poll.close(r)
    with pytest.raises(poll.AnswerRefused, match="closed"):
        poll.answer(closed, "t2", 2, "wrist")
    assert poll.tally(poll.reveal(closed)) == poll.tally(r)


def test_a_room_beyond_the_limit_is_refused_but_tabs_may_change_their_answer() -> None:
    r = _kind_round()
    r = poll.Round(r.number, r.question, answers={f"t{i}": "wrist" for i in range(poll.MAX_TABS)})
    with pytest.raises(poll.AnswerRefused, match="full"):
        poll.answer(r, "new", 1, "wrist")
    assert poll.tally(poll.answer(r, "t0", 1, "elbow")).answered == poll.MAX_TABS


def test_number_answers_read_as_the_language_writes_them() -> None:
    robot = robots.load("planar2")
    q = np.array([0.3, 1.1])
    question = Q.number_question(robot, q, "det")
    r = poll.open_round(1, question)
    value = question.value
    pl = translations("pl")
    r = poll.answer(r, "pl", 1, f"{value:.4f}".replace(".", ","), pl)
    r = poll.answer(r, "en", 1, f"{value:.4f}")
    r = poll.answer(r, "low", 1, str(value - 10 * question.tolerance))
    r = poll.answer(r, "high", 1, f"{value + 10 * question.tolerance:.3e}")
    t = poll.tally(r)
    assert dict(zip(t.labels, t.counts, strict=True)) == {"right": 2, "below": 1, "above": 1}
    assert poll.is_right(question, r.answers["pl"]) is True
    for bad in ("nan", "1e400", "", "0,5", "1_000", "2**10"):
        with pytest.raises(poll.AnswerRefused):
            poll.answer(r, "x", 1, bad)  # English: a decimal comma is refused too, in words
    with pytest.raises(poll.AnswerRefused, match="1e13|beyond|large|limit"):
        poll.answer(r, "x", 1, "1e13")
    assert math.isclose(poll.tally(r).answered, 4)


def test_pointed_directions_counted_under_the_nearest_arrow() -> None:
    from app.core.actions import GoTo
    from app.core.reducer import reduce
    from app.core.snapshot import compute
    from app.core.state import LabState

    robot = robots.load("puma560")
    state = reduce(LabState.initial("puma560", robot), GoTo("wrist_singular"))
    question = Q.lost_question(robot, state.q, compute(state).losses, seed=4)
    r = poll.open_round(1, question)
    (letter,) = question.right
    right = np.array(question.arrows[question.choices.index(letter)].direction)
    r = poll.answer(r, "a", 1, tuple(-right + 0.05))  # the other sense of the same line, a little off
    r = poll.answer(r, "b", 1, "A" if letter != "A" else "B")
    assert dict(zip(poll.tally(r).labels, poll.tally(r).counts, strict=True))[letter] == 1
    assert poll.is_right(question, r.answers["a"]) is True
    for bad in ((0.0, 0.0, 0.0), (1.0, float("nan"), 0.0), (1.0, 2.0), (True, 0.0, 0.0), ("1", 0, 0)):
        with pytest.raises(poll.AnswerRefused):
            poll.answer(r, "c", 1, bad)


def test_csv_has_only_counts_and_defuses_formulas() -> None:
    robot = robots.load("planar2")
    question = Q.custom_question(
        robot, robot.home, '=HYPERLINK("x") "quoted"', ["=1+1", "@SUM(A1)", "plain"], [2]
    )
    r = poll.open_round(1, question)
    for i, c in enumerate(["=1+1", "plain", "plain"]):
        r = poll.answer(r, f"secret-tab-{i}", 1, c)
    text = poll.csv_text(question.prompt, poll.tally(r))
    assert "secret-tab" not in text
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0] == ["question", '\'=HYPERLINK("x") "quoted"']
    assert rows[2:] == [["'=1+1", "1"], ["'@SUM(A1)", "0"], ["plain", "2"]]


def test_closing_drops_what_each_tab_answered_and_keeps_counts_and_verdicts() -> None:
    r = _kind_round()
    r = poll.answer(poll.answer(r, "a", 1, "wrist"), "b", 1, "elbow")
    counts = poll.tally(r)
    closed = poll.close(r)
    assert closed.answers == {} and closed.verdicts == {"a": True, "b": False}
    assert poll.tally(closed) == counts
    shown = poll.seen(poll.reveal(closed), "a", False, counts, 2)
    assert shown.right is True and shown.mine is None and shown.tally == counts
    assert poll.seen(closed, "b", False, counts, 2).right is None  # said only at the reveal
