"""Issue 29 item 8 in the app: the several IK solutions of one pose, found, listed and selectable, merging
as the arm nears a singularity (planar 2R: elbow up (q1, q2) and down (q1 + q2, −q2), by hand)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fakes import poll

import robots
from app.core.actions import IkSolutionsFound, SelectIkSolution, SetConfiguration
from app.core.commands import ChooseRobot, FindIkSolutions
from app.core.reducer import InvalidAction, reduce
from app.core.state import LabState
from app.services.background import ik_solutions
from kinematics import fk


def test_the_planar_2r_has_elbow_up_and_down_and_either_can_be_chosen():
    state = reduce(LabState.initial("planar2", robots.load("planar2")), SetConfiguration((0.2, 1.0)))
    with pytest.raises(InvalidAction, match="one of the solutions found"):
        reduce(state, SelectIkSolution(0))  # none found yet
    state = reduce(state, ik_solutions(state.robot, state.robot_name, np.array(state.q)))
    assert np.allclose(state.motion.solutions, [[0.2, 1.0], [1.2, -1.0]], atol=1e-9)
    assert np.allclose(state.q, (0.2, 1.0))  # finding does not move the arm
    other = reduce(state, SelectIkSolution(1))
    assert np.allclose(other.q, (1.2, -1.0), atol=1e-9)
    assert np.abs(fk(other.robot, other.q)[:3, 3] - fk(state.robot, state.q)[:3, 3]).max() < 1e-9
    for bad in (2, -1, True, 1.0, "1"):
        with pytest.raises(InvalidAction):
            reduce(state, SelectIkSolution(bad))  # type: ignore[arg-type]


def test_the_puma_solutions_reach_the_same_pose():
    state = LabState.initial("puma560", robots.load("puma560"))
    state = reduce(state, ik_solutions(state.robot, state.robot_name, np.array(state.q)))
    T = fk(state.robot, state.q)
    assert len(state.motion.solutions) >= 3
    for k in range(len(state.motion.solutions)):
        assert np.abs(fk(state.robot, reduce(state, SelectIkSolution(k)).q) - T).max() < 1e-9


def test_the_panel_lists_the_solutions_and_says_how_far_apart_they_are(session):
    session.dispatch(ChooseRobot("planar2"))
    session.settle()
    panel = session.panel.motion.course.solutions
    assert panel.menu.disabled and "press Find" in panel.words.content
    for q2, gap in ((1.0, math.sqrt(5) * 1.0), (0.05, math.sqrt(5) * 0.05)):  # √5 q2 with l1 = l2 = 1
        session.dispatch(SetConfiguration((0.2, q2)))
        session.dispatch(FindIkSolutions())
        poll(
            lambda: (
                session.state.motion.solutions is not None
                and np.allclose(session.state.motion.solutions[0], (0.2, q2))  # noqa: B023
            )
        )
        session.settle()
        assert len(panel.menu.options) == 2 and not panel.menu.disabled
        assert "2 IK solutions reach this pose" in panel.words.content
        assert f"{gap:.3g}" in panel.words.content
    assert panel._select("no such entry") is None
    session.dispatch(panel._select(panel.menu.options[1]))
    session.settle()
    assert np.allclose(session.state.q, (0.25, -0.05), atol=1e-9)
    assert panel.menu.value == panel.menu.options[1]
    assert "press Find again" not in panel.words.content  # the other elbow reaches the same point
    session.dispatch(SetConfiguration((0.5, 0.5)))
    session.settle()
    assert "press Find again" in panel.words.content


def test_the_reducer_only_keeps_solutions_found_elsewhere_and_drops_stale_ones():
    """The search runs in the background (app.services.background.ik_solutions); the reducer takes the
    action's rows as they are (elbow up / down of the planar 2R by hand) and drops them if the arm moved."""
    state = reduce(LabState.initial("planar2", robots.load("planar2")), SetConfiguration((0.2, 1.0)))
    T = tuple(float(x) for x in fk(state.robot, state.q).ravel())
    rows = ((0.2, 1.0), (1.2, -1.0))
    kept = reduce(state, IkSolutionsFound("planar2", tuple(state.q), T, rows))
    assert np.array_equal(kept.motion.solutions, rows) and np.array_equal(kept.q, state.q)
    moved = reduce(state, SetConfiguration((0.3, 1.0)))
    assert reduce(moved, IkSolutionsFound("planar2", tuple(state.q), T, rows)) is moved  # another pose now
    with pytest.raises(InvalidAction, match="finite joint values"):
        reduce(state, IkSolutionsFound("planar2", tuple(state.q), T, ((0.2, math.nan), (1.2, -1.0))))
