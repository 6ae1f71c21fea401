"""The symbolic J⁻¹ = adj(J) / det J of kinematics.symbolic.inverse, held against the numeric inverse and
the course's printed inverses (002: the planar RR's J⁻¹ = 1/(a1 a2 s2) [[a2 c12, a2 s12], [−a1 c1 − a2 c12,
−a1 s1 − a2 s12]])."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

import robots
from kinematics import jacobian
from kinematics.analysis import task_rows
from kinematics.symbolic import SymbolicError
from kinematics.symbolic.inverse import inverse, inverse_mathml


@pytest.mark.slow
@pytest.mark.parametrize("name", ["planar2", "trr", "elbow3r"])
def test_adjugate_over_det_is_the_numeric_inverse(name):
    robot = robots.load(name)
    inv = inverse(robot, symbolic_params=False)
    q_syms = [s for s in inv.J.free_symbols if s.name.startswith("q")]
    f = sp.lambdify(sorted(q_syms, key=lambda s: s.name), inv.matrix, "numpy")
    rng = np.random.default_rng(3)
    rows = list(task_rows(robot))
    for _ in range(5):
        q = robot.home + rng.uniform(-0.5, 0.5, robot.dof)
        args = [q[int(s.name[1:]) - 1] for s in sorted(q_syms, key=lambda s: s.name)]
        J = jacobian(robot, q)[rows]
        np.testing.assert_allclose(np.array(f(*args), float), np.linalg.inv(J), atol=1e-9)


def test_planar_rr_matches_the_course_print():
    robot = robots.load("planar2")
    inv = inverse(robot, symbolic_params=True)
    a1, a2, q1, q2 = sp.symbols("a1 a2 q1 q2", real=True)
    course = sp.Matrix(
        [
            [a2 * sp.cos(q1 + q2), a2 * sp.sin(q1 + q2)],
            [-a1 * sp.cos(q1) - a2 * sp.cos(q1 + q2), -a1 * sp.sin(q1) - a2 * sp.sin(q1 + q2)],
        ]
    ) / (a1 * a2 * sp.sin(q2))
    names = {s.name: s for s in inv.matrix.free_symbols}
    ours = inv.matrix.subs(
        {names[k]: v for k, v in zip(("a1", "a2", "q1", "q2"), (a1, a2, q1, q2), strict=True)}
    )
    assert sp.simplify(ours - course) == sp.zeros(2, 2)


@pytest.mark.slow
def test_trr_letters_and_where_it_does_not_exist():
    robot = robots.load("trr")
    inv = inverse(robot, symbolic_params=True)
    l2, l3 = (next(s for s in inv.det.expr.free_symbols if s.name == n) for n in ("l2", "l3"))
    q3 = next(s for s in inv.det.expr.free_symbols if s.name == "q3")
    assert sp.simplify(inv.det.expr + l2 * l3 * sp.sin(q3)) == 0  # det J = −l2 l3 sin q3
    assert sp.simplify(inv.J * inv.adj - inv.det.expr * sp.eye(3)) == sp.zeros(3, 3)
    html = inverse_mathml(robot, symbolic_params=True)
    assert "<mi>adj</mi>" in html and "<msub><mi>l</mi><mn>2</mn></msub>" in html
    assert "no J⁻¹ there" in html and "nan" not in html.lower()
    assert math.isfinite(float(inv.det.expr.subs({l2: 5, l3: 8, q3: 0.3})))


def test_refuses_a_non_square_or_large_task():
    with pytest.raises(SymbolicError, match="up to"):
        inverse(robots.load("puma560"))
    with pytest.raises(SymbolicError, match="pseudo-inverse"):
        inverse(robots.load("scara"))  # 3 task rows, 4 joints
