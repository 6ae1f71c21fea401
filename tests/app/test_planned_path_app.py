"""Issue 29 item 5: the path y(t) the student picks is drawn in the 3-D view before it is followed (a
polyline from the tool point: where the tool will go), stays put while it is followed (the tool runs along
it), and goes when the path is cleared or the robot changes."""

from __future__ import annotations

import numpy as np
import pytest
from fakes import poll

import robots
from app.core.actions import ChooseToolPath, FollowToolPath, SetConfiguration, SetJoint, SetRobot
from app.core.reducer import InvalidAction, reduce
from app.core.state import LabState
from app.core.tool_path import SAMPLES, SECONDS, SIZE, laid_out
from app.services.catalog import RobotCatalog
from app.services.state_codec import RobotWire, decode_state, dumps, encode_state, loads
from app.views.palette import PLANNED_RGB
from kinematics import fk


def drawn(session) -> np.ndarray | None:
    """The scene's polyline of the chosen path as points (k, 3), ``None`` when hidden."""
    line = session.scene.planned.line
    if not line.visible:
        return None
    segments = np.asarray(line.points, dtype=float)
    assert np.array_equal(segments[1:, 0], segments[:-1, 1])  # one polyline, end to end
    return np.vstack([segments[:, 0], segments[-1:, 1]])


def samples(state: LabState, shape: str) -> np.ndarray:
    path = laid_out(state, shape)
    return np.array([path.point(t) for t in np.linspace(0.0, SECONDS, SAMPLES)])


def test_picking_a_path_draws_y_of_t_from_the_tool_point(session):
    session.dispatch(SetRobot("planar2", robots.load("planar2")))
    session.dispatch(SetConfiguration((0.3, 1.2)))
    session.settle()
    assert drawn(session) is None  # nothing chosen yet
    menu = session.panel.motion.course.path
    assert menu.button.disabled
    session.dispatch(ChooseToolPath("line"))
    session.settle()
    state = session.state
    p = drawn(session)
    assert p is not None and len(p) == SAMPLES
    assert np.allclose(p, samples(state, "line"), atol=1e-6)  # float32 on the wire
    # independently: a straight segment from the tool point, 2·0.15 m along the base y axis, evenly
    tool = fk(state.robot, state.q)[:3, 3]
    assert np.allclose(p[0], tool, atol=1e-6)
    assert np.allclose(p - tool, np.outer(np.linspace(0, 2 * SIZE, SAMPLES), [0, 1, 0]), atol=1e-6)
    assert tuple(np.asarray(session.scene.planned.line.colors).reshape(-1, 3)[0]) == PLANNED_RGB
    assert not menu.button.disabled and "line" in str(menu.shape.value)
    # a circle: every point 0.15 m from one centre in the x–y plane (a planar arm), through the tool point
    session.dispatch(ChooseToolPath("circle"))
    session.settle()
    c = drawn(session)
    assert c is not None and np.allclose(c[0], tool, atol=1e-6) and np.allclose(c[0], c[-1], atol=1e-6)
    centre = c[: SAMPLES - 1].mean(axis=0)
    assert np.allclose(np.linalg.norm(c - centre, axis=1), SIZE, atol=1e-6) and np.allclose(c[:, 2], tool[2])
    # the arm moved by hand: the path to come starts at the new tool point
    session.dispatch(SetJoint(0, 0.5))
    session.settle()
    moved = fk(session.state.robot, session.state.q)[:3, 3]
    assert np.allclose(drawn(session)[0], moved, atol=1e-6) and not np.allclose(moved, tool, atol=1e-3)


def test_the_path_stays_while_followed_and_goes_when_cleared_or_the_robot_changes(session):
    session.dispatch(SetRobot("planar2", robots.load("planar2")))
    session.dispatch(SetConfiguration((0.3, 1.2)))
    session.dispatch(ChooseToolPath("line"))
    session.settle()
    before = drawn(session)
    assert before is not None
    session.dispatch(FollowToolPath("line"))
    poll(lambda: session.state.motion.kind == "path" and session.state.playing)
    during = []
    while session.state.playing:
        session.settle()
        p, q = drawn(session), np.array(session.state.q)
        during.append((p, fk(session.state.robot, q)[:3, 3]))
        poll(lambda q=q: not session.state.playing or not np.array_equal(session.state.q, q))
    session.settle()
    during.append((drawn(session), fk(session.state.robot, session.state.q)[:3, 3]))
    a, b = before[0], before[-1]
    u = (b - a) / np.linalg.norm(b - a)
    for p, tool in during:
        assert p is not None and np.allclose(p, before, atol=1e-6)  # the drawn path holds still
        assert np.linalg.norm((tool - a) - ((tool - a) @ u) * u) < 1e-5  # the tool runs along it
    assert np.linalg.norm(during[-1][1] - b) < 1e-5  # and ends at its end
    session.dispatch(ChooseToolPath(""))
    session.settle()
    assert drawn(session) is None and session.panel.motion.course.path.button.disabled
    session.dispatch(ChooseToolPath("circle"))
    session.settle()
    assert drawn(session) is not None
    session.dispatch(SetRobot("puma560", robots.load("puma560")))
    session.settle()
    assert session.state.tool_path == "" and drawn(session) is None


def test_a_path_the_menu_does_not_offer_is_refused():
    state = LabState.initial("planar2", robots.load("planar2"))
    with pytest.raises(InvalidAction, match="shape must be one of line, circle or none"):
        reduce(state, ChooseToolPath("spiral"))
    assert reduce(state, ChooseToolPath("line")).tool_path == "line"


def test_followers_receive_the_chosen_path_and_an_older_state_has_none():
    catalog = RobotCatalog([])
    wire = RobotWire(catalog)
    state = reduce(LabState.initial("planar2", catalog.load("planar2")), ChooseToolPath("circle"))
    data = loads(dumps(encode_state(state, wire.reference(state))))
    assert decode_state(data, wire).tool_path == "circle"
    del data["state"]["f"]["tool_path"]  # what a presenter without the drawn path sends
    assert decode_state(data, wire).tool_path == ""
