"""Issue 29, items 3, 5, 7, 8: the null motion at a singularity, IK along a path, joint-limit
critical points, the several IK solutions of a pose; each checked against an independent computation."""

from __future__ import annotations

import math

import numpy as np
import pytest

import robots
from kinematics import fk, jacobian
from kinematics.motion.branches import branches, gap
from kinematics.motion.path import circle, follow, line
from kinematics.singularity.limits import at_limit, limit_contacts
from kinematics.singularity.null_motion import null_motion, null_motion_path, signed


def puma_wrist_singular():
    robot = robots.load("puma560")
    q = robot.home.copy()
    q[4] = 0.0  # q5 = 0: axes 4 and 6 collinear
    return robot, q


def test_puma_wrist_null_motion_is_q4_equal_minus_q6_and_holds_the_tool_exactly():
    robot, q = puma_wrist_singular()
    m = null_motion(robot, q)
    assert m.dimension == 1 and m.joints == (3, 5)
    assert m.direction[3] == pytest.approx(1 / math.sqrt(2), abs=1e-12)
    assert m.direction[5] == pytest.approx(-1 / math.sqrt(2), abs=1e-12)
    assert np.abs(jacobian(robot, q) @ m.direction).max() < 1e-12
    T0 = fk(robot, q)
    for qs in null_motion_path(q, m.direction, 0.8, 12):  # q4 and q6 sweep ±0.57 rad
        assert np.abs(fk(robot, qs) - T0).max() < 1e-12
    assert np.ptp(null_motion_path(q, m.direction, 0.8, 12)[:, 3]) > 1.0


def test_planar_2r_stretched_null_motion_matches_the_hand_derivation():
    # J at q = (q1, 0) with l1 = l2 = 1: columns 2(−s1, c1) and (−s1, c1): Ker J = span (1, −2)
    robot = robots.load("planar2")
    m = null_motion(robot, [0.4, 0.0])
    assert np.allclose(m.direction, np.array([-1.0, 2.0]) / math.sqrt(5), atol=1e-12)  # the 2 is the largest
    assert m.sigma < 1e-12 and m.dimension == 1
    # first-order only: the tool drifts as s² (finite differences of the tool point)
    p0 = fk(robot, [0.4, 0.0])[:3, 3]
    drift = [np.linalg.norm(fk(robot, [0.4, 0.0] + s * m.direction)[:3, 3] - p0) for s in (1e-2, 2e-2)]
    assert drift[1] / drift[0] == pytest.approx(4.0, rel=1e-2)


def test_regular_configuration_has_no_null_motion_and_the_sign_convention():
    robot = robots.load("planar2")
    m = null_motion(robot, [0.4, 1.0])
    assert m.dimension == 0 and m.sigma == pytest.approx(
        np.linalg.svd(jacobian(robot, [0.4, 1.0])[:2])[1][-1]
    )
    assert signed([0.5, -0.5]).tolist() == [0.5, -0.5] and signed([-0.5, 0.5]).tolist() == [0.5, -0.5]
    assert signed([0.1, -0.9]).tolist() == [-0.1, 0.9]


def test_path_line_and_circle_are_followed_with_a_small_error_and_rates_equal_to_j_inverse_ydot():
    robot = robots.load("planar2")
    for path in (line((1.2, -0.5, 0.0), (1.2, 0.5, 0.0)), circle((1.0, 0.5, 0.0), 0.4, duration=2.0)):
        f = follow(robot, path, [0.3, 1.2], steps=200)
        assert f.newton.converged and f.error.max() < 1e-7
        for k in (0, 77, 200):  # q̇ = J⁻¹ ẏ, checked by solving J q̇ = ẏ
            J = jacobian(robot, f.q[k])[:2]
            assert np.allclose(J @ f.qd[k], path.velocity(float(f.t[k]))[:2], atol=1e-9)
        # finite differences of q(t) agree with the rates
        dt = float(f.t[1] - f.t[0])
        assert np.allclose((f.q[101] - f.q[99]) / (2 * dt), f.qd[100], rtol=1e-3, atol=1e-3)


def test_path_near_the_stretched_singularity_fails_rates_and_error_grow():
    robot = robots.load("planar2")
    far = follow(robot, line((1.5, -0.3, 0.0), (1.5, 0.3, 0.0)), [-0.5, 0.8], steps=200)
    near = follow(robot, line((1.995, -0.3, 0.0), (1.995, 0.3, 0.0)), [-0.3, 0.3], steps=200)
    assert np.abs(near.qd).max() > 10 * np.abs(far.qd).max()
    assert near.error.max() > 1e3 * far.error.max() and near.error.max() > 1e-3


def test_redundant_path_follows_with_the_null_term_and_omega_does_not_disturb_the_tool():
    robot = robots.load("puma560")  # 6 joints, 3 position rows: J⁺ẏ + (I − J⁺J)ω
    c = fk(robot, robot.home)[:3, 3]
    path = circle(c, 0.1, (1.0, 0.0, 0.0), duration=1.0)
    plain = follow(robot, path, robot.home, steps=100)
    moved = follow(robot, path, robot.home, steps=100, omega=lambda t, q: np.ones(6))
    assert plain.error.max() < 1e-7 and moved.error.max() < 1e-7
    assert np.abs(moved.q[-1] - plain.q[-1]).max() > 0.1  # ω moved the joints, not the tool


def test_joint_limit_contact_names_the_joint_the_sense_and_the_signed_column():
    robot = robots.load("planar2")
    lo, hi = robot.qlim
    q = np.array([lo[0], 0.7])
    (c,) = limit_contacts(robot, q)
    assert (c.joint, c.side, c.sense) == (0, "lower", 1)
    assert np.allclose(c.column, jacobian(robot, q)[:, 0])
    (c,) = limit_contacts(robot, [0.2, hi[1]])
    assert (c.joint, c.side, c.sense) == (1, "upper", -1)
    assert np.allclose(c.column, -jacobian(robot, [0.2, hi[1]])[:, 1])
    assert limit_contacts(robot, [0.2, 0.3]) == ()
    assert at_limit(robot, [[0.2, 0.3], [lo[0], 0.3], [0.1, hi[1]]]).tolist() == [False, True, True]


def test_planar_2r_branches_are_elbow_up_and_down_and_merge_at_the_stretch():
    robot = robots.load("planar2")
    gaps = []
    for q2 in (1.0, 0.3, 0.05):
        p = fk(robot, [0.2, q2])[:3, 3]
        found = branches(robot, p, [0.2, q2])
        assert len(found) == 2
        # closed form with l1 = l2 = 1: the other branch is (q1 + q2, −q2)
        assert np.allclose(found[0].q, [0.2, q2], atol=1e-9)
        assert np.allclose(found[1].q, [0.2 + q2, -q2], atol=1e-9)
        gaps.append(gap(robot, found))
        assert gaps[-1] == pytest.approx(math.sqrt(5) * q2, rel=1e-9)
    assert gaps[0] > gaps[1] > gaps[2]


def test_puma_branches_reach_the_pose_and_include_the_start():
    robot = robots.load("puma560")
    q = robot.home.copy()
    q[2], q[4] = -2.5, 0.6
    T = fk(robot, q)
    found = branches(robot, T, q)
    assert len(found) >= 4 and np.allclose(found[0].q, q, atol=1e-9)
    lo, hi = robot.qlim
    for b in found:
        assert np.abs(fk(robot, b.q) - T).max() < 1e-9
        assert np.all(b.q >= lo - 1e-9) and np.all(b.q <= hi + 1e-9)
