"""The acceleration map in the v = J q̇ tab: q̈ as state (issue 29, item 6) and 000's per-joint J̇ᵢ
beside J̇ (item 2), at server level, against finite differences of fk and J."""

from __future__ import annotations

import math

import numpy as np
import pytest
from app_helpers import assert_all_finite, scene_node

import robots
from app.core.actions import SetAcceleration, SetRate, StopRates
from app.core.commands import ChooseRobot
from app.core.ranges import accel_ranges
from app.core.reducer import InvalidAction, reduce
from app.core.state import LabState
from app.services.catalog import RobotCatalog
from app.services.state_codec import RobotWire, decode_state, dumps, encode_state, loads
from app.views.palette import ACCEL_RGB, JQDD_RGB
from app.viser_adapter import node_props
from kinematics import fk, jacobian

H = 1e-4


def _choose(session, name: str) -> None:
    session.dispatch(ChooseRobot(name))
    session.dispatch(StopRates())
    for i in range(session.state.robot.dof):
        session.dispatch(SetAcceleration(i, 0.0))
    session.settle()


def _tool_accel_fd(robot, q, qd, qdd) -> np.ndarray:
    """ẍ of the tool point along q(t) = q + q̇ t + ½ q̈ t²: the second central difference of fk."""

    def x(t: float) -> np.ndarray:
        return fk(robot, q + qd * t + 0.5 * qdd * t * t)[:3, 3]

    return (x(H) - 2 * x(0.0) + x(-H)) / (H * H)


def _jdot_fd(robot, q, qd) -> np.ndarray:
    h = 1e-6
    return (jacobian(robot, q + h * qd) - jacobian(robot, q - h * qd)) / (2 * h)


def test_set_acceleration_is_clamped_and_refused_when_not_finite():
    puma = robots.load("puma560")
    state = LabState.initial("puma560", puma)
    assert np.array_equal(state.qdd, np.zeros(6)) and not state.qdd.flags.writeable
    after = reduce(state, SetAcceleration(2, 1.5))
    assert after.qdd[2] == 1.5 and state.qdd[2] == 0.0
    top = math.radians(accel_ranges(puma)[0].hi)
    assert reduce(state, SetAcceleration(0, 1e9)).qdd[0] == pytest.approx(top)
    with pytest.raises(InvalidAction, match="finite"):
        reduce(state, SetAcceleration(0, math.inf))
    with pytest.raises(InvalidAction):
        reduce(state, SetAcceleration(6, 1.0))


def test_followers_receive_qdd_and_an_older_state_without_it_reads_zero():
    catalog = RobotCatalog([])
    wire = RobotWire(catalog)
    state = reduce(LabState.initial("puma560", catalog.load("puma560")), SetAcceleration(1, -0.75))
    data = loads(dumps(encode_state(state, wire.reference(state))))
    assert decode_state(data, wire).qdd[1] == -0.75
    del data["state"]["f"]["qdd"]  # what a presenter without q̈ sends
    assert np.array_equal(decode_state(data, wire).qdd, np.zeros(6))


def test_j_qdd_and_jdot_qd_sum_to_the_second_difference_of_fk_and_both_are_drawn(session):
    _choose(session, "puma560")
    robot = session.state.robot
    rates, accels = [0.5, -0.3, 0.6, 0.2, -0.4, 0.5], [1.2, -0.8, 0.9, 0.0, 0.5, -1.0]
    for i, (w, a) in enumerate(zip(rates, accels, strict=True)):
        session.dispatch(SetRate(i, w))
        session.dispatch(SetAcceleration(i, a))
    session.settle()
    q, qd, qdd = (np.array(x) for x in (session.state.q, session.state.qd, session.state.qdd))
    np.testing.assert_allclose(qdd, accels)
    snap = session.snapshot
    np.testing.assert_allclose(snap.j_qdd, jacobian(robot, q) @ qdd, atol=1e-12)
    np.testing.assert_allclose(snap.tool_accel[:3], _tool_accel_fd(robot, q, qd, qdd), atol=2e-5)
    np.testing.assert_allclose(snap.tool_accel, snap.j_qdd + snap.jdot_qd, atol=1e-12)
    tool = fk(robot, q)[:3, 3]
    for name, term, rgb in (("j_qdd", snap.j_qdd, JQDD_RGB), ("jdot_qd", snap.jdot_qd, ACCEL_RGB)):
        props = node_props(scene_node(session, f"/lab/jacobian/{name}"))
        assert props["visible"], name
        start, end = np.asarray(props["points"], float)[0]
        np.testing.assert_allclose(start, tool, atol=1e-5)
        d = end - start
        assert np.dot(d, term[:3]) / (np.linalg.norm(d) * np.linalg.norm(term[:3])) == pytest.approx(1.0)
        assert tuple(np.asarray(props["colors"]).reshape(-1, 3)[0]) == rgb
    html = session.panel.forward.accel.content
    assert "J q̈" in html and "magenta" in html and "here q̈ = 0" not in html
    # q̇ = 0 with q̈ ≠ 0: J q̈ alone, still shown and drawn
    session.dispatch(StopRates())
    session.settle()
    assert "J q̈" in session.panel.forward.accel.content
    assert node_props(scene_node(session, "/lab/jacobian/j_qdd"))["visible"]
    assert not node_props(scene_node(session, "/lab/jacobian/jdot_qd"))["visible"]
    np.testing.assert_allclose(
        session.snapshot.tool_accel[:3], _tool_accel_fd(robot, q, np.zeros(6), qdd), atol=2e-5
    )
    assert_all_finite(session)


def test_the_per_joint_jdot_agrees_for_one_joint_and_not_for_several(session):
    _choose(session, "puma560")
    robot = session.state.robot
    session.dispatch(SetRate(1, 0.8))  # the shoulder alone
    session.settle()
    q, qd = np.array(session.state.q), np.array(session.state.qd)
    snap = session.snapshot
    fd = _jdot_fd(robot, q, qd)
    np.testing.assert_allclose(snap.jdot_alone[:, 1], fd[:, 1], atol=1e-6)  # column 2 is 000's J̇₂
    np.testing.assert_allclose(snap.jdot_gap, 0.0, atol=1e-9)
    html = session.panel.forward.accel.content
    assert "Only" in html and "jl-warn" not in html.split("J̇ beside")[0].split("derives J̇ᵢ")[1]
    for i, w in enumerate([0.5, 0.8, -0.6, 0.4, 0.7, -0.3]):
        session.dispatch(SetRate(i, w))
    session.settle()
    q, qd = np.array(session.state.q), np.array(session.state.qd)
    snap = session.snapshot
    fd = _jdot_fd(robot, q, qd)
    np.testing.assert_allclose(snap.jdot, fd, atol=1e-6)
    gap = fd @ qd - snap.jdot_terms.sum(axis=1)
    np.testing.assert_allclose(snap.jdot_gap, gap, atol=1e-6)
    assert np.linalg.norm(gap[:3]) > 0.05
    html = session.panel.forward.accel.content
    assert "6 joints move" in html and "jl-warn" in html
    assert_all_finite(session)
