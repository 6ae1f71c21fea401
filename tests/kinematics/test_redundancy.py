"""Self-motion and the manipulability climb q̇ = (I − J⁺J) ∇w (kinematics.motion.redundancy)."""

from __future__ import annotations

import numpy as np
import pytest
from fakes import random_q

import robots
from kinematics import ConfigurationError, JacobianLabError, OptionError, fk, jacobian, manipulability
from kinematics.motion.redundancy import (
    climb,
    climb_step,
    manipulability_gradient,
    self_motion,
    self_motion_step,
    task_manipulability,
)

CASES = [("panda", None, list(range(6))), ("iiwa14", None, list(range(6))), ("planar3", (0, 1), [0, 1])]


def held(robot, T0, T, rows):
    """Largest change of the held task quantities (position rows and/or orientation)."""
    gap = 0.0
    lin = [r for r in rows if r < 3]
    if lin:
        gap = max(gap, np.abs(T[:3, 3] - T0[:3, 3])[lin].max())
    if any(r >= 3 for r in rows):
        gap = max(gap, np.abs(T[:3, :3] - T0[:3, :3]).max())
    return gap


@pytest.mark.parametrize(("name", "rows", "row_list"), CASES)
def test_self_motion_holds_the_tool_and_moves_along_the_null_space(name, rows, row_list):
    robot = robots.load(name)
    q0 = robot.home
    sm = self_motion(robot, q0, step=0.02, steps=100, rows=rows)
    assert (
        sm.q.shape == (101, robot.dof) and sm.w.shape == (101,) and np.allclose(sm.s, 0.02 * np.arange(101))
    )
    T0 = fk(robot, q0)
    assert max(held(robot, T0, fk(robot, q), row_list) for q in sm.q) < 1e-5
    steps = np.diff(sm.q, axis=0)
    assert np.linalg.norm(sm.q[-1] - q0) > 0.5  # it really moved
    assert np.allclose(np.linalg.norm(steps, axis=1), 0.02, rtol=1e-3)  # corrections are tiny
    # consistent direction: consecutive steps agree, no back-and-forth
    cos = np.sum(steps[1:] * steps[:-1], axis=1) / (0.02**2)
    assert cos.min() > 0.9
    # each step is (to first order: the remainder is O(step²)) in the null space of the task rows
    for q, d in zip(sm.q[:-1], steps, strict=True):
        J = jacobian(robot, q)[row_list]
        assert np.linalg.norm(J @ d) < 0.01 * np.linalg.norm(J) * 0.02
    for q, w in zip(sm.q[::25], sm.w[::25], strict=True):
        assert w == pytest.approx(manipulability(jacobian(robot, q), tuple(row_list)), rel=1e-9)


def test_self_motion_step_direction_is_orthogonal_to_the_task_rows():
    robot = robots.load("panda")
    rng = np.random.default_rng(2)
    q = random_q(robot, rng)
    _, d = self_motion_step(robot, q, step=1e-3)
    J = jacobian(robot, q)
    assert np.linalg.norm(d) == pytest.approx(1.0) and np.abs(J @ d).max() < 1e-12
    # the sign follows the previous direction
    _, d2 = self_motion_step(robot, q, step=1e-3, direction=-d)
    assert np.allclose(d2, -d)


@pytest.mark.parametrize("name", ["puma560", "ur5", "planar2"])
def test_no_redundancy_is_an_error(name):
    robot = robots.load(name)
    with pytest.raises(OptionError, match="no redundancy") as info:
        self_motion(robot, robot.home, step=0.01, steps=3)
    assert "rows" in str(info.value)
    with pytest.raises(OptionError, match="no redundancy"):
        climb(robot, robot.home, steps=3)


def test_gradient_matches_finite_differences_of_manipulability():
    robot = robots.load("panda")
    q = random_q(robot, np.random.default_rng(4))
    g = manipulability_gradient(robot, q, list(range(6)))
    for i in range(robot.dof):
        e = np.zeros(robot.dof)
        e[i] = 1e-5
        fd = (manipulability(jacobian(robot, q + e)) - manipulability(jacobian(robot, q - e))) / 2e-5
        assert g[i] == pytest.approx(fd, abs=1e-7)
    assert task_manipulability(robot, q[None], list(range(6)))[0] == pytest.approx(
        manipulability(jacobian(robot, q))
    )


@pytest.mark.parametrize(("name", "rows", "row_list"), CASES + [("panda", "linear", [0, 1, 2])])
def test_climb_raises_w_and_holds_the_tool(name, rows, row_list):
    robot = robots.load(name)
    rng = np.random.default_rng(8)
    q0 = robot.home if name == "planar3" or rows == "linear" else robot.home + rng.normal(0, 0.3, robot.dof)
    cl = climb(robot, q0, steps=25, rows=rows)
    assert cl.q.shape == (26, robot.dof) and cl.w.shape == (26,)
    assert np.all(np.diff(cl.w) >= 0)
    assert np.all(np.diff(cl.w[:6]) > 0)  # strictly increasing while away from the maximum
    T0 = fk(robot, q0)
    assert max(held(robot, T0, fk(robot, q), row_list) for q in cl.q) < 1e-5
    for q, w in zip(cl.q[::5], cl.w[::5], strict=True):
        assert w == pytest.approx(manipulability(jacobian(robot, q), tuple(row_list)), rel=1e-9)


def test_panda_ready_pose_is_a_maximum_of_w_along_its_self_motion():
    """Over all six rows the ready pose is symmetric: w is even along the self-motion and largest
    there, so the climb stays put (w never decreases) while the self-motion lowers w."""
    robot = robots.load("panda")
    sm = self_motion(robot, robot.home, step=0.05, steps=4)
    assert np.all(np.diff(sm.w) < 0)
    q_next, w_next = climb_step(robot, robot.home)
    assert w_next == pytest.approx(sm.w[0], rel=1e-12) and np.allclose(q_next, robot.home, atol=1e-9)


@pytest.mark.parametrize(
    ("call", "error", "word"),
    [
        (lambda r: self_motion(r, r.home, step=np.nan, steps=3), OptionError, "step"),
        (lambda r: self_motion(r, r.home, step=0.1, steps=-1), OptionError, "steps"),
        (lambda r: self_motion(r, [0.0], step=0.1, steps=1), ConfigurationError, "q"),
        (lambda r: self_motion_step(r, r.home, step=0.1, direction=[1.0]), OptionError, "direction"),
        (lambda r: climb(r, r.home, steps=2, gain=-1.0), OptionError, "gain"),
        (lambda r: climb_step(r, r.home, max_step=0.0), OptionError, "max_step"),
        (lambda r: climb(r, r.home, steps=2, rows=(9,)), OptionError, "rows"),
    ],
)
def test_bad_inputs(call, error, word):
    with pytest.raises(error, match=word) as info:
        call(robots.load("panda"))
    assert isinstance(info.value, JacobianLabError)
