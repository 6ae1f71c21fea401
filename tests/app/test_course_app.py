"""The course in the app's tabs: J⁻¹ beside q̇ = J⁺v (the TRR worked example and the course's question),
the analytic Jacobian J_A with its representation singularity, J̇ q̇ at the tool, and the course's letters.

Server level (handles set as the user sets them, actions dispatched, snapshot and GUI content read).
Every expected value is worked out here from the course's own formulas (002: the TRR's
x = l2 s2 + l3 s23, y = l1 + l2 c2 + l3 c23, z = q1), from finite differences, or from the
Euler angles of the tool, never copied from the app.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from app_helpers import assert_all_finite, scene_node
from fakes import poll

import robots
from app.core.actions import GoTo, GoToRepresentationSingularity, SetConfiguration, SetRate
from app.core.commands import ChooseRobot
from app.views.palette import ACCEL_RGB
from app.viser_adapter import node_props
from kinematics import fk, jacobian
from kinematics.analytic_jacobian import euler_angles

L1, L2, L3 = 10.0, 5.0, 8.0  # the course's TRR
COURSE_V = np.array([17.256, -20.13, 0.5])  # the course's printed tool velocity [m/s]
COURSE_QD = np.array([0.5, math.pi / 2, math.pi / 4])  # its joint rates (0.5 m/s, 90°/s, 45°/s)


def course_J(q: np.ndarray) -> np.ndarray:
    """The course's TRR Jacobian (002, "Matricial"), rows ẋ, ẏ, ż."""
    _, q2, q3 = q
    return np.array(
        [
            [0.0, L2 * math.cos(q2) + L3 * math.cos(q2 + q3), L3 * math.cos(q2 + q3)],
            [0.0, -L2 * math.sin(q2) - L3 * math.sin(q2 + q3), -L3 * math.sin(q2 + q3)],
            [1.0, 0.0, 0.0],
        ]
    )


def course_J_inv(q: np.ndarray) -> np.ndarray:
    """adj(J) / det J of the course's J written out by hand (det J = −l2 l3 sin q3)."""
    _, q2, q3 = q
    s2, c2, s23, c23 = math.sin(q2), math.cos(q2), math.sin(q2 + q3), math.cos(q2 + q3)
    det = -L2 * L3 * math.sin(q3)
    adj = np.array(
        [
            [0.0, 0.0, det],
            [-L3 * s23, -L3 * c23, 0.0],
            [L2 * s2 + L3 * s23, L2 * c2 + L3 * c23, 0.0],
        ]
    )
    return adj / det


def choose(session, name: str) -> None:
    session.dispatch(ChooseRobot(name))
    session.settle()
    assert session.state.robot_name == name


def numbers(html: str) -> list[float]:
    """The numbers of the visible text (real minus signs, ×10ⁿ not expected here)."""
    text = re.sub(r"<[^>]*>", " ", html).replace("\u2212", "-")
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?", text)]


def test_trr_course_example_in_three_clicks(session):
    session.panel.robot.value = "trr"  # click 1: the robot
    session.settle()
    inverse = session.panel.inverse
    assert inverse.example_button is not None  # click 2 is the tab (client-side); click 3:
    inverse.example_button.value = True  # viser runs a button's callbacks on every set
    session.settle()
    state, snap = session.state, session.snapshot
    # The course's q = [5 m, 60°, −15°] is trr's home, and the course's v is desired.
    q = np.array([5.0, math.radians(60), math.radians(-15)])
    np.testing.assert_allclose(state.q, q, atol=1e-12)
    np.testing.assert_allclose(state.v_desired[:3], COURSE_V, atol=1e-12)
    assert state.configuration == "home"
    # J⁻¹ equals the hand-written adj J / det J, and the course's printed (rounded) matrix.
    J_inv = course_J_inv(q)
    np.testing.assert_allclose(snap.inverse.matrix, J_inv, atol=1e-12)
    printed = np.array([[0, 0, 1], [-0.5464, -0.5464, 0], [0.9647, 0.7879, 0]])
    np.testing.assert_allclose(snap.inverse.matrix, printed, atol=5e-5)
    assert snap.inverse.det == pytest.approx(np.linalg.det(course_J(q)))
    # q̇ = J⁻¹ v is the course's (0.5 m/s, 90°/s, 45°/s) up to the print's rounding of v.
    np.testing.assert_allclose(snap.rates, J_inv @ COURSE_V, atol=1e-12)
    np.testing.assert_allclose(snap.rates, COURSE_QD, atol=1e-3)
    bars = re.sub(r"<[^>]*>", " ", inverse.rates.content)
    assert "0.5\u2009m/s" in bars and "90°/s" in bars and "45°/s" in bars
    # The panel shows the printed matrix's figures (4 significant digits) and det J.
    shown = inverse.inverse.content
    assert "J<sup>−1</sup>" in shown
    for figure in ("−0.5464", "0.9647", "0.7879", "10.35"):
        assert figure in shown, figure
    # The worked example: its q̇ gives the course's v = J q̇.
    v = course_J(q) @ COURSE_QD
    assert np.allclose(v, COURSE_V, atol=5e-3)
    assert f"{v[0]:.3f}" in inverse.course.content.replace("\u2212", "-")
    assert_all_finite(session)


def test_the_course_question_is_answered(session):
    choose(session, "trr")
    session.dispatch(GoTo("course_question"))
    session.settle()
    q = np.array([15.0, math.radians(30), math.radians(-30)])
    snap = session.snapshot
    np.testing.assert_allclose(snap.q, q, atol=1e-12)
    J = course_J(q)
    np.testing.assert_allclose(snap.J_base[:3], J, atol=1e-12)
    np.testing.assert_allclose(snap.inverse.matrix, course_J_inv(q), atol=1e-12)
    assert snap.det == pytest.approx(-L2 * L3 * math.sin(q[2]))  # 20
    html = session.panel.inverse.course.content
    assert "question" in html
    v = J @ COURSE_QD  # the course's rates at the question's q
    shown = numbers(html)
    for x in v:
        assert any(abs(s - x) < 5e-3 for s in shown), (x, shown)
    for x in J.ravel():  # J itself is in the answer
        assert any(abs(s - x) < 5e-3 for s in shown), (x, shown)
    inv_shown = numbers(session.panel.inverse.inverse.content)
    for x in course_J_inv(q).ravel():
        assert any(abs(s - x) < 5e-4 for s in inv_shown), (x, inv_shown)
    assert_all_finite(session)


def test_inverse_blows_up_then_does_not_exist(session):
    choose(session, "trr")
    dets = []
    for deg in (-15.0, -1.0, -0.01):
        session.dispatch(SetConfiguration((5.0, math.radians(60), math.radians(deg))))
        session.settle()
        inv = session.snapshot.inverse
        assert inv.kind == "inverse"
        np.testing.assert_allclose(inv.matrix * inv.det, course_J_inv(session.state.q) * inv.det, atol=1e-9)
        dets.append(abs(inv.det))
    assert dets[0] > dets[1] > dets[2]
    session.dispatch(GoTo("stretched"))  # q3 = 0: det J = 0
    session.settle()
    assert session.snapshot.inverse.kind == "none" and session.snapshot.inverse.matrix is None
    assert "does not exist (det J = 0)" in session.panel.inverse.inverse.content
    assert_all_finite(session)


def test_pseudo_inverse_is_labelled_for_a_non_square_task(session):
    choose(session, "panda")  # 6×7
    inv = session.snapshot.inverse
    assert inv.kind == "pseudo"
    J = session.snapshot.J_base
    np.testing.assert_allclose(J @ inv.matrix, np.eye(6), atol=1e-9)
    assert "J<sup>+</sup>" in session.panel.inverse.inverse.content
    assert "not square" in session.panel.inverse.inverse.content


def test_analytic_jacobian_against_finite_differences_of_the_euler_angles(session):
    choose(session, "puma560")
    robot = session.state.robot
    rng = np.random.default_rng(7)
    for convention, label in (("zyx", "roll-pitch-yaw"), ("zyz", "ZYZ")):
        session.panel.matrix.representation.value = next(
            v for v in session.panel.matrix.representation.options if label in v
        )
        session.settle()
        assert session.state.options.representation == convention
        for _ in range(3):
            q = robot.home + rng.uniform(-0.4, 0.4, robot.dof)
            qd = rng.uniform(-1, 1, robot.dof)
            session.dispatch(SetConfiguration(tuple(q)))
            session.settle()
            view = session.snapshot.analytic
            assert view is not None and not view.singular
            h = 1e-6
            phi_plus = euler_angles(fk(robot, q + h * qd), convention)
            phi_minus = euler_angles(fk(robot, q - h * qd), convention)
            phi_dot = (phi_plus - phi_minus) / (2 * h)
            np.testing.assert_allclose(view.J_A[3:] @ qd, phi_dot, atol=1e-5)
            np.testing.assert_allclose(view.J_A[:3], jacobian(robot, q)[:3], atol=1e-12)
            np.testing.assert_allclose(view.M @ (view.J_A[3:] @ qd), jacobian(robot, q)[3:] @ qd, atol=1e-9)
        assert "M(φ)" in session.panel.matrix.analytic.content
    assert_all_finite(session)


def test_representation_singular_at_a_pitch_of_90_degrees(session):
    choose(session, "puma560")
    q0 = np.array(session.state.q) + np.array([0.0, 0.0, 0.0, 0.4, -0.5, 0.3])  # away from pitch ±90°
    session.dispatch(SetConfiguration(tuple(q0)))
    session.settle()
    assert abs(abs(euler_angles(fk(session.state.robot, q0), "zyx")[1]) - math.pi / 2) > 0.1
    session.dispatch(GoToRepresentationSingularity("zyx"))
    session.settle()
    state, snap = session.state, session.snapshot
    assert state.options.representation == "zyx"
    R = fk(state.robot, state.q)[:3, :3]
    assert abs(R[2, 0]) == pytest.approx(1.0, abs=1e-9)  # the tool's x axis along ±z: pitch ±90°
    assert abs(euler_angles(R, "zyx")[1]) == pytest.approx(math.pi / 2, abs=1e-6)
    assert snap.analytic.singular and snap.analytic.J_A is None
    assert snap.rank == 6 and snap.report.status == "regular"  # the geometric J is fine
    assert "representation singular" in session.panel.status.content
    assert "does not exist here" in session.panel.matrix.analytic.content
    # The tool kept its position; the arm is drawn there (the scene's tool frame is at the new q).
    np.testing.assert_allclose(fk(state.robot, state.q)[:3, 3], fk(state.robot, q0)[:3, 3], atol=1e-8)
    np.testing.assert_allclose(snap.tool_point, fk(state.robot, state.q)[:3, 3], atol=1e-12)
    # ZYZ: θ = 0 or 180°, the tool's z axis along the base's.
    session.dispatch(GoToRepresentationSingularity("zyz"))
    session.settle()
    R = fk(state.robot, session.state.q)[:3, :3]
    assert abs(R[2, 2]) == pytest.approx(1.0, abs=1e-9)
    assert session.snapshot.analytic.singular and session.state.options.representation == "zyz"
    assert_all_finite(session)


def test_the_first_analytic_try_at_the_puma_home_says_so_and_offers_the_regular_angles(session):
    """At the Puma's home the tool's x axis points down (R₃₁ = −1): roll-pitch-yaw, the menu's first
    analytic entry, is singular there. The tab says it is the angles' singularity, not the arm's, and
    its button switches to Euler ZYZ (θ = 90° here), which gives J_A at once."""
    choose(session, "puma560")
    matrix = session.panel.matrix
    assert not matrix.use_instead.visible
    matrix.representation.value = next(v for v in matrix.representation.options if "ZYX" in v)
    session.settle()
    R = fk(session.state.robot, session.state.q)[:3, :3]
    assert R[2, 0] == pytest.approx(-1.0, abs=1e-12) and abs(R[2, 2]) < 1e-9  # ZYX singular, ZYZ not
    view = session.snapshot.analytic
    assert view.singular and view.regular_instead == "zyz"
    assert "not of the arm" in matrix.analytic.content and "Euler ZYZ is regular" in matrix.analytic.content
    assert "ZYZ is regular here" in session.panel.status.content
    assert matrix.use_instead.visible and "ZYZ" in matrix.use_instead.label
    matrix.use_instead.value = True  # a click
    session.settle()
    view = session.snapshot.analytic
    assert session.state.options.representation == "zyz" and not view.singular
    assert not matrix.use_instead.visible
    assert euler_angles(R, "zyz")[1] == pytest.approx(math.pi / 2, abs=1e-9)
    J = jacobian(session.state.robot, session.state.q)
    np.testing.assert_allclose(view.M @ view.J_A[3:], J[3:], atol=1e-9)  # ω = M(φ) φ̇, column by column
    assert "representation singular" not in session.panel.status.content
    assert_all_finite(session)


def test_jdot_qd_arrow_and_readout_match_finite_differences(session):
    choose(session, "puma560")
    robot = session.state.robot
    rates = np.array([0.6, -0.4, 0.8, 0.3, -0.5, 0.7])
    for i, w in enumerate(rates):
        session.dispatch(SetRate(i, float(w)))
    session.settle()
    q, qd = np.array(session.state.q), np.array(session.state.qd)
    np.testing.assert_allclose(qd, rates)
    h = 1e-6
    fd = (jacobian(robot, q + h * qd) @ qd - jacobian(robot, q - h * qd) @ qd) / (2 * h)
    a = session.snapshot.jdot_qd
    np.testing.assert_allclose(a, fd, atol=1e-6)
    # The arrow: from the tool point, along the linear part, in its own colour.
    node = scene_node(session, "/lab/jacobian/jdot_qd")
    props = node_props(node)
    assert props["visible"]
    points = np.asarray(props["points"], float)[0]
    np.testing.assert_allclose(points[0], fk(robot, q)[:3, 3], atol=1e-5)
    direction = points[1] - points[0]
    assert np.dot(direction, a[:3]) / (np.linalg.norm(direction) * np.linalg.norm(a[:3])) == pytest.approx(
        1.0
    )
    assert tuple(np.asarray(props["colors"]).reshape(-1, 3)[0]) == ACCEL_RGB
    assert "J̇ q̇" in session.panel.forward.accel.content
    # Off with the toggle.
    session.panel.forward.jdot.value = False
    session.settle()
    assert not node_props(node)["visible"]
    assert_all_finite(session)


@pytest.mark.slow
def test_course_letters_in_the_symbolic_j(symbolic_session):
    session = symbolic_session
    choose(session, "trr")
    letters = session.panel.matrix.letters
    assert letters is not None
    letters.value = True
    session.settle()
    assert session.state.options.course_letters

    def shown() -> str:
        return session.panel.matrix.symbolic.content

    poll(lambda: "letters" in shown())
    html = shown()
    assert "<msub><mi>l</mi><mn>2</mn></msub>" in html and "<msub><mi>l</mi><mn>3</mn></msub>" in html
    assert "<mi>det</mi>" in html  # det J = −l2 l3 s3 and its singular set under J
    letters.value = False
    session.settle()
    poll(lambda: "letters" not in shown() and "<math" in shown())
    assert "<msub><mi>l</mi><mn>3</mn></msub>" not in shown()  # numbers again: 5, 8
    # The symbolic J⁻¹, on demand: the TRR's file names its letters, so J⁻¹ is in them.
    session.panel.inverse.symbolic_button.value = True
    session.settle()
    assert session.state.options.symbolic_inverse
    poll(lambda: "<math" in session.panel.inverse.symbolic.content)
    inv = session.panel.inverse.symbolic.content
    assert "<msub><mi>l</mi><mn>3</mn></msub>" in inv and "<mi>adj</mi>" in inv
    session.panel.inverse.symbolic_button.value = True  # hides it
    session.settle()
    assert not session.state.options.symbolic_inverse and session.panel.inverse.symbolic.content == ""


def test_the_buttons_are_shown_where_they_apply(session):
    assert "trr" in robots.names()
    choose(session, "trr")
    assert session.panel.matrix.letters is not None  # a DH table: letters
    assert session.panel.matrix.go_singular is None  # three joints: no orientation to choose
    assert session.panel.inverse.example_button is not None  # a [[motions]] preset in base axes
    assert session.panel.inverse.symbolic_button is not None  # square task J
    choose(session, "panda")
    assert session.panel.matrix.go_singular is not None
    assert session.panel.inverse.symbolic_button is None  # 6×7: J⁺ only
