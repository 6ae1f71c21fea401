"""Issue 29 item 7 in the app: a joint at its limit makes the configuration a critical point (002: the
singular points and the joint-limit points); the status says which joint, the sense it can still move
in, and that the tool velocity along its column of J is possible in that sense only."""

from __future__ import annotations

import numpy as np
import pytest
from fakes import poll

import robots
from app.core.actions import Play, SetConfiguration, SetDesired, SetJoint, SetRobot
from app.core.i18n import translations
from app.core.reducer import reduce
from app.core.snapshot import compute
from app.core.state import LabState
from app.views.panel.readouts import status_html
from kinematics import fk, jacobian


def test_a_slider_at_its_end_names_the_critical_point_and_the_one_sense_left():
    state = LabState.initial("puma560", robots.load("puma560"))
    assert compute(state).limits == () and "Critical point" not in status_html(compute(state), state)
    state = reduce(state, SetJoint(1, 10.0))  # past the upper limit: the slider stops at it
    snap = compute(state)
    (c,) = snap.limits
    assert (c.joint, c.side, c.sense) == (1, "upper", -1)
    assert np.allclose(c.column, -jacobian(state.robot, state.q)[:, 1])
    # the only velocity left along that column is −J₂: a small step q₂ − h moves the tool by ≈ −h J₂
    h = 1e-6
    q = np.array(state.q)
    q[1] -= h
    moved = (fk(state.robot, q)[:3, 3] - fk(state.robot, state.q)[:3, 3]) / h
    assert np.allclose(moved, c.column[:3], atol=1e-5)
    html = status_html(snap, state)
    assert "Critical point" in html and "upper limit" in html and "q̇2 ≤ 0" in html
    es = status_html(snap, state, translations("es"))
    assert "Punto crítico" in es and "límite articular superior" in es


@pytest.mark.parametrize(
    ("code", "joint"),
    [
        ("en", "joint q2 shoulder is at"),
        ("pt", "a junta q2 shoulder está"),
        ("es", "la articulación q2 shoulder está"),
        ("pl", "przegub q2 shoulder jest"),
    ],
)
def test_the_critical_point_names_the_joint_once_in_each_language(code, joint):
    """The joint's name carries its number ("q2 shoulder"): the line says it once, never "joint 2 (q2 shoulder)"."""
    state = reduce(LabState.initial("puma560", robots.load("puma560")), SetJoint(1, 10.0))
    html = status_html(compute(state), state, translations(code))
    line = next(x for x in html.split("<br>") if "q̇2 ≤ 0" in x)
    assert joint in line and line.count("q2 shoulder") == 1 and "2 (" not in line, line


def test_the_lower_limit_says_the_joint_can_only_increase():
    state = reduce(LabState.initial("planar2", robots.load("planar2")), SetJoint(0, -10.0))
    (c,) = compute(state).limits
    assert (c.joint, c.side, c.sense) == (0, "lower", 1)
    assert "q̇1 ≥ 0" in status_html(compute(state), state)


def test_a_resolved_rate_motion_that_meets_a_limit_stops_at_it_and_the_status_names_it_critical(session):
    """The Puma raising its tool (vz = 0.2 m/s) from a bent elbow meets q3's upper limit (45°) during
    Play: the motion ends ON the limit (not a step before it), so the status names the configuration
    critical, as 002 does, and says why; the tool moved along the twist asked for."""
    puma = robots.load("puma560")
    q0 = np.zeros(6)
    q0[1], q0[2], q0[4] = puma.qlim[1, 1] - 0.3, 0.5, 0.6
    session.dispatch(SetRobot("puma560", puma))
    session.dispatch(SetConfiguration(tuple(float(x) for x in q0)))
    session.dispatch(SetDesired(2, 0.2))
    session.settle()
    assert "Critical point" not in session.panel.status.content
    session.dispatch(Play(True, "resolved_rate"))
    poll(lambda: session.state.motion.kind == "resolved_rate" and not session.state.playing, what="the stop")
    state = session.state
    assert "would pass its upper limit 45°" in state.stopped
    assert state.q[2] == pytest.approx(puma.qlim[1, 2], abs=1e-12)  # AT the limit
    assert (np.array(state.q) <= puma.qlim[1] + 1e-12).all() and (
        np.array(state.q) >= puma.qlim[0] - 1e-12
    ).all()
    rise = fk(puma, state.q)[:3, 3] - fk(puma, q0)[:3, 3]  # up; Euler steps drift sideways a little
    assert rise[2] > 0.05 and np.abs(rise[:2]).max() < 1e-2 * rise[2]
    (c,) = compute(state).limits
    assert (c.joint, c.side, c.sense) == (2, "upper", -1)
    session.settle()
    # Once a motion has stopped its lines are beside its rates, over the 3-D view (issue 28, stumble 4).
    live = session.panel.live
    status = poll(lambda: live.visible and "Critical point" in live.content and live.content)
    assert "upper limit" in status and "q̇3 ≤ 0" in status
    assert "Critical point" not in session.panel.status.content  # not twice
