"""Issue 29 item 7 in the app: a joint at its limit makes the configuration a critical point (002: the
singular points and the joint-limit points); the status says which joint, the sense it can still move
in, and that the tool velocity along its column of J is possible in that sense only."""

from __future__ import annotations

import numpy as np

import robots
from app.core.actions import SetJoint
from app.core.i18n import translations
from app.core.reducer import reduce
from app.core.snapshot import compute
from app.core.state import LabState
from app.views.panel.readouts import status_html
from kinematics import fk, jacobian


def test_a_slider_at_its_end_names_the_critical_point_and_the_one_sense_left():
    state = LabState.initial("puma560", robots.load("puma560"))
    assert compute(state).limits == () and "Critical point" not in status_html(compute(state), state)
    state = reduce(state, SetJoint(1, 10.0))  # past the upper limit: the slider stops at it
    snap = compute(state)
    (c,) = snap.limits
    assert (c.joint, c.side, c.sense) == (1, "upper", -1)
    assert np.allclose(c.column, -jacobian(state.robot, state.q)[:, 1])
    # the only velocity left along that column is −J₂: a small step q₂ − h moves the tool by ≈ −h J₂
    h = 1e-6
    q = np.array(state.q)
    q[1] -= h
    moved = (fk(state.robot, q)[:3, 3] - fk(state.robot, state.q)[:3, 3]) / h
    assert np.allclose(moved, c.column[:3], atol=1e-5)
    html = status_html(snap, state)
    assert "Critical point" in html and "joint 2" in html and "upper limit" in html and "q̇2 ≤ 0" in html
    es = status_html(snap, state, translations("es"))
    assert "Punto crítico" in es and "límite articular superior" in es


def test_the_lower_limit_says_the_joint_can_only_increase():
    state = reduce(LabState.initial("planar2", robots.load("planar2")), SetJoint(0, -10.0))
    (c,) = compute(state).limits
    assert (c.joint, c.side, c.sense) == (0, "lower", 1)
    assert "q̇1 ≥ 0" in status_html(compute(state), state)
