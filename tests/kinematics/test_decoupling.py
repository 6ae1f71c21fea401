"""Arm/wrist decoupling (kinematics.singularity.decoupling) against independent derivations: the wrist centre from
the axis lines, J at the centre from finite differences of the centre, det J = det J₁₁ · det J₂₂, and the
lost directions at the named configurations from the geometry of the axes."""

from __future__ import annotations

import numpy as np
import pytest
from fakes import random_q

from kinematics import chain_frames, jacobian
from kinematics.analysis import task_rows
from kinematics.singularity.decoupling import decouple, spherical_wrist, wrist_centre
from kinematics.singularity.lost import characteristic_length, lost_directions
from robots import load

SIX_AXIS_WRISTS = ("puma560", "puma560_mdh", "stanford")


@pytest.mark.parametrize(
    ("name", "wrist"),
    [
        ("puma560", (3, 4, 5)),
        ("puma560_mdh", (3, 4, 5)),
        ("stanford", (3, 4, 5)),
        ("iiwa14", (4, 5, 6)),
        ("ur5", None),  # offset wrist: axes 4, 5, 6 do not meet
        ("panda", None),
        ("planar3", None),
        ("elbow3r", None),
        ("wrist", None),  # three joints only: a wrist with no arm
    ],
)
def test_spherical_wrist_is_found_from_the_model(name, wrist):
    assert spherical_wrist(load(name)) == wrist


def _distance_to_line(x, p, z):
    d = x - p
    return float(np.linalg.norm(d - (d @ z) * z))


@pytest.mark.parametrize("name", [*SIX_AXIS_WRISTS, "iiwa14"])
def test_wrist_centre_and_jacobian_at_it_from_finite_differences(name):
    robot = load(name)
    wrist = spherical_wrist(robot)
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = random_q(robot, rng)
        d = decouple(robot, q)
        W, _ = chain_frames(robot, q)
        for k in wrist:  # on every wrist axis
            assert _distance_to_line(d.centre, W[k, :3, 3], W[k, :3, 2]) < 1e-9
        # v rows of J at the centre: the centre's own velocity, by central differences
        h = 1e-6
        for i in range(robot.dof):
            dq = np.zeros(robot.dof)
            dq[i] = h
            fd = (wrist_centre(robot, q + dq, wrist) - wrist_centre(robot, q - dq, wrist)) / (2 * h)
            np.testing.assert_allclose(d.J_centre[:3, i], fd, atol=1e-7)
        np.testing.assert_allclose(d.J_centre[3:], jacobian(robot, q)[3:])  # ω rows do not move
        np.testing.assert_allclose(d.J_centre[:3, list(wrist)], 0.0, atol=1e-12)  # block-triangular


@pytest.mark.parametrize("name", SIX_AXIS_WRISTS)
def test_det_j_is_the_product_of_the_arm_and_wrist_determinants(name):
    robot = load(name)
    rng = np.random.default_rng(11)
    for _ in range(20):
        q = random_q(robot, rng)
        d = decouple(robot, q)
        det = np.linalg.det(jacobian(robot, q))
        assert d.det_arm * d.det_wrist == pytest.approx(det, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("name", ("puma560", "stanford"))
def test_the_wrist_block_is_singular_exactly_where_theta5_is_zero(name):
    """Orthogonal wrist axes: det J₂₂ = z₄ · (z₅ × z₆) = ±sin θ₅; θ₅ = 0 loses the rotation about z₄ × z₅."""
    robot = load(name)
    rng = np.random.default_rng(3)
    for _ in range(10):
        q = random_q(robot, rng)
        assert abs(decouple(robot, q).det_wrist) == pytest.approx(abs(np.sin(q[4])), abs=1e-12)
        q[4] = 0.0
        d = decouple(robot, q)
        assert d.wrist_singular and not d.arm_singular
        assert abs(np.linalg.det(jacobian(robot, q))) < 1e-12
        W, _ = chain_frames(robot, q)
        normal = np.cross(W[3, :3, 2], W[4, :3, 2])
        (axis,) = d.wrist_lost
        assert abs(axis @ normal / np.linalg.norm(normal)) == pytest.approx(1.0, abs=1e-9)


def test_named_arm_singularities_of_the_puma_lose_the_direction_the_geometry_says():
    robot = load("puma560")
    # Elbow: seen along the parallel axes z₂ = z₃, shoulder, elbow and wrist centre in line (stretched):
    # joints 2 and 3 both move the centre across that line, so the line's direction is lost.
    q = robot.configuration("elbow_singular")
    d = decouple(robot, q)
    W, _ = chain_frames(robot, q)
    z2, p2, p3 = W[1, :3, 2], W[1, :3, 3], W[2, :3, 3]
    assert abs(z2 @ np.cross(d.centre - p2, d.centre - p3)) < 1e-9
    (u,) = d.arm_lost
    for k in (0, 1, 2):  # no arm joint moves the centre along u
        assert abs(u @ np.cross(W[k, :3, 2], d.centre - W[k, :3, 3])) < 1e-9
    r = d.centre - p2
    r -= (r @ z2) * z2
    assert abs(u @ r) / np.linalg.norm(r) > 0.9  # mostly along the shoulder-to-wrist line
    assert not d.wrist_singular and d.det_arm == pytest.approx(0.0, abs=1e-12)
    # Shoulder: the centre in the plane of the waist axis: only the waist would move it sideways, and it
    # does not (the centre is on its axis up to the shoulder offset that joints 2, 3 also give).
    q = robot.configuration("shoulder_singular")
    d = decouple(robot, q)
    W, _ = chain_frames(robot, q)
    (u,) = d.arm_lost
    arm_columns = d.J11
    assert np.linalg.norm(u @ arm_columns) < 1e-9  # no arm joint moves the centre along u
    assert abs(u @ W[1, :3, 2]) == pytest.approx(1.0, abs=1e-9)  # along the shoulder axis z₂
    # Wrist: nothing lost by the arm.
    d = decouple(robot, robot.configuration("wrist_singular"))
    assert d.wrist_singular and not d.arm_singular


def test_iiwa_candle_loses_two_translations_of_the_wrist_centre_and_one_rotation():
    robot = load("iiwa14")
    d = decouple(robot, robot.configuration("candle"))
    assert len(d.arm_lost) == 2 and len(d.wrist_lost) == 1
    # The arm cannot move the centre up (stretched) nor sideways (axes 2 and 4 both about y at zero).
    span = d.arm_lost.T @ d.arm_lost
    np.testing.assert_allclose(span, np.diag([0.0, 1.0, 1.0]), atol=1e-9)
    assert abs(d.wrist_lost[0] @ [1.0, 0, 0]) == pytest.approx(1.0, abs=1e-9)  # axes 5, 7 in line
    # The whole J loses three dimensions, as many as the blocks.
    assert np.linalg.matrix_rank(jacobian(robot, robot.configuration("candle")), tol=1e-9) == 3


def test_lost_directions_of_a_multi_rank_loss_span_what_the_jacobian_cannot_do():
    robot = load("iiwa14")
    q = robot.configuration("candle")
    J, rows, L = jacobian(robot, q), task_rows(robot), characteristic_length(robot)
    lost = lost_directions(J, rows, L)
    assert len(lost) == 3
    W = np.diag([1.0] * 3 + [L] * 3)
    for x in lost:
        weighted = np.concatenate(
            [x.translation * np.sqrt(x.translation_share), x.rotation * np.sqrt(x.rotation_share)]
        )
        assert np.linalg.norm(weighted) == pytest.approx(1.0)
        assert np.linalg.norm(weighted @ (W @ J)) < 1e-9  # orthogonal to everything J can do
    # Separated: the vertical translation, a sideways one and a pure rotation.
    assert sorted(round(x.translation_share, 9) for x in lost) == [0.0, 1.0, 1.0]
    assert any(abs(x.translation[2]) == pytest.approx(1.0) for x in lost)


def test_robots_without_a_spherical_wrist_are_not_decoupled():
    assert decouple(load("ur5"), load("ur5").configuration("wrist_singular")) is None
