"""The course's derivations as numbers (kinematics.steps) against J itself, over random configurations."""

from __future__ import annotations

import numpy as np
import pytest

import robots
from kinematics import Robot, jacobian, joint_frames, link_frames
from kinematics.errors import ArrayError
from kinematics.steps import differentiation, force_propagation, propagation, whitney

NAMES = robots.names()


def _samples(robot: Robot, count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lo = np.array([j.qlim[0] if j.qlim else -np.pi for j in robot.joints])
    hi = np.array([j.qlim[1] if j.qlim else np.pi for j in robot.joints])
    return rng.uniform(lo, hi, size=(count, robot.dof))


def _assembled(robot: Robot, cols: np.ndarray, joints: list[int]) -> np.ndarray:
    J = np.zeros((6, robot.dof))
    for j, c in zip(joints, cols, strict=True):
        J[:, j] += c
    return J


@pytest.mark.parametrize("name", NAMES)
def test_whitney_columns_assemble_J(name):
    robot = robots.load(name)
    for q in _samples(robot, 5, 1):
        cols = whitney(robot, q)
        J = _assembled(robot, np.array([c.column for c in cols]), [c.joint for c in cols])
        np.testing.assert_allclose(J, jacobian(robot, q), atol=1e-12)
        W = joint_frames(robot, q)
        for c in cols:
            assert abs(np.linalg.norm(c.z) - 1) < 1e-12
            # z is the axis and p lies on it: the joint frame's z axis and origin.
            np.testing.assert_allclose(c.z, W[c.axis, :3, 2], atol=1e-15)
            np.testing.assert_allclose(c.p + c.r, link_frames(robot, q)[-1, :3, 3], atol=1e-12)


def test_whitney_on_the_planar_arm_by_hand():
    # Unit 2R arm at q = (0, 90°): z0 = z1 = ẑ, p0 = 0, p1 = (1, 0, 0), tool (1, 1, 0).
    r = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)] * 2)
    c0, c1 = whitney(r, [0.0, np.pi / 2])
    np.testing.assert_allclose(c0.r, [1, 1, 0], atol=1e-15)
    np.testing.assert_allclose(c0.linear, [-1, 1, 0], atol=1e-15)
    np.testing.assert_allclose(c1.p, [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(c1.linear, [-1, 0, 0], atol=1e-15)


@pytest.mark.parametrize("name", NAMES)
def test_differentiation_agrees_with_J(name):
    robot = robots.load(name)
    for q in _samples(robot, 3, 2):
        cols = differentiation(robot, q)
        J = np.array([c.column for c in cols]).T
        scale = max(1.0, float(np.abs(jacobian(robot, q)).max()))
        np.testing.assert_allclose(J, jacobian(robot, q), atol=2e-7 * scale)
        for c in cols:  # (∂R/∂q) Rᵀ is skew-symmetric
            np.testing.assert_allclose(c.S, -c.S.T, atol=1e-7)


@pytest.mark.parametrize("name", NAMES)
def test_propagated_tool_velocity_is_J_qdot(name):
    robot = robots.load(name)
    rng = np.random.default_rng(3)
    for q in _samples(robot, 4, 3):
        qd = rng.normal(size=robot.dof)
        links = propagation(robot, q, qd)
        np.testing.assert_allclose(
            np.concatenate([links[-1].v, links[-1].omega]), jacobian(robot, q) @ qd, atol=1e-11
        )
        assert len(links) == len(robot.axes) + 1


def test_propagated_link_velocities_by_finite_differences():
    # Each link frame's origin velocity and angular velocity, against moving q by q̇·dt.
    robot = robots.load("puma560")
    rng = np.random.default_rng(4)
    q, qd, dt = _samples(robot, 1, 4)[0], rng.normal(size=6), 1e-6
    links = propagation(robot, q, qd)
    Lp, Lm = link_frames(robot, q + qd * dt), link_frames(robot, q - qd * dt)
    for link in links:
        k = link.frame
        v = (Lp[k, :3, 3] - Lm[k, :3, 3]) / (2 * dt)
        S = (Lp[k, :3, :3] - Lm[k, :3, :3]) / (2 * dt) @ link.R.T
        w = 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])
        np.testing.assert_allclose(link.v, v, atol=1e-7)
        np.testing.assert_allclose(link.omega, w, atol=1e-7)
        np.testing.assert_allclose(link.R @ link.omega_own, link.omega, atol=1e-14)


@pytest.mark.parametrize("name", NAMES)
def test_force_propagation_is_J_transpose(name):
    robot = robots.load(name)
    rng = np.random.default_rng(5)
    for q in _samples(robot, 4, 5):
        F = rng.normal(size=6)
        tau = np.zeros(robot.dof)
        loads = force_propagation(robot, q, F)
        assert [x.axis for x in loads] == list(reversed(range(len(robot.axes))))  # inward
        for x in loads:
            tau[x.joint] += x.multiplier * x.load
        np.testing.assert_allclose(tau, jacobian(robot, q).T @ F, atol=1e-11)


def test_force_on_the_planar_arm_by_hand():
    # Unit 2R arm stretched along x, 1 N along +y at the tool: τ = (2, 1) N·m.
    r = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)] * 2)
    loads = force_propagation(r, [0.0, 0.0], [0, 1, 0, 0, 0, 0])
    assert [round(x.load, 12) for x in loads] == [1.0, 2.0]


def test_bad_wrench_is_named():
    robot = robots.load("planar2")
    with pytest.raises(ArrayError, match="wrench"):
        force_propagation(robot, [0, 0], [0, np.nan, 0, 0, 0, 0])
    with pytest.raises(ArrayError, match="wrench"):
        force_propagation(robot, [0, 0], [1, 2])
