"""Issue 29 item 5 in the app: the course's Jacobian IK along a path y(t) (Newton for q(t₀), then
q̇ = J⁺ẏ(t)), played back: the tool stays on the line or circle (fk), the rates chart gets q̇(t) equal to
J⁻¹ẏ, and near a singularity the method fails and says so."""

from __future__ import annotations

import numpy as np
import pytest

import robots
from app.core.actions import FollowToolPath, SetConfiguration, Step
from app.core.i18n import translations
from app.core.motion_rules import FRAME_DT
from app.core.reducer import InvalidAction, reduce
from app.core.refusals import say
from app.core.state import LabState
from app.core.tool_path import laid_out
from app.views.panel.live import live_html
from kinematics import fk, jacobian


def played(state: LabState) -> tuple[LabState, list[np.ndarray]]:
    seen = [np.array(state.q)]
    while state.playing:
        state = reduce(state, Step(FRAME_DT))
        seen.append(np.array(state.q))
    return state, seen


@pytest.mark.parametrize("shape", ["line", "circle"])
def test_the_planar_2r_follows_the_path_through_its_tool_point(shape):
    state = reduce(LabState.initial("planar2", robots.load("planar2")), SetConfiguration((0.3, 1.2)))
    path = laid_out(state, shape)
    assert np.allclose(path.point(0.0), fk(state.robot, state.q)[:3, 3], atol=1e-12)  # starts at the tool
    state = reduce(state, FollowToolPath(shape))
    assert "following the path y(t)" in live_html(reduce(state, Step(FRAME_DT)))
    state, seen = played(state)
    assert len(seen) == 121  # 4 s at 30 frames per second
    after = live_html(state)  # played out: not "stopped: following the path y(t)"
    assert "the path y(t) was followed to its end" in after and "following the path" not in after
    for k, q in enumerate(seen):
        assert np.linalg.norm(fk(state.robot, q)[:2, 3] - path.point(k * FRAME_DT)[:2]) < 1e-6
    # the charted rate (a finite difference of the played q) is J⁻¹ ẏ at the middle of the step
    trace = state.motion.trace
    k = 60
    qm = 0.5 * (seen[k] + seen[k - 1])
    expected = np.linalg.solve(jacobian(state.robot, qm)[:2], path.velocity((k - 0.5) * FRAME_DT)[:2])
    assert np.allclose(trace.qd[k], expected, rtol=1e-3, atol=1e-4)
    assert state.stopped.startswith(f"the tool followed the {shape}")


def test_near_the_stretch_the_circle_is_lost_and_the_words_say_why():
    state = reduce(LabState.initial("planar2", robots.load("planar2")), SetConfiguration((-0.1, 0.12)))
    state, seen = played(reduce(state, FollowToolPath("circle")))
    assert state.stopped.startswith("the tool left the circle near a singularity")
    away = reduce(LabState.initial("planar2", robots.load("planar2")), SetConfiguration((0.3, 1.2)))
    away, _ = played(reduce(away, FollowToolPath("circle")))
    assert away.stopped.startswith("the tool followed the circle")
    # the same circle's rates blow up near the stretch (J⁻¹ grows like 1/σmin)
    assert np.abs(state.motion.trace.qd).max() > 5.0 * np.abs(away.motion.trace.qd).max()
    pl = say(state.stopped, translations("pl"))
    assert "osobliwo" in pl and pl != state.stopped


def test_the_puma_follows_a_circle_with_the_pseudo_inverse():
    state = LabState.initial("puma560", robots.load("puma560"))
    path = laid_out(state, "circle")
    state, seen = played(reduce(state, FollowToolPath("circle")))
    for k, q in enumerate(seen):
        assert np.linalg.norm(fk(state.robot, q)[:3, 3] - path.point(k * FRAME_DT)) < 1e-6
    assert np.ptp(np.array(seen), axis=0).max() > 0.1


def test_a_shape_the_menu_does_not_offer_is_refused():
    state = LabState.initial("planar2", robots.load("planar2"))
    with pytest.raises(InvalidAction, match="shape must be one of line, circle"):
        reduce(state, FollowToolPath("spiral"))
