"""The room answers (issue 31), at server level: a presenter asks about what it shows, followers answer on
their own tabs, the presenter sees the bars and reveals; across two workers every answer counts once."""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest
from app_helpers import running_lab
from fakes import poll
from test_classroom import room, settle
from test_room import Room, Tab

from app.core import poll as rounds
from app.core import questions as Q
from app.core.actions import GoTo, SetJoint
from app.core.commands import AnswerRoom, AskRoom, EndQuestion
from app.core.i18n import translations
from app.core.state import LabState
from app.services.question_desk import NOT_PRESENTING, TOO_FAST
from app.views.panel.question import ASK_LABELS, HIDDEN_WORDS

TOKEN = "Xq7-vR2pLw9sKd4TzY"


def _said(*sessions) -> list[list[str]]:
    """What each tab's notices say from now on (the body of each notice, recorded)."""
    out = []
    for session in sessions:
        bodies: list[str] = []
        notify = session.notices.notify
        session.notices.notify = lambda title, body, seconds=8.0, bodies=bodies, notify=notify: (
            bodies.append(body),
            notify(title, body, seconds),
        )
        out.append(bodies)
    return out


def _at(presenter, configuration: str) -> None:
    presenter.dispatch(GoTo(configuration))
    presenter.settle()


def test_peer_instruction_on_the_puma_wrist_in_one_process():
    with room(2) as (lab, presenter, followers):
        poll(lambda: all(f.role.following for f in followers), what="both follow")
        assert presenter.state.robot_name == "puma560"
        _at(presenter, "wrist_singular")
        poll(
            lambda: all(f.state.configuration == "wrist_singular" for f in followers), what="followers there"
        )
        settle(*followers)
        assert "wrist" in presenter.panel.status.content  # the answer is on screen before the question
        presenter.dispatch(AskRoom("kind"))
        seen = poll(
            lambda: all(f.role.question for f in followers) and followers[0].role.question, what="asked"
        )
        assert seen.question.right == {"wrist"} and seen.phase == "open"
        poll(lambda: presenter.role.question is not None and presenter.role.question.presenting)
        settle(presenter, *followers)
        for tab in (presenter, *followers):  # the status line would say "wrist": hidden until the reveal
            assert tab.panel.status.content.count(HIDDEN_WORDS.split(":")[0]) == 1
            assert "wrist" not in tab.panel.status.content
        said = _said(*followers)
        assert followers[0].panel.question.box.visible and not presenter.panel.question.box.visible
        assert [b.label for b in followers[0].panel.question.buttons if b.visible][:2] == ["regular", "wrist"]
        # One answers wrong, changes its mind; the other answers right; a forged choice is refused.
        followers[0].dispatch(AnswerRoom(seen.number, "elbow"))
        followers[0].dispatch(AnswerRoom(seen.number, "wrist"))
        followers[1].dispatch(AnswerRoom(seen.number, "shoulder"))
        followers[1].dispatch(AnswerRoom(seen.number, "<img src=x onerror=alert(1)>"))
        settle(*followers)
        assert any("not one of" in n for n in said[1])
        bars = poll(
            lambda: (t := presenter.role.question.tally) is not None and t.answered == 2 and t,
            what="2 answered",
        )
        counts = dict(zip(bars.labels, bars.counts, strict=True))
        assert counts == {"regular": 0, "wrist": 1, "elbow": 0, "shoulder": 1, "boundary": 0, "other": 0}
        assert followers[0].role.question.tally is None  # a follower never sees the bars before the reveal
        settle(presenter)
        assert "2 of 2 tabs answered" in presenter.panel.question.bars.content
        # A follower cannot close or reveal; the presenter reveals.
        followers[0].dispatch(EndQuestion(True))
        settle(followers[0])
        assert any(translations().gettext(NOT_PRESENTING) in n for n in said[0])
        assert presenter.role.question.phase == "open"
        presenter.dispatch(EndQuestion(True))
        poll(lambda: all(f.role.question.phase == "revealed" for f in followers), what="revealed")
        assert followers[0].role.question.right is True and followers[1].role.question.right is False
        settle(presenter, *followers)
        assert "wrist" in presenter.panel.status.content  # the picture settles it
        assert "Right!" in followers[0].panel.question.verdict.content
        assert "Not this time" in followers[1].panel.question.verdict.content
        # Answers after the reveal are refused in words; the counts stay.
        followers[1].dispatch(AnswerRoom(seen.number, "wrist"))
        settle(followers[1])
        assert any("closed" in n for n in said[1])
        text = lab.classroom.questions.csv(presenter.client.client_id, lambda q: (q.prompt, q.choices))
        rows = list(csv.reader(io.StringIO(text)))
        assert rows[2:] == [["regular", "0"], ["wrist", "1"], ["elbow", "0"], ["shoulder", "1"],
                            ["boundary", "0"], ["other", "0"]]  # fmt: skip
        assert lab.classroom.questions.csv(followers[0].client.client_id, lambda q: ("", ())) is None


def test_the_lost_direction_question_hides_the_arrow_and_draws_four_candidates():
    with room(1) as (lab, presenter, followers):
        _at(presenter, "wrist_singular")
        presenter.dispatch(AskRoom("lost"))
        seen = poll(lambda: followers[0].role.question, what="asked")
        settle(presenter, *followers)
        scene = presenter.screen.scene
        assert not scene.overlays.lost_tips.size  # the arm's own lost axis waits for the reveal
        assert scene.candidates.lines.visible and len(scene.candidates.extent) == 8
        assert [label.visible for label in scene.candidates.labels] == [True] * 4 + [False] * 2
        presenter.dispatch(EndQuestion(True))
        poll(lambda: followers[0].role.question.phase == "revealed")
        settle(presenter)
        assert len(scene.candidates.extent) == 2 and scene.overlays.lost_tips.size  # the answer, and the axis
        (letter,) = seen.question.right
        right = seen.question.arrows[seen.question.choices.index(letter)]
        z = presenter.snapshot.J_base[3:, 3:6]  # the wrist's axes: the right line is orthogonal to all three
        assert np.linalg.norm(z.T @ np.array(right.direction)) < 1e-9


def test_a_number_question_reads_each_tabs_language():
    with room(1) as (lab, presenter, followers):
        _at(presenter, "home")
        presenter.dispatch(AskRoom("kappa"))
        seen = poll(lambda: followers[0].role.question, what="asked")
        assert seen.question.value == pytest.approx(presenter.snapshot.report.condition, rel=1e-9)
        desk, key = lab.classroom.questions, followers[0].client.client_id
        pl = translations("pl")
        assert desk.answer(key, seen.number, f"{seen.question.value:.3f}".replace(".", ","), pl) == ""
        refusal = desk.answer(key, seen.number, "nan", pl)
        assert refusal and refusal != desk.answer(key, seen.number, "nan")  # said in Polish, not English
        desk.flush()
        assert presenter.role.question.tally.counts == (1, 0, 0)


def test_only_the_presenter_asks_and_a_flood_is_refused():
    with room(1) as (lab, presenter, followers):
        desk, key = lab.classroom.questions, followers[0].client.client_id
        robot = presenter.state.robot
        question = Q.kind_question(robot, presenter.state.q)
        assert desk.ask(key, question) == NOT_PRESENTING
        assert desk.ask(presenter.client.client_id, question) == ""
        number = desk.round.number
        said = [desk.answer(key, number, "regular") for _ in range(40)]
        assert said.count("") <= 9 and said.count(TOO_FAST) >= 31  # a burst of 8, then 4 a second
        assert rounds.tally(desk.round).answered == 1


class AnsweringTab(Tab):
    """A worker's tab that also hears the room's question (1 presenter + 60 followers: 30 and 30 in two workers)."""

    def __init__(self, state) -> None:
        super().__init__(state)
        self.seen: list = []

    def question_changed(self, seen) -> None:
        self.seen.append(seen)


def test_sixty_followers_on_two_workers_every_answer_counted_once():
    r = Room(2)
    try:
        tabs = {}
        for w, keys in ((1, range(1, 31)), (2, range(100, 131))):
            for key in keys:
                tab = AnsweringTab(LabState.initial("planar2", r.catalog.load("planar2")))
                r.workers[w].join(key, tab)
                r.workers[w].questions.join(key, tab)
                tabs[(w, key)] = tab
        assert r.workers[1].claim(1, TOKEN) == ""
        poll(lambda: r.workers[1].followers() == 60, what="60 follow")
        presenter = tabs[(1, 1)]
        question = Q.kind_question(presenter.state.robot, presenter.state.q)
        assert r.workers[1].questions.ask(1, question) == ""
        followers = {k: t for k, t in tabs.items() if k != (1, 1)}
        poll(lambda: all(t.seen and t.seen[-1] is not None for t in followers.values()), what="all asked")
        rng = np.random.default_rng(11)
        last = {}
        for (w, key), tab in followers.items():
            number = tab.seen[-1].number
            for _ in range(int(rng.integers(1, 3))):
                choice = str(rng.choice(question.choices))
                assert r.workers[w].questions.answer(key, number, choice) == ""
                last[(w, key)] = choice
        forged = r.workers[2].questions.answer(100, number, "wrist; DROP TABLE")
        assert "not one of" in forged
        want = tuple(sum(1 for v in last.values() if v == c) for c in question.choices)
        got = poll(
            lambda: (
                (s := presenter.seen[-1]) is not None and s.tally is not None and s.tally.counts == want and s
            ),
            what="the room's counts complete at the presenter",
        )
        assert got.tally.answered == 60 and got.room == 60
        assert r.workers[1].questions.end(1, True) == ""
        poll(
            lambda: all(t.seen[-1].phase == "revealed" for t in followers.values()),
            what="revealed everywhere",
        )
        for k, tab in followers.items():
            assert tab.seen[-1].right == (last[k] in question.right)
    finally:
        r.close()


def test_which_joint_blows_up_asked_from_the_box_before_play_and_revealed_by_playing():
    with room(1) as (lab, presenter, followers):
        box = presenter.panel.question
        assert box.ask_box.visible and not followers[0].panel.question.ask_box.visible
        assert presenter.state.motion.preset == ""  # the Motion tab shows its first preset, not applied
        box.kind.value = translations().gettext(ASK_LABELS["blowup"])  # as chosen in the menu
        box._ask()
        seen = poll(lambda: followers[0].role.question, what="asked")
        assert seen.question.right == {"q4", "q6"}  # the Puma's wrist: q̇4 = −q̇6 blow up together
        assert presenter.state.motion.preset == "straight line into the wrist singularity"
        followers[0].dispatch(AnswerRoom(seen.number, "q4"))
        poll(
            lambda: presenter.role.question.tally is not None and presenter.role.question.tally.answered == 1
        )
        assert not presenter.state.playing
        presenter.dispatch(EndQuestion(True))
        poll(lambda: presenter.state.playing, what="the reveal plays the motion")
        poll(lambda: followers[0].role.question.right is True, what="told it was right")


def test_what_no_browser_would_send_changes_nothing_and_the_room_keeps_going():
    """Over a follower's real websocket: its hidden "Reveal the answer" and "Ask the room" buttons, a choice
    button beyond the question's choices, a 50 000-character answer and a non-text answer."""
    from hostile_helpers import widget
    from wsclient import ViserWsClient

    from app.viser_adapter import message_class

    update = message_class("GuiUpdateMessage")

    def button(ws, label):
        return widget(
            ws, lambda m: m["type"] == "GuiButtonMessage" and m.get("props", {}).get("label") == label
        )

    def text_box(ws, label):
        return widget(
            ws, lambda m: m["type"] == "GuiTextMessage" and m.get("props", {}).get("label") == label
        )

    with running_lab(presenter_token=TOKEN) as (lab, teacher, _ws):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as ws:
            poll(lambda: len(lab.sessions) == 2)
            student = next(s for s in lab.sessions.values() if s is not teacher)
            assert lab.classroom.claim(teacher.key, TOKEN) == ""
            poll(lambda: student.role.following)
            teacher.dispatch(GoTo("wrist_singular"))
            teacher.settle()
            teacher.dispatch(AskRoom("lost"))
            seen = poll(lambda: student.role.question, what="asked")
            student.settle()  # its Question box shows the question (a click answers what it shows)
            ws.send(update(button(ws, "Reveal the answer"), {"value": True}))  # hidden: only the presenter's
            ws.send(update(button(ws, "Ask the room"), {"value": True}))
            ws.send(update(button(ws, "5"), {"value": True}))  # a sixth choice of a four-choice question
            ws.send(update(text_box(ws, "Your answer"), {"value": "9" * 50_000}))
            ws.send(update(text_box(ws, "Your answer"), {"value": {"__class__": "os.system"}}))
            ws.send(update(button(ws, "Send"), {"value": True}))
            ws.send(update(button(ws, "0"), {"value": True}))  # then a real answer: choice A
            poll(lambda: lab.classroom.questions.round.answers.get(str(student.key)) == "A", what="A taken")
            student.settle()
            assert lab.classroom.questions.round.number == seen.number  # nobody asked again
            assert lab.classroom.questions.round.phase == "open"  # nobody revealed
            assert len(lab.classroom.questions.round.answers) == 1
            teacher.dispatch(SetJoint(1, 0.3))  # the room keeps going
            teacher.settle()
            poll(lambda: student.state.q[1] == pytest.approx(0.3), what="the follower still follows")


def test_the_teachers_own_question_from_the_box():
    with room(2) as (lab, presenter, followers):
        box = presenter.panel.question
        box.kind.value = translations().gettext(ASK_LABELS["custom"])
        box._kind_changed()
        assert box.own.visible and box.own_choices.visible and box.own_right.visible
        box.own.value = "Where does <b>q5 = 0</b> put the wrist?"
        box.own_choices.value = "a singularity; a regular pose ;  ; a joint limit"
        box.own_right.value = "1"
        box._ask()
        seen = poll(lambda: followers[0].role.question, what="asked")
        assert seen.question.kind == "custom" and seen.question.choices == (
            "a singularity",
            "a regular pose",
            "a joint limit",
        )
        assert seen.question.right == {"a singularity"}
        settle(*followers)
        assert (
            "&lt;b&gt;q5 = 0&lt;/b&gt;" in followers[0].panel.question.text.content
        )  # shown as typed, escaped
        followers[0].dispatch(AnswerRoom(seen.number, "a singularity"))
        followers[1].dispatch(AnswerRoom(seen.number, "a joint limit"))
        poll(lambda: (t := presenter.role.question.tally) is not None and t.answered == 2, what="answered")
        presenter.dispatch(EndQuestion(True))
        poll(lambda: followers[1].role.question.right is False and followers[0].role.question.right is True)
        # A question with no right answer is a poll: nobody is told right or wrong.
        box.own_right.value = ""
        box._ask()
        poll(lambda: followers[0].role.question.number == seen.number + 1, what="a second round")
        assert not followers[0].role.question.question.right
        followers[0].dispatch(AnswerRoom(seen.number + 1, "a joint limit"))
        followers[0].settle()
        presenter.dispatch(EndQuestion(True))
        poll(lambda: followers[0].role.question.phase == "revealed")
        assert followers[0].role.question.right is None
