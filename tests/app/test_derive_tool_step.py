"""The DH walk's last step (issue 29, item 1): the tool frame as row n + 1 of the DH table, 001's ³T₄
and ⁰T₄ of the 3R, at server level: its numbers against the robot's tool transform and fk, the
step's bounds, the 3-D frames drawn, and its symbolic steps chosen for the tab."""

from __future__ import annotations

import numpy as np
from app_helpers import assert_all_finite, derive_walk

import robots
from app.core.actions import SetConfiguration, SetOption
from app.core.commands import ChooseRobot
from app.core.reducer import reduce
from app.core.snapshot.derive import METHODS
from app.core.state import LabState
from app.views.panel.derive_html import formulas_html
from kinematics import fk, link_frames


def test_the_3r_walk_ends_with_the_tool_frame_3T4_and_0T4(session):
    session.dispatch(ChooseRobot("elbow3r"))  # 001's spatial 3R: the tool is frame 4 = Tx(L3)
    session.dispatch(SetConfiguration((0.3, -0.7, 1.1)))
    session.settle()
    derive_walk(session, "dh", 3)
    assert session.state.options.derive_step == 3 and session.panel.derive.step.max == 4
    d = session.snapshot.derive
    robot, q = session.state.robot, np.array(session.state.q)
    assert d.tool and d.joint == 3
    L3 = 0.4  # the robot file's L3: ³T₄ = Tx(L3), 001's fourth DH row (α₃ = 0, a₃ = L3, θ₄ = 0)
    expected = np.eye(4)
    expected[0, 3] = L3
    np.testing.assert_allclose(d.A, expected, atol=1e-12)
    np.testing.assert_allclose(d.T0, fk(robot, q), atol=1e-12)
    L = link_frames(robot, q)
    np.testing.assert_allclose(d.T0, L[3] @ expected, atol=1e-12)  # ⁰T₄ = ⁰T₃ · ³T₄
    body = session.panel.derive.body.content
    assert "Step 4 of 4: the tool frame, row 4 of the DH table" in body
    assert "³T₄" in body and "⁰T₄ = A₁ A₂ A₃ · ³T₄" in body
    labels = [lab.text for lab in session.scene.derive.labels if lab.visible]
    assert "x₃" in labels and "x₄" in labels
    assert len(session.scene.derive.extent)
    # Joint steps of the DH walk count the tool step too; Next stops on it.
    derive_walk(session, "dh", 0)
    assert "Step 1 of 4" in session.panel.derive.body.content
    session.dispatch(SetOption("derive_step", 9))
    session.settle()
    assert session.state.options.derive_step == 3
    # Another method has no tool step: back on the last joint.
    session.panel.derive.method.value = METHODS["whitney"]
    session.settle()
    assert session.state.options.derive_step == 2 and session.panel.derive.step.max == 3
    assert "Step 3 of 3" in session.panel.derive.body.content
    assert_all_finite(session)


def test_the_tool_step_is_reduced_only_on_the_dh_walk():
    puma = robots.load("puma560")
    state = reduce(LabState.initial("puma560", puma), SetOption("derive", "whitney"))
    assert reduce(state, SetOption("derive_step", 6)).options.derive_step == 5
    dh = reduce(state, SetOption("derive", "dh"))
    assert reduce(dh, SetOption("derive_step", 6)).options.derive_step == 6
    back = reduce(reduce(dh, SetOption("derive_step", 6)), SetOption("derive", "propagation"))
    assert back.options.derive_step == 5


def test_the_tool_step_shows_the_tool_transform_in_symbols_or_says_there_is_none():
    steps = (
        (0, "A1", "A₁", "<math>a1</math>"),
        (None, "Atool", "³T_tool", "<math>tool</math>"),
        (None, "T0_tool", "⁰T_tool", "<math>T0tool</math>"),
    )
    html = formulas_html(steps, "", "dh", 3, tool=True)
    assert "<math>tool</math>" in html and "<math>T0tool</math>" in html and "a1" not in html
    none = formulas_html(steps[:1], "", "dh", 2, tool=True)
    assert "frame 2 itself" in none and "identity" in none
