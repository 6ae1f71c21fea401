"""Classroom mode at server level: a presenter (by token), tabs that follow it, leaving and coming
back, wrong tokens, and the presenter leaving. Three tabs of one running lab (websocket clients)."""

from __future__ import annotations

import contextlib

import numpy as np
import pytest
from app_helpers import assert_all_finite, running_lab
from fakes import POLL_TIMEOUT, FakeClock, MemberStub, poll
from wsclient import ViserWsClient

import robots
from app.core.actions import ApplyPreset, Play, SetJoint
from app.core.commands import AnswerHandover, ExploreAlone
from app.services.classroom import (
    ASKED,
    HANDED_OVER,
    HANDED_OVER_ROOM,
    KEPT,
    PRESENTER_AWAY,
    TAKEN_OVER,
    TOKEN_TRIES,
    WAITING,
    Classroom,
)

TOKEN = "lecture-7"


@contextlib.contextmanager
def room(n_followers: int = 2, sockets: list | None = None):
    """A lab in classroom mode with 1 + n tabs: (lab, presenter, followers) — the presenter claimed
    (``sockets``: a list given the followers' websocket clients, in the order they connected)."""
    with running_lab(presenter_token=TOKEN) as (lab, first, _):
        clients = [ViserWsClient(f"ws://127.0.0.1:{lab.port}") for _ in range(n_followers)]
        if sockets is not None:
            sockets.extend(clients)
        try:
            for c in clients:
                c.start()
            poll(lambda: len(lab.sessions) == 1 + n_followers)
            others = [s for s in lab.sessions.values() if s is not first]
            first.panel.classroom.token.value = TOKEN  # as typed: no other click
            first.settle()
            # The role is the classroom's at once; the panel shows it (the room's question box) once drawn.
            poll(lambda: first.role.presenting and first.panel.question.ask_box.visible)
            yield lab, first, others
        finally:
            for c in clients:
                c.close()


def settle(*sessions) -> None:
    for s in sessions:
        s.settle()


def test_a_presenter_moves_and_every_follower_draws_the_same_snapshot():
    with room() as (lab, presenter, followers):
        poll(lambda: all(f.role.following for f in followers))
        settle(presenter)
        assert presenter.role.followers == 2
        assert "2 tabs follow" in presenter.panel.classroom.status.content
        computed = presenter.redraws
        presenter.dispatch(SetJoint(2, -0.7))
        settle(presenter)
        poll(lambda: all(f.state.q[2] == pytest.approx(-0.7) for f in followers))
        settle(*followers)
        for f in followers:
            # One computation per presenter change: the followers draw the presenter's own snapshot.
            assert f.snapshot is presenter.snapshot
            assert "read-only" in f.panel.classroom.status.content
            assert_all_finite(f)
        assert presenter.redraws == computed + 1


def test_a_followers_own_input_is_read_only_and_undone():
    with room(1) as (lab, presenter, (follower,)):
        poll(lambda: follower.role.following)
        q_before = np.array(follower.state.q)
        slider = follower.panel.joints.sliders[1]
        slider.value = float(slider.value) + 20.0  # the student drags a slider
        settle(follower)
        assert np.array(follower.state.q) == pytest.approx(q_before)
        poll(lambda: float(slider.value) == pytest.approx(np.degrees(q_before[1]), abs=1e-6))


def test_leave_explore_and_come_back():
    with room(1) as (lab, presenter, (follower,)):
        poll(lambda: follower.role.following)
        settle(follower)  # what the tab shows (the button says what a click will do)
        button = follower.panel.classroom.button
        assert button.label == "Explore on my own"
        button.value = True  # a click
        poll(lambda: not follower.role.following)
        settle(follower)
        assert button.label == "Follow the presenter"
        follower.dispatch(SetJoint(0, 0.4))  # its own inputs work again
        presenter.dispatch(SetJoint(0, -0.3))
        settle(presenter, follower)
        assert follower.state.q[0] == pytest.approx(0.4)
        button.value = True  # follow again: it jumps to what the presenter shows
        poll(lambda: follower.role.following)
        poll(lambda: follower.state.q[0] == pytest.approx(-0.3))


def test_a_presenters_motion_plays_on_the_followers_without_their_clocks():
    with room(1) as (lab, presenter, (follower,)):
        poll(lambda: follower.role.following)
        p = robots.motions("puma560")[0]
        presenter.dispatch(ApplyPreset(p.name, tuple(p.q), tuple(p.twist), p.frame, 0.3))
        presenter.dispatch(Play(True, "resolved_rate"))
        settle(presenter)
        poll(lambda: follower.state.playing and len(follower.state.motion.trace) > 5)
        assert not follower.ticker.running  # moved by the presenter's clock only
        assert (
            follower.state.motion.trace is presenter.state.motion.trace
            or len(follower.state.motion.trace) > 5
        )
        presenter.dispatch(Play(False))
        settle(presenter)
        poll(lambda: not follower.state.playing)


def test_the_camera_follows_the_presenter():
    with room(1) as (lab, presenter, (follower,)):
        poll(lambda: follower.role.following)
        lab.classroom.camera(presenter.key, (2.0, -1.0, 1.5), (0.1, 0.0, 0.3), (0.0, 0.0, 1.0))
        assert np.asarray(follower.client.camera.position) == pytest.approx([2.0, -1.0, 1.5])
        assert np.asarray(follower.client.camera.look_at) == pytest.approx([0.1, 0.0, 0.3])
        lab.classroom.camera(follower.key, (9.0, 9.0, 9.0), (0, 0, 0), (0, 0, 1))  # not the presenter
        assert np.asarray(presenter.client.camera.position) != pytest.approx([9.0, 9.0, 9.0])


def test_wrong_tokens_change_nothing():
    with room(1) as (lab, presenter, (follower,)):
        poll(lambda: follower.role.following)
        follower.panel.classroom.token.value = "lecture-8"
        poll(lambda: lab.classroom.wrong_tries(follower.key) == 1)
        assert presenter.role.presenting and not follower.role.presenting and follower.role.following


@pytest.mark.slow
def test_the_presenter_leaving_leaves_the_followers_where_they_were():
    with running_lab(presenter_token=TOKEN) as (lab, _, _ws):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as presenter_ws:
            poll(lambda: len(lab.sessions) == 2)
            presenter = lab.session()
            follower = next(s for s in lab.sessions.values() if s is not presenter)
            presenter.panel.classroom.token.value = TOKEN
            poll(lambda: follower.role.following)
            presenter.dispatch(SetJoint(1, 0.9))
            poll(lambda: follower.state.q[1] == pytest.approx(0.9))
        presenter_ws.close()
        poll(lambda: not follower.role.presenter)
        settle(follower)
        assert not follower.role.following and follower.state.q[1] == pytest.approx(0.9)
        follower.dispatch(SetJoint(1, 0.2))  # explores on its own now
        settle(follower)
        assert follower.state.q[1] == pytest.approx(0.2)


def test_tokens_are_limited_per_connection_and_hold_no_other_tab_back():
    room_ = Classroom("right")

    class Tab:
        latest = (None, None)

        def subscribe(self, fn):
            return lambda: None

        def mirror(self, state, snapshot):
            pass

        def mirror_camera(self, *pose):
            pass

        def role_changed(self, role):
            self.role = role

    a, b = Tab(), Tab()
    room_.join(1, a)
    room_.join(2, b)
    for _ in range(TOKEN_TRIES):
        assert room_.claim(1, "wrong") == "that is not the presenter token"
    # This connection is spent, even for the right token (a reload is a new connection) ...
    assert room_.claim(1, "right").startswith(f"this tab has typed {TOKEN_TRIES} wrong tokens")
    assert not room_.role(1).presenting and room_.wrong_tries(1) == TOKEN_TRIES
    assert room_.claim(2, "right") == ""  # ... and no other tab is held back
    assert room_.role(2).presenting and room_.role(1).following
    room_.closed(1)
    room_.join(3, a)  # the student's reload: a new connection with its own tries
    assert room_.claim(3, "right") == WAITING  # taken: tab 2 presents, so it is asked first
    room_.answer(2, accept=True)
    assert room_.role(3).presenting and not room_.role(2).presenting
    room_.closed(3)
    assert b.role.note == PRESENTER_AWAY and not b.role.following
    with pytest.raises(ValueError):
        Classroom("")


def test_followers_draw_a_robot_only_the_presenter_has():
    """A robot built in the presenter's Build tab (not in the followers' lists) still reaches them."""
    from app.core.actions import EditRobot
    from kinematics import Robot, jacobian

    with room(1) as (lab, presenter, (follower,)):
        poll(lambda: follower.role.following)
        rows = [
            {"joint": "revolute", "a": 0.4, "alpha": 0.0, "d": 0.0, "theta": 0.0},
            {"joint": "revolute", "a": 0.3, "alpha": 0.0, "d": 0.0, "theta": 0.0},
        ]
        built = Robot.from_dh(rows, "standard", name="built")
        presenter.dispatch(EditRobot("(built in the browser)", built, ()))
        settle(presenter)
        poll(lambda: follower.state.robot is built)
        settle(follower)
        assert follower.errors == 0
        assert follower.snapshot.J_base == pytest.approx(jacobian(built, follower.state.q))
        assert_all_finite(follower)
        # It is listed in the follower's own robots: after exploring, the student can go back to it.
        assert "(built in the browser)" in follower.panel.robot.options
        assert follower.catalog.load("(built in the browser)") is built


def test_a_followers_browser_gets_the_presenters_scene():
    """The scene messages of the presenter's redraw are replayed to the followers' browsers: what a
    follower's websocket receives for the arm is what the presenter's scene holds."""
    from app_helpers import scene_node, scene_update_to

    with running_lab(presenter_token=TOKEN) as (lab, presenter, _ws):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as student:
            poll(lambda: len(lab.sessions) == 2)
            follower = next(s for s in lab.sessions.values() if s is not presenter)
            presenter.panel.classroom.token.value = TOKEN
            poll(lambda: follower.role.following)
            settle(presenter, follower)
            for value in (-0.4, 0.3, 0.8):
                mark = student.mark()
                presenter.dispatch(SetJoint(1, value))
                settle(presenter)
                poll(lambda value=value: follower.state.q[1] == pytest.approx(value))
                settle(follower)
                arm = scene_node(presenter, "/lab/arm/cylinders")
                want = np.asarray(arm.batched_positions, dtype=np.float32).ravel()

                student.wait_for(scene_update_to("/lab/arm/cylinders", want), after=mark)
            # Exploring alone again: the follower's own scene is rebuilt and drawn from its state.
            follower.dispatch(ExploreAlone())
            settle(follower)
            poll(lambda: not follower.role.following)
            follower.dispatch(SetJoint(0, 0.5))
            settle(follower)
            own = np.asarray(scene_node(follower, "/lab/arm/cylinders").batched_positions).reshape(-1, 3)
            theirs = np.asarray(scene_node(presenter, "/lab/arm/cylinders").batched_positions).reshape(-1, 3)
            assert not np.allclose(own, theirs)
            assert_all_finite(follower)


def test_typing_the_token_key_by_key_tries_it_once():
    """A browser sends every keystroke: the half-typed token must not use up the tab's tries."""
    with room(1) as (lab, presenter, (follower,)):
        token = follower.panel.classroom.token
        for k in range(1, len(TOKEN) + 1):
            token.value = TOKEN[:k]  # as typed, key by key
        poll(lambda: presenter.role.asked and follower.role.waiting)  # the presenter is asked once
        presenter.dispatch(AnswerHandover(accept=True))
        poll(lambda: follower.role.presenting)
        assert not presenter.role.presenting and presenter.role.following
        assert lab.classroom.wrong_tries(follower.key) == 0


def test_the_presenter_closing_while_it_redraws_does_not_deadlock():
    """A presenter's redraw holds its session's lock and asks the classroom to relay; its tab closing
    at that moment makes the classroom unsubscribe, which needs the session's lock. The classroom never
    holds its own lock while it calls into a session, so both finish."""
    import threading

    room_ = Classroom("t")
    relays = []
    session_lock = threading.RLock()
    unsubscribing = threading.Event()

    class Tab:
        latest = (None, None)
        scene_messages = ()

        def subscribe(self, fn):
            relays.append(fn)

            def unsubscribe():
                unsubscribing.set()
                with session_lock:  # as ClientSession.subscribe's unsubscribe does
                    pass

            return unsubscribe

        def mirror(self, *args):
            pass

        def mirror_camera(self, *pose):
            pass

        def role_changed(self, role):
            pass

    room_.join(1, Tab())
    room_.join(2, Tab())
    assert room_.claim(1, "t") == ""
    done = []

    def redraw():  # the presenter's commit: its session lock held, then the relay
        with session_lock:
            started.set()
            unsubscribing.wait(POLL_TIMEOUT)
            relays[-1](None, None)  # the subscriber the classroom gave the presenter's session
        done.append("redraw")

    started = threading.Event()
    a = threading.Thread(target=redraw, daemon=True)
    a.start()
    started.wait(POLL_TIMEOUT)
    b = threading.Thread(target=lambda: (room_.closed(1), done.append("closed")), daemon=True)
    b.start()
    a.join(10)
    b.join(10)
    assert sorted(done) == ["closed", "redraw"]


# ---------------------------------------------------------------- issue 28, item 7: a hand-over


def _handover_room(n: int = 4, clock=None):
    """A classroom with tabs 1..n; tab 1 presents (by token)."""
    room_ = Classroom(TOKEN, clock=clock) if clock else Classroom(TOKEN)
    tabs = {k: MemberStub() for k in range(1, n + 1)}
    for k, tab in tabs.items():
        room_.join(k, tab)
    assert room_.claim(1, TOKEN) == ""
    return room_, tabs


def test_a_right_token_asks_the_presenter_and_replaces_it_only_when_it_hands_over():
    """On the old code claim(2) returned "" and tab 2 presented at once (tab 1 told TAKEN_OVER)."""
    room_, tabs = _handover_room()
    old_key = room_.resume_key(1)
    assert room_.claim(2, TOKEN) == WAITING
    assert room_.role(1).presenting and room_.role(1).asked and tabs[1].notes[-1] == ASKED
    assert room_.role(2).waiting and room_.role(2).following and tabs[2].notes[-1] == WAITING
    assert not room_.role(3).asked and not room_.role(3).waiting and not tabs[3].notes
    room_.answer(1, accept=True)
    assert room_.role(2).presenting and not room_.role(2).waiting and not room_.role(2).asked
    assert room_.role(1).following and tabs[1].notes[-1] == HANDED_OVER
    assert tabs[3].notes == [HANDED_OVER_ROOM] and tabs[4].notes == [HANDED_OVER_ROOM]
    new_key = room_.resume_key(2)
    assert new_key and new_key != old_key and room_.resume_key(1) == ""
    room_.closed(2)
    room_.join(5, MemberStub())
    assert room_.resume(5, old_key) is False and room_.resume(5, new_key) is None  # the new key only


def test_a_presenter_that_refuses_keeps_presenting_and_the_tab_may_ask_again():
    room_, tabs = _handover_room()
    assert room_.claim(2, TOKEN) == WAITING
    room_.answer(1, accept=False)
    assert room_.role(1).presenting and not room_.role(1).asked
    assert tabs[2].notes[-1] == KEPT and room_.role(2).following and not room_.role(2).waiting
    assert room_.claim(2, TOKEN) == WAITING and room_.role(1).asked  # a new request
    room_.answer(1, accept=True)
    assert room_.role(2).presenting


def test_only_the_presenter_s_answer_counts():
    room_, tabs = _handover_room()
    assert room_.claim(2, TOKEN) == WAITING
    for forger in (2, 3, 99):  # the asking tab itself, a follower, a tab that is not there
        room_.answer(forger, accept=True)
    assert room_.role(1).presenting and room_.role(1).asked and room_.role(2).waiting
    room_.answer(3, accept=False)  # nor refuse in its name
    assert room_.role(1).asked and room_.role(2).waiting and tabs[2].notes[-1] == WAITING


def test_no_answer_changes_nothing_and_a_newer_request_replaces_an_older_one():
    room_, tabs = _handover_room()
    assert room_.claim(2, TOKEN) == WAITING
    assert room_.claim(3, TOKEN) == WAITING
    assert not room_.role(2).waiting and room_.role(3).waiting and room_.role(1).presenting
    room_.answer(1, accept=True)
    assert room_.role(3).presenting and room_.role(2).following and room_.role(1).following


def test_the_asking_tab_closing_withdraws_its_request():
    room_, tabs = _handover_room()
    assert room_.claim(2, TOKEN) == WAITING
    room_.closed(2)
    assert room_.role(1).presenting and not room_.role(1).asked and not tabs[1].role.asked
    room_.answer(1, accept=True)  # too late: nothing to grant
    assert room_.role(1).presenting


def test_with_no_presenter_connected_a_right_token_presents_at_once():
    clock = FakeClock()
    room_, tabs = _handover_room(clock=clock)
    assert room_.claim(2, TOKEN) == WAITING
    room_.closed(1)  # the presenter's tab closed (within the resume grace): the request is dropped
    assert not room_.role(2).waiting and not room_.role(3).presenter
    assert room_.claim(3, TOKEN) == "" and room_.role(3).presenting


def test_the_presenter_s_reconnect_key_takes_over_at_once():
    """Only the teacher's browser has it: a second tab of that browser presents without asking."""
    room_, tabs = _handover_room()
    key = room_.resume_key(1)
    assert room_.claim(2, TOKEN) == WAITING
    assert room_.resume(3, key) is None  # no state committed yet
    assert room_.role(3).presenting and not room_.role(3).asked and not room_.role(2).waiting
    assert room_.role(1).following and tabs[1].notes[-1] == TAKEN_OVER
