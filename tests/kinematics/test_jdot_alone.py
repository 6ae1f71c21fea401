"""000's per-joint J̇ᵢ (kinematics.jacobian_dot_alone) against the course's formula written out joint by
joint, against finite differences of J with one joint moving, and its limit with several moving."""

from __future__ import annotations

import numpy as np
import pytest
from test_export_latex import display_formulas, katex  # noqa: F401  (katex is a fixture)

import kinematics
import robots

H = 1e-6
NAMES = ["planar2", "elbow3r", "trr", "scara", "puma560", "stanford", "ur5"]


def _course(robot: kinematics.Robot, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """000, §7, written out: revolute J̇ᵢ = [z_{i−1} × (z_{i−1} × (pₙ − p_{i−1})) q̇ᵢ; 0], prismatic 0."""
    W = kinematics.joint_frames(robot, q)
    p_n = kinematics.fk(robot, q)[:3, 3]
    cols = []
    for i, kind in enumerate(robot.joint_types):
        z, p = W[i][:3, 2], W[i][:3, 3]
        top = np.cross(z, np.cross(z, p_n - p)) * qd[i] if kind == "revolute" else np.zeros(3)
        cols.append(np.concatenate([top, np.zeros(3)]))
    return np.column_stack(cols)


def _fd(robot: kinematics.Robot, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    return (kinematics.jacobian(robot, q + H * qd) - kinematics.jacobian(robot, q - H * qd)) / (2 * H)


@pytest.mark.parametrize("name", NAMES)
def test_per_joint_jdot_is_the_course_formula_and_agrees_when_one_joint_moves(name):
    robot = robots.load(name)
    rng = np.random.default_rng(11)
    q = rng.uniform(-1.2, 1.2, robot.dof)
    qd_all = rng.uniform(0.3, 0.9, robot.dof)
    assert np.allclose(kinematics.jacobian_dot_alone(robot, q, qd_all), _course(robot, q, qd_all), atol=1e-12)
    for i in range(robot.dof):
        qd = np.zeros(robot.dof)
        qd[i] = qd_all[i]
        alone = kinematics.jacobian_dot_alone(robot, q, qd)
        assert np.allclose(alone[:, i], _fd(robot, q, qd)[:, i], atol=1e-5)  # column i: the true one
        # Σⱼ J̇ⱼ q̇ⱼ = J̇ᵢ q̇ᵢ = J̇ q̇: the course's acceleration term is right for one joint alone
        assert np.allclose(alone @ qd, _fd(robot, q, qd) @ qd, atol=1e-5)


@pytest.mark.parametrize("name", ["elbow3r", "puma560", "trr"])
def test_per_joint_jdot_misses_the_coupling_when_several_joints_move(name):
    robot = robots.load(name)
    q = np.random.default_rng(3).uniform(-1.2, 1.2, robot.dof)
    qd = np.full(robot.dof, 0.7)
    true = _fd(robot, q, qd)
    alone = kinematics.jacobian_dot_alone(robot, q, qd)
    assert np.linalg.norm(true @ qd - alone @ qd) > 0.05  # the accelerations differ
    assert np.allclose(kinematics.jacobian_dot(robot, q, qd), true, atol=1e-5)


def test_prismatic_columns_are_zero():
    robot = robots.load("trr")  # joint 1 slides
    J = kinematics.jacobian_dot_alone(robot, np.array([1.0, 0.4, -0.3]), np.array([2.0, 0.5, 0.5]))
    assert np.all(J[:, 0] == 0) and np.all(J[3:] == 0)


def _column(html: str, after: str) -> list[float]:
    """The first column vector printed after the caption ``after`` (MathML numbers, real minus signs)."""
    import re

    part = html[html.index(after) :]
    block = part[: part.index("</mtable>")]
    return [float(x.replace("−", "-").replace(",", ".")) for x in re.findall(r"<mn>([^<]+)</mn>", block)]


def test_the_handout_prints_jdot_qd_and_the_per_joint_sum_with_the_rates():
    from kinematics.symbolic.handout import handout

    robot = robots.load("elbow3r")
    q = robot.home
    for rates_deg, agree in (([0.0, 40.0, 0.0], True), ([30.0, 40.0, -35.0], False)):
        qd = np.radians(rates_deg)
        html = handout(robot, "html", "whitney", rates=qd)  # SI: the CLI takes °/s
        jdot = _column(html, "the tool accelerates")
        alone = _column(html, "per-joint J̇ᵢ holds")
        np.testing.assert_allclose(jdot, (_fd(robot, q, qd) @ qd)[:3], atol=1e-3)  # 3 significant digits
        np.testing.assert_allclose(alone, (_course(robot, q, qd) @ qd)[:3], atol=1e-3)
        assert np.allclose(jdot, alone, atol=1e-3) == agree
    tex = handout(robot, "tex", "whitney", rates=np.radians([30.0, 40.0, -35.0]))
    assert "\\sum_i \\dot{J}_i \\dot{q}_i" in tex and "\\dot{J} \\dot{q}" in tex


def test_the_new_handout_formulas_typeset_in_katex(katex):  # noqa: F811 (a fixture)
    from kinematics.symbolic.handout import handout

    formulas = display_formulas(handout(robots.load("elbow3r"), "tex", "whitney", rates=[0.5, 0.7, -0.6]))
    formulas += display_formulas(handout(robots.load("trr"), "tex", "whitney"))  # ∂g/∂x: item 4
    new = [f for f in formulas if "\\sum_i" in f or "\\dot{J} \\dot{q}" in f or "\\partial g" in f]
    assert len(new) == 3
    assert katex(new) == [None] * 3


@pytest.mark.slow
@pytest.mark.parametrize("name", ["planar2", "elbow3r", "trr"])
def test_the_symbolic_per_joint_jdot_is_the_one_joint_derivative_and_the_numeric_one(name):
    import sympy as sp

    from kinematics.symbolic import jacobian as symbolic_jacobian
    from kinematics.symbolic import joint_symbols
    from kinematics.symbolic.jdot import jacobian_dot_alone_symbolic, rate_symbols_of

    robot = robots.load(name)
    q, qd = joint_symbols(robot), rate_symbols_of(robot)
    course = jacobian_dot_alone_symbolic(robot)
    J = symbolic_jacobian(robot, "base")
    for i in range(robot.dof):  # 000's J̇ᵢ is ∂Jᵢ/∂qᵢ q̇ᵢ: column i's rate with joint i alone moving
        alone = J[:, i].diff(q[i]) * qd[i]
        assert sp.simplify(course[:, i] - alone) == sp.zeros(6, 1), i
    f = sp.lambdify([q, qd], course, "numpy")
    rng = np.random.default_rng(1)
    for _ in range(5):
        qv, qdv = rng.uniform(-1.5, 1.5, robot.dof), rng.uniform(-1, 1, robot.dof)
        np.testing.assert_allclose(
            np.asarray(f(qv, qdv), float), kinematics.jacobian_dot_alone(robot, qv, qdv), atol=1e-12
        )
