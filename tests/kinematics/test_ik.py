"""Inverse kinematics (kinematics.motion.ik.solve): the course's Newton iteration and damped least squares."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fakes import random_q
from scipy.spatial.transform import Rotation

import robots
from kinematics import (
    ArrayError,
    ConfigurationError,
    JacobianLabError,
    OptionError,
    condition_number,
    fk,
    jacobian,
)
from kinematics.motion.ik import pinv_solve, pose_error, solve

DEG = math.pi / 180


def trr_tool(q):
    """The course's closed-form TRR tool position (l1 = 10, l2 = 5, l3 = 8 m)."""
    q1, q2, q3 = q
    return np.array(
        [5 * math.sin(q2) + 8 * math.sin(q2 + q3), 10 + 5 * math.cos(q2) + 8 * math.cos(q2 + q3), q1]
    )


def test_course_trr_newton_reaches_the_course_question():
    """From q = (5 m, 60°, −15°) toward the tool position of q = (15 m, 30°, −30°): Newton gets
    there in about nine steps, converging quadratically at the end."""
    trr = robots.load("trr")
    target = trr_tool([15, 30 * DEG, -30 * DEG])
    res = solve(trr, target, [5, 60 * DEG, -15 * DEG])
    assert res.converged and res.reason == "converged"
    assert 6 <= res.iterations <= 12
    assert np.allclose(trr_tool(res.q), target, atol=1e-9)
    assert np.allclose(fk(trr, res.q)[:3, 3], target, atol=1e-9)
    # the branch reached from this start is the course's own configuration
    assert np.allclose(res.q, [15, 30 * DEG, -30 * DEG], atol=1e-9)
    e = res.errors
    assert len(e) == res.iterations + 1 and e[0] == pytest.approx(
        np.linalg.norm(target - trr_tool([5, 60 * DEG, -15 * DEG]))
    )
    assert e[-1] <= 1e-10 and e[-2] < 1e-4 and e[-1] < 10 * e[-2] ** 2  # quadratic convergence


def test_one_newton_step_is_the_course_formula():
    """q₁ = q₀ + J⁻¹(y_d − k(q₀)) with the course's J."""
    trr = robots.load("trr")
    q0 = np.array([5, 60 * DEG, -15 * DEG])
    target = trr_tool([15, 30 * DEG, -30 * DEG])
    q1, q2, q3 = q0
    J = np.array(
        [
            [0, 5 * math.cos(q2) + 8 * math.cos(q2 + q3), 8 * math.cos(q2 + q3)],
            [0, -5 * math.sin(q2) - 8 * math.sin(q2 + q3), -8 * math.sin(q2 + q3)],
            [1, 0, 0],
        ]
    )
    expected = q0 + np.linalg.solve(J, target - trr_tool(q0))
    res = solve(trr, target, q0, max_iterations=1)
    assert res.iterations == 1 and res.reason == "iteration limit"
    assert np.allclose(res.q if res.errors[1] < res.errors[0] else expected, expected, atol=1e-9)


@pytest.mark.parametrize("name", ["puma560", "panda", "iiwa14", "ur5", "stanford"])
@pytest.mark.parametrize("method", ["newton", "dls"])
def test_pose_targets_of_spatial_arms(name, method):
    robot = robots.load(name)
    rng = np.random.default_rng(7)
    goals = [q for q in random_q(robot, rng, 12) if condition_number(jacobian(robot, q)) < 50][:4]
    assert len(goals) == 4
    for q_goal in goals:  # regular goals: DLS converges only linearly near a singular one
        T_goal = fk(robot, q_goal)
        q0 = q_goal + rng.normal(0, 0.15, robot.dof)
        res = solve(robot, T_goal, q0, method=method, damping=0.01, max_iterations=200)
        assert res.converged, (res.reason, res.errors[-3:])
        T = fk(robot, res.q)
        assert np.abs(T[:3, 3] - T_goal[:3, 3]).max() < 1e-9
        assert np.abs(T[:3, :3] - T_goal[:3, :3]).max() < 1e-9


@pytest.mark.parametrize("name", ["planar3", "trr", "elbow3r", "panda"])
def test_point_targets(name):
    robot = robots.load(name)
    rng = np.random.default_rng(3)
    for _ in range(4):
        q_goal = random_q(robot, rng)
        p_goal = fk(robot, q_goal)[:3, 3]
        res = solve(robot, p_goal, q_goal + rng.normal(0, 0.2, robot.dof), max_iterations=100)
        assert res.converged
        assert np.abs(fk(robot, res.q)[:3, 3] - p_goal).max() < 1e-9
        assert res.residual.shape == ((2,) if robot.planar else (3,))


def test_pose_error_is_the_rotation_vector_of_r_target_r_tool_transposed():
    rng = np.random.default_rng(0)
    for k in range(200):
        R_tool = Rotation.random(random_state=k).as_matrix()
        angle = [1e-9, 0.3, math.pi - 1e-7, math.pi - 1e-3, rng.uniform(0, math.pi)][k % 5]
        axis = rng.normal(size=3)
        rotvec = angle * axis / np.linalg.norm(axis)
        T_tool, T_goal = np.eye(4), np.eye(4)
        T_tool[:3, :3] = R_tool
        T_goal[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix() @ R_tool
        T_goal[:3, 3] = rng.normal(size=3)
        e = pose_error(T_tool, T_goal)
        assert np.allclose(e[:3], T_goal[:3, 3])
        assert np.allclose(Rotation.from_rotvec(e[3:]).as_matrix(), T_goal[:3, :3] @ R_tool.T, atol=1e-12)
        assert np.linalg.norm(e[3:]) <= math.pi + 1e-12


def test_pose_error_rows_match_the_angular_rows_of_j():
    """For a small joint step, the orientation error grows like J's ω rows times that step."""
    robot = robots.load("puma560")
    q = robot.home + 0.1
    dq = 1e-6 * np.random.default_rng(1).normal(size=robot.dof)
    e = pose_error(fk(robot, q), fk(robot, q + dq))
    assert np.allclose(e, jacobian(robot, q) @ dq, atol=1e-11)


@pytest.mark.parametrize("method", ["newton", "dls"])
@pytest.mark.parametrize("step_limit", [None, 0.2])
def test_unreachable_target_gives_a_finite_best_effort(method, step_limit):
    """Planar 2R arm (unit links) asked for a point 10 m away: no exception, a finite q, and
    with bounded steps the arm ends stretched toward the target (error → 10 − 2 m)."""
    robot = robots.load("planar2")
    res = solve(robot, [10.0, 0.0, 0.0], [0.3, 0.4], method=method, max_iterations=60, step_limit=step_limit)
    assert not res.converged and res.reason in ("iteration limit", "stalled")
    assert np.isfinite(res.q).all() and np.isfinite(res.errors).all()
    assert res.errors.min() == pytest.approx(np.linalg.norm(res.residual))
    assert np.linalg.norm(res.residual) <= res.errors[0]
    if step_limit is not None:
        assert np.linalg.norm(res.residual) == pytest.approx(8.0, abs=0.05)


def test_newton_step_at_an_exact_singularity_is_the_pseudo_inverse_step():
    """At q2 = 0 (stretched) J loses the radial direction; the Newton step is still J⁺e (it turns
    joint 1 toward the target), equal to NumPy's pseudo-inverse, and with a step limit it helps."""
    robot = robots.load("planar2")
    q0 = np.array([0.5, 0.0])
    J = jacobian(robot, q0)[:2]
    e = np.array([10.0, 0.0]) - fk(robot, q0)[:2, 3]
    expected = np.linalg.pinv(J, rcond=1e-9) @ e
    assert np.linalg.norm(expected) > 1.0
    assert np.allclose(pinv_solve(J, e), expected, atol=1e-9)
    res = solve(robot, [10.0, 0.0, 0.0], q0, max_iterations=1, step_limit=0.1)
    assert res.errors[1] < res.errors[0]
    assert np.allclose(res.q - q0, 0.1 * expected / np.abs(expected).max(), atol=1e-12)


def test_singular_start_does_not_explode():
    """Puma at its wrist singularity (q5 = 0) with a target that needs the lost rotation."""
    robot = robots.load("puma560")
    q0 = np.zeros(robot.dof)
    T = fk(robot, q0)
    T_goal = T.copy()
    T_goal[:3, :3] = Rotation.from_rotvec([0.3, 0.2, 0.1]).as_matrix() @ T[:3, :3]
    for step_limit in (None, 0.2):
        res = solve(robot, T_goal, q0, max_iterations=60, step_limit=step_limit)
        assert np.isfinite(res.q).all()
        assert res.converged, res.errors[-3:]
        assert np.abs(fk(robot, res.q)[:3, :3] - T_goal[:3, :3]).max() < 1e-9


def test_step_limit_bounds_every_step():
    robot = robots.load("trr")
    q0 = np.array([5, 60 * DEG, -15 * DEG])
    target = trr_tool([15, 30 * DEG, -30 * DEG])
    res = solve(robot, target, q0, step_limit=0.5, max_iterations=1)
    assert np.abs(res.q - q0).max() <= 0.5 + 1e-12 and res.errors[1] < res.errors[0]
    full = solve(robot, target, q0, step_limit=0.5)
    assert full.converged and full.iterations > solve(robot, target, q0).iterations


def test_warm_start_at_the_solution_takes_no_step():
    robot = robots.load("panda")
    T = fk(robot, robot.home)
    res = solve(robot, T, robot.home)
    assert res.converged and res.iterations == 0 and np.array_equal(res.q, robot.home)


def test_rows_choose_the_error_rows():
    """Solving only the position rows of a pose target leaves the orientation free."""
    robot = robots.load("puma560")
    rng = np.random.default_rng(5)
    q_goal = random_q(robot, rng)
    T_goal = fk(robot, q_goal)
    res = solve(robot, T_goal, q_goal + 0.2, rows="linear")
    assert res.converged and res.residual.shape == (3,)
    assert np.abs(fk(robot, res.q)[:3, 3] - T_goal[:3, 3]).max() < 1e-9


@pytest.mark.parametrize(
    ("kwargs", "error", "word"),
    [
        (dict(target=[1.0, 2.0]), ArrayError, "target"),
        (dict(target=[1.0, np.nan, 0.0]), ArrayError, "target"),
        (dict(target=np.ones((4, 4))), ArrayError, "target"),
        (dict(target="here"), ArrayError, "target"),
        (dict(q0=[0.0, 0.0]), ConfigurationError, "q0"),
        (dict(q0=[0.0, np.inf, 0.0, 0, 0, 0]), ConfigurationError, "q0"),
        (dict(method="gauss"), OptionError, "method"),
        (dict(method="dls", damping=-0.1), OptionError, "damping"),
        (dict(tol=0.0), OptionError, "tol"),
        (dict(max_iterations=2.5), OptionError, "max_iterations"),
        (dict(step_limit=-1.0), OptionError, "step_limit"),
        (dict(rows=(7,)), OptionError, "rows"),
        (dict(rows="angular"), OptionError, "rows"),
    ],
)
def test_bad_inputs_raise_clear_errors(kwargs, error, word):
    robot = robots.load("puma560")
    args = dict(target=fk(robot, robot.home)[:3, 3], q0=robot.home)
    args.update(kwargs)
    target, q0 = args.pop("target"), args.pop("q0")
    with pytest.raises(error, match=word) as info:
        solve(robot, target, q0, **args)
    assert isinstance(info.value, JacobianLabError)
