"""Symbolic kinematics: exactness, the course's results, agreement with the numeric Jacobian, derivations."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from fakes import random_configurations

import kinematics
import robots
from kinematics import symbolic
from kinematics.symbolic import SymbolicError
from kinematics.symbolic.exact import exact_angle, exact_number

LIBRARY = [n for n in robots.names() if robots.load(n).dof <= 7]
SMALL = ["planar2", "planar3", "trr", "elbow3r", "wrist", "scara"]


def q_symbols(n):
    return sp.symbols(f"q1:{n + 1}", real=True)


# ------------------------------------------------------------------ exactness
def test_exact_numbers_and_angles():
    assert exact_angle(np.pi / 2) == sp.pi / 2
    assert exact_angle(np.radians(-90.0)) == -sp.pi / 2
    assert exact_angle(np.pi) == sp.pi
    assert exact_number(0.4318) == sp.Rational(2159, 5000)
    assert exact_number(np.cos(np.pi / 4)) == sp.sqrt(2) / 2
    assert exact_number(6.123e-17) == 0
    assert exact_angle(0.3) == sp.Rational(3, 10)


def test_symbols_are_real_q1_to_qn():
    J = symbolic.jacobian(robots.load("puma560"))
    assert J.shape == (6, 6)
    assert {s.name for s in J.free_symbols} <= {f"q{i}" for i in range(1, 7)}
    assert all(s.is_real for s in J.free_symbols)
    assert symbolic.joint_symbols(robots.load("puma560")) == q_symbols(6)


def test_fk_keeps_right_angles_exact():
    T = symbolic.fk(robots.load("puma560"))
    assert not T.atoms(sp.Float)
    assert T[3, :] == sp.Matrix([[0, 0, 0, 1]])
    assert sp.Rational(2159, 5000) in T.atoms(sp.Rational) or sp.Rational(-2159, 5000) in T.atoms(sp.Rational)


# ----------------------------------------------------------- course's results
def test_planar_2r():
    q1, q2 = q_symbols(2)
    a1, a2 = sp.symbols("a1 a2", real=True)
    J = symbolic.jacobian(robots.load("planar2"), symbolic_params=True)
    expected = sp.Matrix(
        [
            [-a1 * sp.sin(q1) - a2 * sp.sin(q1 + q2), -a2 * sp.sin(q1 + q2)],
            [a1 * sp.cos(q1) + a2 * sp.cos(q1 + q2), a2 * sp.cos(q1 + q2)],
        ]
    )
    assert J[:2, :] == expected
    assert J[5, :] == sp.Matrix([[1, 1]])
    assert sp.expand(J[:2, :].det() - a1 * a2 * sp.sin(q2)) != 0  # unsimplified product ...
    assert symbolic.is_zero(J[:2, :].det() - a1 * a2 * sp.sin(q2), (q1, q2))  # ... equals a1 a2 s2


def test_trr_course_rows():
    q1, q2, q3 = q_symbols(3)
    l2, l3 = sp.symbols("l2 l3", real=True)
    J = symbolic.jacobian(robots.load("trr"), symbolic_params=True)
    c2, s2, c23, s23 = sp.cos(q2), sp.sin(q2), sp.cos(q2 + q3), sp.sin(q2 + q3)
    expected = sp.Matrix([[0, l2 * c2 + l3 * c23, l3 * c23], [0, -l2 * s2 - l3 * s23, -l3 * s23], [1, 0, 0]])
    assert sp.expand(J[:3, :] - expected) == sp.zeros(3, 3)
    l1 = sp.Symbol("l1", real=True)
    p = symbolic.fk(robots.load("trr"), symbolic_params=True)[:3, 3]
    assert sp.expand(p - sp.Matrix([l2 * s2 + l3 * s23, l1 + l2 * c2 + l3 * c23, q1])) == sp.zeros(3, 1)


def test_elbow_3r_position_and_jacobian():
    q1, q2, q3 = q_symbols(3)
    L1, L2, L3 = sp.symbols("L1 L2 L3", real=True)
    robot = robots.load("elbow3r")
    r = L1 + L2 * sp.cos(q2) + L3 * sp.cos(q2 + q3)
    p_expected = sp.Matrix([sp.cos(q1) * r, sp.sin(q1) * r, L2 * sp.sin(q2) + L3 * sp.sin(q2 + q3)])
    p = symbolic.fk(robot, symbolic_params=True)[:3, 3]
    assert sp.expand(p - p_expected) == sp.zeros(3, 1)
    J = symbolic.jacobian(robot, symbolic_params=True)
    assert sp.expand(J[:3, :] - p_expected.jacobian([q1, q2, q3])) == sp.zeros(3, 3)
    # what a person writes: sums of angles collapsed, common factors out
    assert J[2, 1] == L2 * sp.cos(q2) + L3 * sp.cos(q2 + q3)
    assert J[1, 0] == sp.cos(q1) * r


def test_simplified_form_is_readable():
    J = symbolic.jacobian(robots.load("puma560"))
    q = q_symbols(6)
    trig_args = {f.args[0] for f in J.atoms(sp.sin, sp.cos)}
    assert q[1] + q[2] in trig_args  # s23 / c23 collapsed
    assert all(not a.has(sp.pi) for a in trig_args)  # no √2 sin(q + π/4) phases
    assert max(len(sp.Add.make_args(sp.expand(e))) for e in J) <= 12


# ----------------------------------------------------------- numeric agreement
@pytest.mark.slow
@pytest.mark.parametrize("name", LIBRARY)
def test_symbolic_equals_numeric(name):
    robot = robots.load(name)
    for frame in ("base", "tool"):
        d = symbolic.derive(robot, frame)
        assert d.complete and d.notes == ()
        J = symbolic.numeric_function(d.J, symbolic.build_model(robot))
        T = symbolic.numeric_function(d.T, symbolic.build_model(robot))
        for q in random_configurations(robot, 5, seed=1):
            np.testing.assert_allclose(J(q), kinematics.jacobian(robot, q, frame), atol=1e-9, rtol=0)
            np.testing.assert_allclose(T(q), kinematics.fk(robot, q), atol=1e-9, rtol=0)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "elbow3r", "stanford"])
def test_symbolic_params_numeric(name):
    robot = robots.load(name)
    model = symbolic.build_model(robot, True)
    assert model.params and all(isinstance(v, float) for v in model.params.values())
    f = symbolic.numeric_function(symbolic.jacobian(robot, symbolic_params=True), model)
    for q in random_configurations(robot, 3, seed=1):
        np.testing.assert_allclose(f(q), kinematics.jacobian(robot, q), atol=1e-9, rtol=0)


@pytest.mark.slow
def test_urdf_chain(tmp_path):
    robot = robots.load("stanford")
    path = tmp_path / "stanford.urdf"
    path.write_text(kinematics.to_urdf(robot))
    urdf = robots.load(path)
    assert urdf.dh is None
    J = symbolic.numeric_function(symbolic.jacobian(urdf), symbolic.build_model(urdf))
    for q in random_configurations(urdf, 3, seed=1):
        np.testing.assert_allclose(J(q), kinematics.jacobian(urdf, q), atol=1e-9, rtol=0)
    with pytest.raises(SymbolicError, match="DH table"):
        symbolic.jacobian(urdf, symbolic_params=True)


# ------------------------------------------------------------------ derivations
@pytest.mark.slow
@pytest.mark.parametrize("name", LIBRARY)
def test_derivations_agree(name):
    robot = robots.load(name)
    result = symbolic.check_derivations(robot, "base", symbolic=name in SMALL + ["puma560"], samples=3)
    assert set(result.numeric) == set(symbolic.DERIVATIONS)
    assert result.ok, result
    if name in SMALL:
        assert all(v is True for k, v in result.symbolic.items() if k != "whitney")


@pytest.mark.slow
@pytest.mark.parametrize("name", ["trr", "elbow3r", "stanford"])
def test_derivations_agree_in_tool_frame(name):
    result = symbolic.check_derivations(robots.load(name), "tool", symbolic=True, samples=3)
    assert result.ok and all(v is True for k, v in result.symbolic.items() if k != "whitney")


def test_force_propagation_is_the_transpose():
    robot = robots.load("elbow3r")
    q = np.array([0.3, -0.7, 1.1])
    F = np.array([1.0, -2.0, 0.5, 0.1, 0.2, -0.3])
    JT = symbolic.numeric_function(symbolic.jacobian_force_propagation(robot).T, symbolic.build_model(robot))(
        q
    )
    np.testing.assert_allclose(JT @ F, kinematics.jacobian(robot, q).T @ F, atol=1e-12)


def test_normal_form_is_canonical():
    x, y = sp.symbols("x y", real=True)
    assert symbolic.is_zero(sp.sin(x + y) - sp.sin(x) * sp.cos(y) - sp.cos(x) * sp.sin(y), (x, y))
    assert symbolic.is_zero(sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1, (x,))
    assert not symbolic.is_zero(sp.sin(x) - sp.cos(x), (x,))


# --------------------------------------------------------- time limit and cache
def test_time_limit_falls_back_with_a_note():
    robot = robots.load("panda")
    d = symbolic.derive(robot, symbolic_params=True, timeout=1e-6, use_cache=False)
    assert not d.complete and "time limit" in d.notes[0] and "unsimplified" in d.notes[0]
    f = symbolic.numeric_function(d.J, symbolic.build_model(robot, True))
    q = random_configurations(robot, 1, seed=1)[0]
    np.testing.assert_allclose(f(q), kinematics.jacobian(robot, q), atol=1e-9)


def test_bad_inputs_raise_clear_errors():
    robot = robots.load("planar2")
    with pytest.raises(SymbolicError, match="frame must be 'base' or 'tool'"):
        symbolic.jacobian(robot, "world")
    with pytest.raises(SymbolicError, match="timeout"):
        symbolic.jacobian(robot, timeout=-1)
    with pytest.raises(SymbolicError, match="kinematics.Robot"):
        symbolic.jacobian("planar2")
    with pytest.raises(kinematics.JacobianLabError):
        symbolic.check_derivations(robot, "elsewhere")


def odd_arm(n):
    """An arm with twists and offsets that are not multiples of 90°: nothing collapses nicely."""
    rows = [
        dict(joint="revolute", a=0.1 * (i + 1), alpha=0.3 * (i + 1), d=0.05 * i, theta=0.2 * i)
        for i in range(n)
    ]
    return kinematics.Robot.from_dh(rows, name=f"odd{n}")


@pytest.mark.slow
@pytest.mark.parametrize("params", [False, True])
def test_odd_twists_and_offsets(params):
    robot = odd_arm(3)
    d = symbolic.derive(robot, symbolic_params=params, timeout=30)
    assert d.complete
    q2 = q_symbols(3)[1]
    offset = sp.Symbol("theta20", real=True) if params else sp.Rational(1, 5)
    assert sp.sin(q2 + offset) in d.J.atoms(sp.sin)  # offsets kept inside the angle, not expanded
    f = symbolic.numeric_function(d.J, symbolic.build_model(robot, params))
    for q in random_configurations(robot, 3, seed=1):
        np.testing.assert_allclose(f(q), kinematics.jacobian(robot, q), atol=1e-9, rtol=0)
