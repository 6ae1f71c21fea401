"""Where the course notes are wrong, checked with numbers (README, "Where the course is wrong").

Each test computes the quantity independently (finite differences, plain linear algebra), shows
that the course's printed statement fails where it does, and that the library follows the
mathematics instead. The notes are in ``../shared/course/``; the quoted lines are in the README.
"""

from __future__ import annotations

import numpy as np
import pytest

import kinematics
import robots
from kinematics.analytic_jacobian import euler_rate_matrix

H = 1e-6


def _rz(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def _ry(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def _zyz(y: np.ndarray) -> np.ndarray:
    return _rz(y[0]) @ _ry(y[1]) @ _rz(y[2])


def _omega(y: np.ndarray, yd: np.ndarray) -> np.ndarray:
    """ω (base axes) of R(y(t)) by central differences: [ω]× = Ṙ Rᵀ."""
    Rdot = (_zyz(y + H * yd) - _zyz(y - H * yd)) / (2 * H)
    W = Rdot @ _zyz(y).T
    return np.array([W[2, 1], W[0, 2], W[1, 0]])


def test_004_printed_M_is_the_inverse_of_the_matrix_its_text_describes():
    """004: "M(y) = [m1 m2 m3], mi(y) – unit vectors of the rotation axes" (ω = M ẏ), but the matrix
    printed for Euler angles (with ctg θ and 1/sin θ) is M⁻¹: it maps ω to the angle rates."""
    rng = np.random.default_rng(4)
    for _ in range(5):
        phi, theta, psi = rng.uniform(0.2, 2.9, 3)
        y, yd = np.array([phi, theta, psi]), rng.uniform(-1, 1, 3)
        cf, sf, ct, st = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta)
        printed = np.array([[-cf * ct / st, -sf * ct / st, 1], [-sf, cf, 0], [cf / st, sf / st, 0]])
        # the text: columns are the unit axes z, Rz(φ) y, Rz(φ) Ry(θ) z, and ω = M ẏ
        M = np.column_stack([[0, 0, 1], _rz(phi) @ [0, 1, 0], _rz(phi) @ _ry(theta) @ [0, 0, 1]])
        assert np.allclose(np.linalg.norm(M, axis=0), 1)
        assert np.allclose(M @ yd, _omega(y, yd), atol=1e-8)
        # the printed matrix is not that: its columns are not unit vectors, and it is M's inverse
        assert not np.allclose(np.linalg.norm(printed, axis=0), 1)
        assert not np.allclose(printed @ yd, _omega(y, yd), atol=1e-3)
        assert np.allclose(printed @ M, np.eye(3))
        assert np.allclose(printed @ _omega(y, yd), yd, atol=1e-8)
        # the library's B(φ) (ω = B φ̇) is the text's M
        assert np.allclose(euler_rate_matrix(y, "zyz"), M)


def _w(robot: kinematics.Robot, q: np.ndarray, rows: list[int]) -> float:
    A = kinematics.jacobian(robot, q)[rows]
    return float(np.sqrt(np.linalg.det(A @ A.T)))


def test_004_gradient_step_with_minus_sign_lowers_manipulability():
    """004: "ω = grad_q(−√det(A Aᵀ))" to optimise manipulability: the null-space step along it
    lowers w; the sign must be + (the library's climb uses +)."""
    robot = robots.load("planar3")
    rows = [0, 1]  # the tool position: 2 rows, 3 joints, one redundant
    rng = np.random.default_rng(2)
    eps = 1e-3
    for _ in range(5):
        q = rng.uniform(-2.5, 2.5, 3)
        grad = np.array(
            [(_w(robot, q + H * e, rows) - _w(robot, q - H * e, rows)) / (2 * H) for e in np.eye(3)]
        )
        A = kinematics.jacobian(robot, q)[rows]
        P = np.eye(3) - np.linalg.pinv(A) @ A  # the course's (I − A⁺A)
        if np.linalg.norm(P @ grad) < 1e-6:
            continue
        w0 = _w(robot, q, rows)
        assert _w(robot, q + eps * P @ (-grad), rows) < w0  # the course's sign: w falls
        assert _w(robot, q + eps * P @ grad, rows) > w0  # the + sign: w rises


def test_002_finite_tool_forces_never_need_infinite_torques():
    """002: "para fuerzas y pares finitos en el extremo pueden corresponderles fuerzas y pares
    infinitos en articulaciones" is backwards: τ = Jᵀ F is finite for every finite F; it is finite
    joint torques that can balance arbitrarily large tool forces (F = J⁻ᵀ τ) near a singularity."""
    robot = robots.load("planar2")
    F = np.array([1.0, 0.0])
    tau = np.array([0.0, 1.0])
    forces = []
    for eps in (1e-1, 1e-2, 1e-3, 1e-4):
        J = kinematics.jacobian(robot, [0.3, eps])[:2]
        # ‖τ‖ ≤ ‖J‖ ‖F‖ ≤ ‖J‖_F ‖F‖ ≤ √((a₁ + a₂)² + a₂²) ‖F‖ = √5 ‖F‖ at every configuration
        assert np.linalg.norm(J.T @ F) <= np.linalg.norm(J, "fro") * np.linalg.norm(F) <= np.sqrt(5) + 1e-12
        forces.append(np.linalg.norm(np.linalg.solve(J.T, tau)))
    assert all(b > 9 * a for a, b in zip(forces, forces[1:], strict=False))  # grows like 1/ε
    # at the singularity, a force along the lost direction needs no torque at all
    J = kinematics.jacobian(robot, [0.3, 0.0])[:2]
    lost = np.linalg.svd(J)[0][:, -1]
    assert np.allclose(J.T @ (1e6 * lost), 0, atol=1e-6)


def _course_Jdot(robot: kinematics.Robot, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """000's per-joint formula: J̇ᵢ = [z_{i−1} × (z_{i−1} × (pₙ − p_{i−1})) q̇ᵢ; 0] (revolute)."""
    W = kinematics.joint_frames(robot, q)
    p_n = kinematics.fk(robot, q)[:3, 3]
    cols = []
    for i in range(robot.dof):
        z, p = W[i][:3, 2], W[i][:3, 3]
        cols.append(np.concatenate([np.cross(z, np.cross(z, p_n - p)) * qd[i], np.zeros(3)]))
    return np.column_stack(cols)


def _Jdot_fd(robot: kinematics.Robot, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    return (kinematics.jacobian(robot, q + H * qd) - kinematics.jacobian(robot, q - H * qd)) / (2 * H)


@pytest.mark.parametrize("name", ["elbow3r", "puma560"])
def test_000_per_joint_Jdot_holds_only_when_one_joint_moves(name):
    robot = robots.load(name)
    q = np.random.default_rng(5).uniform(-1.2, 1.2, robot.dof)
    for i in range(robot.dof):  # one joint moving: column i agrees
        qd = np.zeros(robot.dof)
        qd[i] = 0.7
        assert np.allclose(_course_Jdot(robot, q, qd)[:, i], _Jdot_fd(robot, q, qd)[:, i], atol=1e-6)
    qd = np.full(robot.dof, 0.7)  # all joints moving: it does not
    true = _Jdot_fd(robot, q, qd)
    assert np.abs(_course_Jdot(robot, q, qd) - true).max() > 0.1
    assert np.abs(true[3:, 1:]).max() > 0.1  # the ω part of J̇ is not 0 (the course's formula says it is)
    assert np.allclose(kinematics.jacobian_dot(robot, q, qd), true, atol=1e-6)  # the library's J̇
