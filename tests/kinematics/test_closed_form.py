"""J⁻¹ from the closed-form inverse kinematics (002's third way), against the course's TRR numbers,
finite differences of the closed-form IK itself, and the inverse of J."""

from __future__ import annotations

import math

import numpy as np
import pytest

import robots
from kinematics import fk, jacobian
from kinematics.analysis import task_rows
from kinematics.errors import ConfigurationError
from kinematics.motion.closed_form import closed_form, closed_form_ik, closed_form_inverse_jacobian


def test_the_course_trr_inverse_from_the_closed_form():
    robot = robots.load("trr")
    q = np.array([5.0, math.radians(60), math.radians(-15)])
    course = np.array([[0, 0, 1], [-0.5464, -0.5464, 0], [0.9647, 0.7879, 0]])  # 002, TRR example
    Ji = closed_form_inverse_jacobian(robot, q)
    assert Ji is not None
    np.testing.assert_allclose(Ji, course, atol=5e-5)
    rates = Ji @ np.array([17.256, -20.13, 0.500])  # the course's tool velocity back to its q̇
    np.testing.assert_allclose(rates, [0.5, math.pi / 2, math.pi / 4], atol=2e-3)


@pytest.mark.parametrize("name", ["planar2", "trr"])
def test_closed_form_jinv_is_the_derivative_of_the_ik_and_the_inverse_of_j(name):
    robot = robots.load(name)
    rows = list(task_rows(robot))
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(40):
        q = rng.uniform(-2.5, 2.5, robot.dof)
        if name == "trr":
            q[0] = rng.uniform(0, 16)
        if abs(math.sin(q[-1])) < 0.1:
            continue
        x = fk(robot, q)[:3, 3]
        elbow = math.copysign(1.0, math.sin(q[-1]))
        back = closed_form_ik(robot, x, elbow)
        np.testing.assert_allclose(fk(robot, back)[:3, 3], x, atol=1e-9)  # the IK reaches the point
        h = 1e-6
        fd = np.column_stack(
            [
                (closed_form_ik(robot, x + h * e, elbow) - closed_form_ik(robot, x - h * e, elbow)) / (2 * h)
                for e in np.eye(3)[rows]
            ]
        )
        Ji = closed_form_inverse_jacobian(robot, q)
        assert Ji is not None
        np.testing.assert_allclose(Ji, fd, atol=1e-5)  # ∂g/∂x, by hand = by differences
        np.testing.assert_allclose(Ji, np.linalg.inv(jacobian(robot, q)[rows]), atol=1e-9)
        checked += 1
    assert checked > 20


def test_no_closed_form_inverse_at_a_singularity_or_for_other_arms():
    assert closed_form_inverse_jacobian(robots.load("planar2"), [0.4, 0.0]) is None  # q2 = 0: straight
    assert closed_form_inverse_jacobian(robots.load("trr"), [3.0, 0.5, math.pi]) is None
    for name in ("puma560", "elbow3r", "planar3", "scara", "ur5"):
        assert closed_form(robots.load(name)) is None
    with pytest.raises(ConfigurationError, match="no closed-form"):
        closed_form_inverse_jacobian(robots.load("puma560"), np.zeros(6))
    with pytest.raises(ConfigurationError, match="out of reach"):
        closed_form_ik(robots.load("planar2"), [3.0, 0.0, 0.0])


def test_the_handout_carries_the_closed_form_jinv_in_each_language():
    from app.core.i18n import translations
    from kinematics.symbolic.handout import handout

    trr = robots.load("trr")  # its home is the course's q = (5 m, 60°, −15°)
    english = handout(trr, "html", "whitney")
    part = english[english.index("the third way") :]
    for figure in ("−0.5464", "0.9647", "0.7879"):
        assert figure in part, figure
    assert "the third way" in handout(trr, "tex", "whitney")
    polish = handout(trr, "html", "whitney", words=translations("pl"))
    assert "trzeci sposób" in polish and "0,9647" in polish[polish.index("trzeci sposób") :]
    assert "the third way" not in handout(robots.load("puma560"), "html", "whitney")


@pytest.mark.parametrize("name", ["planar2", "trr"])
def test_the_symbolic_derivative_of_the_closed_form_is_the_numeric_one(name):
    import sympy as sp

    from kinematics.symbolic.closed_form import TOOL_POINT, closed_form_symbols

    robot = robots.load(name)
    rows = list(task_rows(robot))
    rng = np.random.default_rng(3)
    for elbow in (1, -1):
        g, dg = closed_form_symbols(robot, elbow)
        G = sp.lambdify(TOOL_POINT, g, "numpy")
        DG = sp.lambdify(TOOL_POINT, dg, "numpy")
        for _ in range(10):
            q = rng.uniform(-2.5, 2.5, robot.dof)
            q[-1] = elbow * rng.uniform(0.3, 2.8)  # on this branch, away from sin q = 0
            x = fk(robot, q)[:3, 3]
            back = np.asarray(G(*x), float).ravel()
            np.testing.assert_allclose(np.cos(back - q), 1.0, atol=1e-9)  # g(f(q)) = q (mod 2π)
            np.testing.assert_allclose(
                np.asarray(DG(*x), float), closed_form_inverse_jacobian(robot, q), atol=1e-9
            )
            assert np.asarray(DG(*x), float).shape == (len(rows), len(rows))
