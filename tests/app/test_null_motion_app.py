"""Issue 29 item 3 in the app: the null joint motion at a singularity (Ker J), in the snapshot, said in
words in the Motion tab and played (the joints move, the tool stands still; checked by fk)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fakes import poll

import robots
from app.core.actions import PlayNullMotion, SetConfiguration, Step
from app.core.i18n import translations
from app.core.motion_rules import FRAME_DT
from app.core.reducer import InvalidAction, reduce
from app.core.refusals import say
from app.core.self_motion import null_motion_text
from app.core.snapshot import compute
from app.core.state import LabState
from app.views.panel.live import live_html
from kinematics import fk, jacobian


def wrist_singular() -> tuple[float, ...]:
    q = robots.load("puma560").home.copy()
    q[4] = 0.0  # q5 = 0: axes 4 and 6 collinear
    return tuple(float(x) for x in q)


def test_the_snapshot_holds_the_null_motion_only_at_a_singularity():
    state = LabState.initial("puma560", robots.load("puma560"))
    assert compute(state).null is None  # home is regular
    state = reduce(state, SetConfiguration(wrist_singular()))
    null = compute(state).null
    assert null is not None and null.joints == (3, 5)
    assert np.abs(jacobian(state.robot, state.q) @ null.direction).max() < 1e-12
    assert null_motion_text(null.direction) == "q̇4 = −q̇6"


def test_playing_the_null_motion_moves_q4_and_q6_and_holds_the_tool_pose():
    state = reduce(LabState.initial("puma560", robots.load("puma560")), SetConfiguration(wrist_singular()))
    T0 = fk(state.robot, state.q)
    state = reduce(state, PlayNullMotion())
    assert state.playing and state.motion.kind == "path"
    state = reduce(state, Step(FRAME_DT))
    assert "the null motion (Ker J)" in live_html(state)  # not "to the nearest singularity"
    seen = [np.array(state.q)]
    while state.playing:
        state = reduce(state, Step(FRAME_DT))
        seen.append(np.array(state.q))
        assert np.abs(fk(state.robot, state.q) - T0).max() < 1e-12
    Q = np.array(seen)
    assert np.ptp(Q[:, 3]) > 1.0 and np.ptp(Q[:, 5]) > 1.0  # both swung over a radian
    assert np.allclose(Q[:, 3] - Q[0, 3], -(Q[:, 5] - Q[0, 5]), atol=1e-12)  # q̇4 = −q̇6
    assert np.ptp(Q[:, [0, 1, 2, 4]], axis=0).max() == 0.0
    assert state.stopped == "the null motion q̇4 = −q̇6 moved the joints; the tool stood still"


def test_the_null_motion_is_refused_where_j_has_full_rank():
    state = LabState.initial("puma560", robots.load("puma560"))
    with pytest.raises(InvalidAction, match="full rank"):
        reduce(state, PlayNullMotion())


def test_the_planar_2r_stretched_null_motion_is_said_with_its_ratio_in_each_language():
    state = reduce(LabState.initial("planar2", robots.load("planar2")), SetConfiguration((0.4, 0.0)))
    null = compute(state).null
    assert null is not None
    assert null_motion_text(null.direction) == "q̇1 = −0.5 q̇2"  # Ker J = span (1, −2), by hand
    state = reduce(state, PlayNullMotion())
    while state.playing:
        state = reduce(state, Step(FRAME_DT))
    pl = say(state.stopped, translations("pl"))
    assert "−0,5" in pl and "q̇2" in pl and pl != state.stopped


def test_the_motion_tab_says_the_null_motion_and_its_button_plays_it(session):
    words = session.panel.motion.course.null
    assert words.button.disabled and "full rank" in words.words.content
    session.dispatch(SetConfiguration(wrist_singular()))
    session.settle()
    assert not words.button.disabled and "q̇4 = −q̇6" in words.words.content
    T0 = fk(session.state.robot, session.state.q)
    session.dispatch(PlayNullMotion())
    poll(lambda: session.state.motion.kind == "path")
    poll(lambda: not session.state.playing)
    state = session.state
    assert np.abs(fk(state.robot, state.q) - T0).max() < 1e-12
    assert state.stopped.startswith("the null motion q̇4 = −q̇6")
    assert math.isfinite(state.time) and state.time > 0


def test_the_null_motion_refusal_is_said_in_the_tab_language():
    """The refusal reaches the error notice through the catalogs (Polish), not in English."""
    from app.tab.notices import _said

    state = LabState.initial("puma560", robots.load("puma560"))  # J has full rank at home
    with pytest.raises(InvalidAction) as refused:
        reduce(state, PlayNullMotion())
    said = _said(refused.value, translations("pl"))
    assert said == "brak ruchu zerowego: J ma tu pełny rząd (najpierw przejdź do osobliwości)"
