"""A tab's state across a reload, a lost connection and a server restart (issue 21, item 10).

Server level, with tabs of a running lab (websocket clients): a presenter that comes back with its
reconnect key keeps its role and its state and the room follows it again; a tab's page restores the
robot and q of its address, checked like any widget value; followers open the presenter's tab.
The page's reports are typed into the panel's hidden report input, as the page script does.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from app_helpers import assert_all_finite, running_lab, wait_until
from wsclient import ViserWsClient

import robots
from app.core.actions import SetJoint, SetRate
from app.core.page_state import PageError, checked_q, page_address, parse_report
from app.services.classroom import PRESENTER_AWAY
from app.views.panel import TAB_LABELS

TOKEN = "lecture-7"


def report(session, **fields) -> None:
    """What the page script sends: a JSON report typed into the hidden report input."""
    session.panel.report.value = json.dumps(fields)
    session.settle()
    session.settle()  # a restore dispatches the robot, then q


def newest(lab, known):
    wait_until(lambda: any(s not in known for s in lab.sessions.values()))
    return next(s for s in lab.sessions.values() if s not in known)


def test_a_presenter_that_reloads_keeps_its_role_and_state_and_the_room_follows_again():
    with running_lab(presenter_token=TOKEN) as (lab, follower, _ws):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as first_ws:
            presenter = newest(lab, {follower})
            presenter.panel.classroom.token.value = TOKEN
            wait_until(lambda: presenter.role.presenting and follower.role.following)
            key = lab.classroom.resume_key(presenter.key)
            assert key and TOKEN not in key and len(key) >= 24  # a random key, never the token
            report(presenter, kind="tab", tab="Motion")  # the presenter opens the Motion tab
            presenter.dispatch(SetJoint(1, 0.9))
            presenter.dispatch(SetRate(0, 0.3))
            presenter.settle()
            wait_until(lambda: follower.state.q[1] == pytest.approx(0.9))
            shown = presenter.state
        first_ws.close()  # the presenter reloads: its connection closes ...
        wait_until(lambda: not follower.role.presenter)
        assert follower.role.note == PRESENTER_AWAY
        assert follower.state.q[1] == pytest.approx(0.9)  # the room keeps what was shown
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}"):
            back = newest(lab, {follower})  # ... and its page connects again
            assert back.state.q[1] != pytest.approx(0.9) and not back.role.presenting
            report(back, kind="load", address="", resume=key, tab="Motion")
            wait_until(lambda: back.role.presenting and follower.role.following)
            back.settle()
            np.testing.assert_allclose(back.state.q, shown.q)
            np.testing.assert_allclose(back.state.qd, shown.qd)
            assert back.state.robot_name == shown.robot_name
            back.dispatch(SetJoint(2, -0.4))  # and the room follows it again
            back.settle()
            wait_until(lambda: follower.state.q[2] == pytest.approx(-0.4))
            assert_all_finite(back)


def test_a_wrong_or_stale_key_gives_no_role():
    with running_lab(presenter_token=TOKEN) as (lab, tab, _ws):
        report(tab, kind="load", address="", resume="x" * 32)
        assert not tab.role.presenting
        tab.panel.classroom.token.value = TOKEN
        wait_until(lambda: tab.role.presenting)
        key = lab.classroom.resume_key(tab.key)
        # The button does what it says on screen: wait until the panel says "Stop presenting".
        wait_until(lambda: tab.panel.classroom.button.label == "Stop presenting")
        tab.panel.classroom.button.value = True  # "Stop presenting": the key is void
        wait_until(lambda: not tab.role.presenting)
        assert lab.classroom.resume_key(tab.key) == ""
        report(tab, kind="load", address="", resume=key)
        assert not tab.role.presenting


def test_a_reload_restores_the_robot_and_q_of_the_address():
    ur5 = robots.load("ur5")
    q = np.array([0.1, -1.2, 1.3, -0.4, 0.5, 0.6])
    with running_lab() as (lab, tab, _ws):
        report(tab, kind="load", address=page_address("ur5", list(q)) + "&tab=Motion")
        assert tab.state.robot_name == "ur5"
        np.testing.assert_allclose(tab.state.q, q, atol=1e-6)
        assert tab.page.tab == "Motion"
        # The tab writes its robot and q back into the address as it changes.
        tab.dispatch(SetJoint(0, 0.25))
        tab.settle()
        wait_until(lambda: tab.page.address == page_address("ur5", [0.25, *q[1:]]))
        assert checked_q(ur5, tuple(q)) == pytest.approx(tuple(q))
        for k in range(12):  # a burst of changes, faster than the address is written: the last one is
            tab.dispatch(SetJoint(0, 0.3 + 0.01 * k))
            tab.settle()
        wait_until(lambda: tab.page.address == page_address("ur5", [0.41, *q[1:]]))


@pytest.mark.parametrize(
    ("address", "words"),
    [
        ("robot=nope&q=0", "there is no robot “nope”"),
        ("robot=ur5&q=1,2", "has 2 values, ur5 has 6 joints"),
        ("robot=ur5&q=nan,0,0,0,0,0", "not finite"),
        ("robot=ur5&q=1e400,0,0,0,0,0", "not finite"),
        ("robot=ur5&q=a,b", "not a list of numbers"),
        ("robot=%3Cimg%20src%3Dx%3E&q=0", "there is no robot “<img src=x>”"),
    ],
)
def test_a_hostile_address_is_refused_in_words(address, words):
    with running_lab() as (lab, tab, _ws):
        said: list[str] = []
        real = tab.notices.notify
        tab.notices.notify = lambda title, body, **k: said.append(body) or real(title, body, **k)
        before = (tab.state.robot_name, tuple(tab.state.q))
        report(tab, kind="load", address=address)
        assert any(words in s for s in said), said
        if "joints" in words or "finite" in words or "numbers" in words:
            assert tab.state.robot_name in ("ur5", before[0])
        else:
            assert (tab.state.robot_name, tuple(tab.state.q)) == before
        assert_all_finite(tab)


def test_a_q_beyond_the_sliders_is_clamped():
    with running_lab() as (lab, tab, _ws):
        report(tab, kind="load", address="robot=trr&q=99,0,0")
        assert tab.state.robot_name == "trr" and tab.state.q[0] == pytest.approx(16.0)  # q1 ≤ 16 m


def test_reports_are_checked():
    with pytest.raises(PageError):
        parse_report("x" * 5000, TAB_LABELS)
    with pytest.raises(PageError):
        parse_report("[1, 2]", TAB_LABELS)
    with pytest.raises(PageError):
        parse_report(json.dumps({"kind": "tab", "tab": "<script>"}), TAB_LABELS)
    r = parse_report(json.dumps({"kind": "load", "address": "tab=Nope", "resume": "a b"}), TAB_LABELS)
    assert r.tab == "" and r.resume == ""  # an edited tab or key is dropped, not an error


def test_followers_open_the_presenters_tab_already_filled():
    """A follower's page opens the presenter's tab only once the tab's readouts are drawn for the state
    on screen (in the same frame): it never shows what the tab held when it was last open."""
    with running_lab(presenter_token=TOKEN) as (lab, presenter, _ws):
        sent: list[tuple[str, str, str]] = []
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}"):
            follower = newest(lab, {presenter})
            report(follower, kind="load", address="")  # its page is on the first tab
            inverse = follower.panel.inverse.inverse  # a readout of the q̇ = J⁺v tab
            follower.page.show_tab = lambda label: sent.append(
                (label, follower.panel.open_tab, inverse.content)
            )
            presenter.panel.classroom.token.value = TOKEN
            wait_until(lambda: follower.role.following)
            report(presenter, kind="tab", tab="Motion")
            wait_until(lambda: [s[0] for s in sent] == ["Motion"])
            assert sent[0][1] == "Motion"  # drawn as the open tab before the page was told
            stale = inverse.content
            presenter.dispatch(SetJoint(1, 1.1))  # the follower's J⁺ tab is closed: its readout waits
            presenter.settle()
            wait_until(lambda: abs(follower.state.q[1] - 1.1) < 1e-12)
            follower.settle()
            assert inverse.content == stale
            label = next(t for t in TAB_LABELS if "J⁺" in t)
            report(presenter, kind="tab", tab=label)
            wait_until(lambda: len(sent) == 2)
            assert sent[1][:2] == (label, label)
            assert sent[1][2] != stale and sent[1][2] == presenter.panel.inverse.inverse.content  # q2 = 1.1


def test_a_redraw_fills_the_open_tab_and_a_tab_opened_is_drawn_with_the_state_on_screen():
    """Only the open tab's readouts follow a change (less work per change); the tab the page reports
    opened is drawn at once with what is on screen, as a page that never reported has it drawn."""
    with running_lab() as (lab, tab, _ws), ViserWsClient(f"ws://127.0.0.1:{lab.port}"):
        other = newest(lab, {tab})  # never reports: every tab is drawn
        assert tab.panel.open_tab == "" and other.panel.open_tab == ""
        report(tab, kind="load", address="")  # the page opens on its first tab
        assert tab.panel.open_tab == TAB_LABELS[0]
        inverse = tab.panel.inverse.inverse  # J⁻¹ of the q̇ = J⁺v tab, a readout of q
        matrix, hidden = tab.panel.matrix.numeric.content, inverse.content
        for session in (tab, other):
            session.dispatch(SetJoint(1, 1.1))
            session.settle()
        assert tab.panel.matrix.numeric.content != matrix  # the open tab follows the change
        assert tab.panel.matrix.numeric.content == other.panel.matrix.numeric.content
        assert inverse.content == hidden != other.panel.inverse.inverse.content  # the hidden one waits
        redraws = tab.redraws
        label = next(t for t in TAB_LABELS if "J⁺" in t)
        report(tab, kind="tab", tab=label)
        assert tab.panel.open_tab == label and tab.redraws == redraws + 1
        assert inverse.content == other.panel.inverse.inverse.content  # drawn at once, for this q
        assert_all_finite(tab)
