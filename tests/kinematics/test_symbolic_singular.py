"""det J factored, singular sets, and the analytic Jacobian's symbolic form."""

from __future__ import annotations

import time

import numpy as np
import pytest
import sympy as sp
from fakes import random_configurations

import kinematics
import robots
from kinematics import symbolic
from kinematics.symbolic import SymbolicError


def q_symbols(n):
    return sp.symbols(f"q1:{n + 1}", real=True)


def kinds(det):
    return {s.kind: s for s in det.singular_sets}


def test_planar_2r_det_is_a1_a2_s2():
    q1, q2 = q_symbols(2)
    a1, a2 = sp.symbols("a1 a2", real=True)
    d = symbolic.determinant(robots.load("planar2"), symbolic_params=True)
    assert d.rows == (0, 1) and not d.gram
    assert sp.expand(d.expr - a1 * a2 * sp.sin(q2)) == 0
    (s,) = d.singular_sets
    assert s.factor == sp.sin(q2) and s.solutions == (0, sp.pi) and s.kind == "elbow"


def test_elbow_3r_det():
    q1, q2, q3 = q_symbols(3)
    L1, L2, L3 = sp.symbols("L1 L2 L3", real=True)
    d = symbolic.determinant(robots.load("elbow3r"), symbolic_params=True)
    assert d.rows == (0, 1, 2)
    expected = -L2 * L3 * sp.sin(q3) * (L1 + L2 * sp.cos(q2) + L3 * sp.cos(q2 + q3))
    assert sp.expand(d.expr - expected) == 0
    k = kinds(d)
    assert k["elbow"].solutions == (0, sp.pi)
    assert sp.expand(k["shoulder"].factor - (L1 + L2 * sp.cos(q2) + L3 * sp.cos(q2 + q3))) == 0


def test_trr_singular_when_q3_is_zero():
    d = symbolic.determinant(robots.load("trr"), symbolic_params=True)
    l2, l3 = sp.symbols("l2 l3", real=True)
    assert sp.expand(d.expr + l2 * l3 * sp.sin(q_symbols(3)[2])) == 0


def test_spherical_wrist():
    d = symbolic.determinant(robots.load("wrist"))
    assert d.rows == (3, 4, 5)  # the robot's task: orientation
    (s,) = d.singular_sets
    assert s.kind == "wrist" and s.factor == sp.sin(q_symbols(3)[1]) and s.solutions == (0, sp.pi)


@pytest.mark.slow
def test_puma_560_wrist_elbow_shoulder():
    q = q_symbols(6)
    a2, a3, d4 = sp.symbols("a2 a3 d4", real=True)
    d = symbolic.determinant(robots.load("puma560"), symbolic_params=True)
    assert d.rows == (0, 1, 2, 3, 4, 5) and not d.gram
    k = kinds(d)
    assert set(k) == {"wrist", "elbow", "shoulder"}
    assert k["wrist"].factor == sp.sin(q[4]) and k["wrist"].solutions == (0, sp.pi)
    assert sp.expand(k["elbow"].factor - (d4 * sp.cos(q[2]) + a3 * sp.sin(q[2]))) == 0
    shoulder = a2 * sp.cos(q[1]) + a3 * sp.cos(q[1] + q[2]) - d4 * sp.sin(q[1] + q[2])
    assert sp.expand(k["shoulder"].factor - shoulder) == 0 or sp.expand(k["shoulder"].factor + shoulder) == 0
    # with numbers: same factors, values substituted
    numeric = symbolic.determinant(robots.load("puma560"))
    assert {s.kind for s in numeric.singular_sets} == {"wrist", "elbow", "shoulder"}
    assert not numeric.expr.free_symbols - set(q)


def test_stanford_singular_sets():
    d = symbolic.determinant(robots.load("stanford"))
    k = kinds(d)
    q = q_symbols(6)
    assert k["wrist"].factor == sp.sin(q[4]) and k["shoulder"].factor == sp.sin(q[1])


@pytest.mark.slow
@pytest.mark.parametrize("name", ["planar3", "trr", "elbow3r", "scara", "stanford", "puma560", "ur5"])
def test_det_matches_numeric(name):
    robot = robots.load(name)
    d = symbolic.determinant(robot)
    f = sp.lambdify([list(q_symbols(robot.dof))], d.expr)
    for q in random_configurations(robot, 4, seed=2):
        J = kinematics.jacobian(robot, q)[list(d.rows)]
        assert float(f(q)) == pytest.approx(np.linalg.det(J), abs=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["panda", "iiwa14"])
def test_redundant_arm_gram_determinant(name):
    robot = robots.load(name)
    d = symbolic.determinant(robot)
    assert d.gram and len(d.minors) == 7 and d.expr is not None
    f = sp.lambdify([list(q_symbols(robot.dof))], d.expr)
    for q in random_configurations(robot, 2, seed=2):
        J = kinematics.jacobian(robot, q)
        assert float(f(q)) == pytest.approx(np.linalg.det(J @ J.T), rel=1e-8, abs=1e-12)
    if name == "iiwa14":  # every 6×6 minor vanishes with sin q4: the stretched elbow
        assert [s.factor for s in d.singular_sets] == [sp.sin(q_symbols(7)[3])]


@pytest.mark.slow
def test_rows_argument_and_errors():
    robot = robots.load("puma560")
    d = symbolic.determinant(robot, "linear")  # 3×6: det(J_v J_vᵀ); every minor has the arm's factors
    assert d.rows == (0, 1, 2) and d.gram and len(d.minors) == 20
    assert {s.kind for s in d.singular_sets} == {"elbow", "shoulder"}
    with pytest.raises(SymbolicError, match="rows"):
        symbolic.determinant(robot, "sideways")
    with pytest.raises(SymbolicError, match="rows"):
        symbolic.determinant(robot, (0, 0, 7))
    d = symbolic.determinant(robots.load("wrist"), "linear")  # a pure wrist cannot place its flange
    assert d.identically_zero and "identically zero" in d.notes[-1]


# ------------------------------------------------------------- analytic Jacobian
@pytest.mark.slow
@pytest.mark.parametrize("convention, singular", [("zyx", (-sp.pi / 2, sp.pi / 2)), ("zyz", (0, sp.pi))])
def test_analytic_jacobian(convention, singular):
    robot = robots.load("puma560")
    A = symbolic.analytic_jacobian(robot, convention)
    assert A.singular_values == singular
    assert A.condition == (sp.cos(A.angles[1]) if convention == "zyx" else sp.sin(A.angles[1]))
    f = sp.lambdify([list(q_symbols(6)), list(A.angles)], A.JA)
    for q in random_configurations(robot, 3, seed=2):
        phi = kinematics.euler_angles(kinematics.fk(robot, q), convention)
        expected = kinematics.analytic_jacobian(robot, q, convention)
        np.testing.assert_allclose(np.array(f(q, phi), dtype=float), expected, atol=1e-9)


def test_analytic_jacobian_rejects_unknown_convention():
    with pytest.raises(SymbolicError, match="zyx"):
        symbolic.analytic_jacobian(robots.load("planar2"), "xyz")


@pytest.mark.slow
def test_large_determinant_is_declined_quickly():
    rows = [
        dict(joint="revolute", a=0.1 * (i + 1), alpha=0.3 * (i + 1), d=0.05 * i, theta=0.2 * i)
        for i in range(6)
    ]
    robot = kinematics.Robot.from_dh(rows, name="odd6")
    start = time.thread_time()  # the work done, which another job on the machine cannot inflate
    d = symbolic.determinant(robot, use_cache=False)
    assert time.thread_time() - start < 30
    assert d.expr is None and d.singular_sets == () and "not computed" in d.notes[0]
