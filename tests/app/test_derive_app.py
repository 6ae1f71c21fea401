"""Server-level tests of the Derive tab: the DH table follows the joints, each derivation's step shows
the numbers of an independent construction at q, draws its vectors in the 3-D view, and never shows a
NaN. Each test starts from a fresh state of the default robot (the ``session`` fixture)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from app_helpers import assert_all_finite, derive_walk, running_lab, scene_node
from fakes import poll
from locations import DATA

from app.core.actions import SetJoint, SetRate, SetWrench
from app.core.commands import ChooseRobot
from app.core.snapshot.derive import METHODS
from app.views.fmt import fixed
from app.views.palette import joint_color
from app.views.scene.overlays import LINEAR_SECONDS
from kinematics import fk, jacobian, link_frames


def choose(session, name: str) -> None:
    session.dispatch(ChooseRobot(name))
    session.settle()
    assert session.state.robot_name == name


def text(html: str) -> str:
    return re.sub(r"<[^>]*>", " ", html)


def vec(v) -> str:
    return ", ".join(fixed(x, 3) for x in v)


def test_dh_table_shows_the_moving_joint_variable(session):
    choose(session, "puma560")
    session.dispatch(SetJoint(1, math.radians(-37.5)))
    session.settle()
    table = text(session.panel.derive.table.content)
    row = session.state.robot.dh[1]
    expected = math.degrees(-math.radians(37.5) + row.theta)
    assert f"= {expected:.4g}°".replace("-", "−") in table
    assert "θᵢ" in table and "αᵢ" in table  # standard DH columns
    choose(session, "puma560_mdh")
    assert "αᵢ₋₁" in text(session.panel.derive.table.content)  # modified DH columns


def test_whitney_step_shows_and_draws_the_column(session):
    choose(session, "puma560")
    session.dispatch(SetJoint(2, 0.4))
    session.settle()
    derive_walk(session, "whitney", 2)
    robot, q = session.state.robot, np.array(session.state.q)
    # Independently: joint 3 turns about z₂ of DH frame 2, through its origin p₂.
    L = link_frames(robot, q)
    z2, p2, pn = L[2, :3, 2], L[2, :3, 3], L[-1, :3, 3]
    column = np.cross(z2, pn - p2)
    body = text(session.panel.derive.body.content)
    assert "z₂ × (pₙ − p₂)" in body and vec(column) in body and vec(z2) in body
    assert "✓ equals column 3 of J(q)" in body
    np.testing.assert_allclose(column, jacobian(robot, q)[:3, 2], atol=1e-12)
    arrows = scene_node(session, "/lab/derive/arrows")
    assert arrows.visible
    np.testing.assert_allclose(arrows.points[0, 1] - arrows.points[0, 0], column * LINEAR_SECONDS, atol=1e-5)
    labels = {scene_node(session, f"/lab/derive/label_{k}").text for k in range(3)}
    assert labels == {"z₂", "pₙ − p₂", "z₂ × (pₙ − p₂)"}
    assert tuple(arrows.colors[0]) == joint_color(2)
    lever = scene_node(session, "/lab/derive/thin_arrows")
    np.testing.assert_allclose(lever.points[0], [p2, pn], atol=1e-5)
    derive_walk(session, "whitney", 1)  # the next joint's arrows take its colour
    assert tuple(scene_node(session, "/lab/derive/arrows").colors[0]) == joint_color(1)
    assert_all_finite(session)


def test_next_and_previous_step_stop_at_the_ends(session):
    choose(session, "planar2")
    derive_walk(session, "whitney", 0)
    buttons = session.panel.derive.buttons
    for expected in (1, 1):
        buttons._impl.value = "Next ▶"  # noqa: SLF001 - what the click handler reads
        session.panel.derive._clicked(type("E", (), {"target": buttons})())  # noqa: SLF001
        session.settle()
        assert session.state.options.derive_step == expected
    buttons._impl.value = "◀ Previous"  # noqa: SLF001
    for expected in (0, 0):
        session.panel.derive._clicked(type("E", (), {"target": buttons})())  # noqa: SLF001
        session.settle()
        assert session.state.options.derive_step == expected


def test_dh_step_shows_A_i_and_its_product(session):
    choose(session, "puma560")
    derive_walk(session, "dh", 3)
    robot, q = session.state.robot, np.array(session.state.q)
    L = link_frames(robot, q)
    A4 = np.linalg.inv(L[3]) @ L[4]
    T04 = np.linalg.inv(L[0]) @ L[4]
    body = session.panel.derive.body.content
    for T in (A4, T04):
        for row in T[:3]:
            assert "".join(f"<td>{fixed(x, 3)}</td>" for x in row) in body
    labels = {scene_node(session, f"/lab/derive/label_{k}").text for k in range(4)}
    assert labels == {"x₃", "z₃", "x₄", "z₄"}
    assert "sel" in session.panel.derive.table.content


def test_differentiation_step_draws_the_tool_path_and_its_tangent(session):
    choose(session, "planar2")
    derive_walk(session, "differentiation", 0)
    robot, q = session.state.robot, np.array(session.state.q)
    lines = scene_node(session, "/lab/derive/lines")
    assert lines.visible
    # The path: the tool as q1 alone sweeps; every point at the tool's distance from the base axis.
    r = np.linalg.norm(fk(robot, q)[:2, 3])
    np.testing.assert_allclose(np.linalg.norm(lines.points[:, 0, :2], axis=1), r, rtol=1e-5)
    arrows = scene_node(session, "/lab/derive/arrows")
    h = 1e-5
    dq = np.array([h, 0.0])
    dp = (fk(robot, q + dq)[:3, 3] - fk(robot, q - dq)[:3, 3]) / (2 * h)
    np.testing.assert_allclose(arrows.points[0, 1] - arrows.points[0, 0], dp * LINEAR_SECONDS, atol=1e-5)


def test_propagation_uses_the_tabs_rates_and_ends_at_J_qdot(session):
    choose(session, "puma560")
    derive_walk(session, "propagation", 5)
    assert "shown for q̇ᵢ = 1" in text(session.panel.derive.body.content)
    for i, rate in enumerate((0.3, -0.2, 0.5, 0.1, 0.4, -0.6)):
        session.dispatch(SetRate(i, rate))
    session.settle()
    body = text(session.panel.derive.body.content)
    assert "shown for q̇ᵢ = 1" not in body
    twist = jacobian(session.state.robot, session.state.q) @ np.array(session.state.qd)
    assert "✓ at the tool, (v, ω) equals J q̇" in body
    assert vec(twist[3:]) in body  # ω₆ = ω of the tool
    assert_all_finite(session)


def test_force_step_is_the_transpose(session):
    choose(session, "planar2")
    derive_walk(session, "force", 0)
    session.dispatch(SetWrench(1, 2.0))
    session.settle()
    tau = jacobian(session.state.robot, session.state.q).T @ np.array(session.state.wrench)
    body = text(session.panel.derive.body.content)
    assert "✓ equals (Jᵀ F)₁" in body
    assert f"{fixed(tau[0], 3)}".rstrip("0").rstrip(".") in body


def test_switching_robot_keeps_the_walk_and_starts_at_joint_1(session):
    """A new robot's walk starts at its first joint, not at the last robot's step (issue 21)."""
    choose(session, "puma560")
    derive_walk(session, "whitney", 5)
    choose(session, "planar2")
    assert session.state.options.derive == "whitney" and session.state.options.derive_step == 0
    assert "Step 1 of 2" in text(session.panel.derive.body.content)


@pytest.mark.parametrize("method", [m for m in METHODS if m])
def test_every_step_at_a_singularity_is_finite(session, method):
    choose(session, "puma560")
    session.dispatch(SetJoint(4, 0.0))  # wrist singular
    session.settle()
    for step in range(6):
        derive_walk(session, method, step)
        assert "✗" not in session.panel.derive.body.content
        assert_all_finite(session)
    session.panel.derive.method.value = METHODS[""]
    session.settle()
    assert not scene_node(session, "/lab/derive/arrows").visible
    assert not session.panel.derive.body.visible


def test_a_urdf_robot_has_no_dh_table_but_every_walk():
    with running_lab(urdf=str(DATA / "iiwa14_like.urdf")) as (lab, session, _):
        assert "comes from a URDF" in session.panel.derive.table.content
        for method, step in (("whitney", 3), ("propagation", 6), ("force", 3)):
            derive_walk(session, method, step)
            assert "✓" in session.panel.derive.body.content
            assert_all_finite(session)


@pytest.mark.slow
def test_each_step_is_shown_in_symbols_too(symbolic_session):
    """The symbolic worker types the step's formulas; the tab shows the ones of the current joint
    (and the assembled J and det J at the last one)."""
    session = symbolic_session
    choose(session, "planar2")
    derive_walk(session, "whitney", 1)
    formula = session.panel.derive.formula
    poll(lambda: "<math" in formula.content)
    assert "Column 2 = z₁ × (pₙ − p₁)" in formula.content
    assert "Column 1" not in formula.content  # only this joint's steps
    # The last step: det J, and its singular set typeset under it (θ₂ ∈ {0, π}), not as SymPy text.
    assert "det J of the task rows, factored: J is singular where a factor vanishes" in formula.content
    assert "(elbow singularity)" in formula.content and "<mo>⇒</mo>" in formula.content
    assert "sin(q2)" not in formula.content
    derive_walk(session, "whitney", 0)
    assert "Column 1 = z₀ × (pₙ − p₀)" in formula.content and "det J" not in formula.content
    derive_walk(session, "propagation", 0)
    poll(lambda: "ω" in formula.content and "<math" in formula.content)
    derive_walk(session, "dh", 1)
    poll(lambda: "A₂" in formula.content and "⁰T₂" in formula.content)


@pytest.mark.parametrize(
    ("robot", "method"), [("trr", "propagation"), ("puma560", "whitney"), ("stanford", "dh")]
)
def test_step_labels_keep_clear_of_the_joint_labels_and_of_each_other(session, robot, method):
    """Issue 21, item 12: on the TRR, frames 2 and 3 share their origin, so v₂'s label sat on q3's.
    Every step label is at least CLEARANCE robot sizes from every joint label and every other step label."""
    from app.views.scene.geometry import LABEL_CLEARANCE as CLEARANCE

    choose(session, robot)
    size = session.scene.size
    for step in range(session.state.robot.dof):
        derive_walk(session, method, step)
        joints = [scene_node(session, f"/lab/arm/label_{j}") for j in range(session.state.robot.dof)]
        at = [np.asarray(n.position) for n in joints if n.visible]
        shown = [
            np.asarray(n.position)
            for k in range(6)
            if (n := scene_node(session, f"/lab/derive/label_{k}")).visible
        ]
        assert shown, (robot, method, step)
        for i, p in enumerate(shown):
            others = at + shown[:i]
            if others:
                gaps = np.linalg.norm(np.array(others) - p, axis=1)
                assert gaps.min() >= CLEARANCE * size * (1 - 1e-6), (
                    robot,
                    method,
                    step,
                    i,
                    gaps.min() / size,
                )


@pytest.mark.slow
def test_det_j_s_step_shows_its_singular_sets_typeset_under_it_in_the_joints_notation():
    """The Derive tab's det J step (what the symbolic worker sends): its caption leads to the sets, and
    the sets follow the formula as MathML (θ₂ ∈ {0, π}, the elbow singularity), not as SymPy text."""
    from app.services.symbolic_requests import _steps_mathml
    from robots import load

    steps = {s[1]: (s[2], s[3]) for s in _steps_mathml(load("planar2"), "whitney", 120.0)}
    title, body = steps["detJ"]
    assert title.endswith("J is singular where a factor vanishes")
    assert "sin(" not in title and "pi" not in title
    sets = body.split("</math>")[-2]  # the last block: the set, after the formula of det J
    assert "<mo>⇒</mo>" in sets and "&#952;" in sets and "&#960;" in sets  # ⇒ θ₂ ∈ {0, π}
    assert "(elbow singularity)" in sets
