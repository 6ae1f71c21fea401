"""002's third way to J⁻¹ in the q̇ = J⁺ v tab (issue 29, item 4): from the closed-form inverse
kinematics, beside the inverse of J, for the TRR and the planar 2R, at server level."""

from __future__ import annotations

import math
import re

import numpy as np
from app_helpers import assert_all_finite

from app.core.actions import SetConfiguration, SetOption
from app.core.commands import ChooseRobot
from kinematics import jacobian


def _choose(session, name: str) -> None:
    session.dispatch(ChooseRobot(name))
    session.dispatch(SetOption("twist_frame", "base"))
    session.settle()


def _closed_text(html: str) -> str:
    part = html.split('<div class="jl-closed">', 1)
    return re.sub(r"<[^>]*>", " ", part[1]) if len(part) == 2 else ""


def test_trr_closed_form_jinv_is_the_courses_and_the_inverse_of_j(session):
    _choose(session, "trr")
    session.dispatch(SetConfiguration((5.0, math.radians(60), math.radians(-15))))
    session.settle()
    view = session.snapshot.inverse
    assert view.kind == "inverse" and view.closed and view.closed_form is not None
    course = np.array([[0, 0, 1], [-0.5464, -0.5464, 0], [0.9647, 0.7879, 0]])  # 002, TRR example
    np.testing.assert_allclose(view.closed_form, course, atol=5e-5)
    np.testing.assert_allclose(
        view.closed_form, np.linalg.inv(jacobian(session.state.robot, session.state.q)[:3])
    )
    assert view.closed_gap is not None and view.closed_gap < 1e-12
    text = _closed_text(session.panel.inverse.inverse.content)
    for figure in ("−0.5464", "0.9647", "0.7879", "third way", "∂g/∂x"):
        assert figure in text, figure
    # Singular (q3 = 0): neither exists, and the tab says why in the closed form's words.
    session.dispatch(SetConfiguration((5.0, 0.4, 0.0)))
    session.settle()
    view = session.snapshot.inverse
    assert view.kind == "none" and view.closed and view.closed_form is None
    assert "sin q3 = 0" in session.panel.inverse.inverse.content
    assert_all_finite(session)


def test_planar_2r_has_it_and_the_puma_does_not(session):
    _choose(session, "planar2")
    session.dispatch(SetConfiguration((0.3, 1.1)))
    session.settle()
    view = session.snapshot.inverse
    J = jacobian(session.state.robot, session.state.q)[:2]
    np.testing.assert_allclose(view.closed_form, np.linalg.inv(J), atol=1e-12)
    a1 = a2 = 1.0
    q1, q2 = 0.3, 1.1  # 002's printed J⁻¹ of the planar arm, written out
    printed = np.array(
        [
            [a2 * math.cos(q1 + q2), a2 * math.sin(q1 + q2)],
            [-a1 * math.cos(q1) - a2 * math.cos(q1 + q2), -a1 * math.sin(q1) - a2 * math.sin(q1 + q2)],
        ]
    ) / (a1 * a2 * math.sin(q2))
    np.testing.assert_allclose(view.closed_form, printed, atol=1e-12)
    session.dispatch(SetOption("twist_frame", "tool"))
    session.settle()
    assert session.snapshot.inverse.closed_form is None
    assert "base axes only" in session.panel.inverse.inverse.content
    _choose(session, "puma560")
    assert not session.snapshot.inverse.closed and "jl-closed" not in session.panel.inverse.inverse.content
