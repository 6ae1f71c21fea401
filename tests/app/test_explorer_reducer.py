"""The singularity explorer's rules, reduced on a fake clock (no browser, no threads): resolved-rate
presets, Step and Reset, dragging the tool, self-motion and the manipulability climb.

Checked against independent values: the course's TRR numbers, straight lines, fk of the solution,
the tool pose held, w computed afresh from J."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import robots
from app.core.actions import (
    ApplyPreset,
    DriveTool,
    Play,
    ResetMotion,
    SelfMove,
    SetJoint,
    SetOption,
    Step,
    StepOnce,
)
from app.core.motion_rules import FRAME_DT, redundancy_rows
from app.core.reducer import InvalidAction, reduce
from app.core.state import LabState
from kinematics import fk, jacobian
from kinematics.analysis import manipulability, task_rows


def fresh(name: str) -> LabState:
    return LabState.initial(name, robots.load(name))


def preset(state: LabState, index: int = 0) -> LabState:
    p = robots.motions(state.robot_name)[index]
    return reduce(state, ApplyPreset(p.name, tuple(p.q), tuple(p.twist), p.frame, p.speed))


def run(state: LabState, frames: int) -> list[LabState]:
    states = [state]
    for _ in range(frames):
        state = reduce(state, Step(FRAME_DT))
        states.append(state)
        if not state.playing:
            break
    return states


def test_the_trr_preset_takes_the_courses_rates_at_its_example_configuration():
    """The course inverts its example: J⁻¹ (17.256, −20.13, 0.5) m/s = (0.5 m/s, π/2, π/4 rad/s)."""
    state = reduce(preset(fresh("trr")), StepOnce("resolved_rate"))
    assert not state.playing
    qd = state.motion.trace.qd[-1]
    assert qd == pytest.approx([0.5, math.pi / 2, math.pi / 4], abs=2e-3)  # the course rounds to 4 digits
    assert state.options.speed == pytest.approx(0.1)  # shown ten times slower
    # One step at speed 0.1 moves q by q̇ Δt/10.
    assert np.array(state.q) - robots.load("trr").configuration("home") == pytest.approx(qd * FRAME_DT * 0.1)


def test_the_puma_preset_moves_the_tool_in_a_straight_line_into_the_wrist_singularity():
    state = reduce(preset(fresh("puma560")), Play(True, "resolved_rate"))
    assert state.playing and state.motion.kind == "resolved_rate"
    puma = state.robot
    p0, R0 = fk(puma, state.q)[:3, 3], fk(puma, state.q)[:3, :3]
    v = np.array(state.v_desired[:3])
    states = run(state, 600)
    end = states[-1]
    assert not end.playing and end.stopped.startswith("stopped:")
    # The tool on the line p0 + v t, its orientation held, while the rates are moderate (to the
    # first-order error of Euler steps: under 2 mm over the 0.25 m travelled in 75 frames).
    assert len(states) > 80
    for s in states[1:75]:
        T = fk(puma, s.q)
        assert T[:3, 3] == pytest.approx(p0 + v * s.time, abs=2e-3)
        assert T[:3, :3] == pytest.approx(R0, abs=1e-2)
    # It ran into the wrist singularity: q5 near 0, σmin down, κ up, the wrist rates blown up.
    trace = end.motion.trace
    assert abs(end.q[4]) < math.radians(6)
    assert trace.sigma_min[-1] < 0.2 * trace.sigma_min[0]
    assert trace.kappa[-1] > 5 * trace.kappa[0]
    assert np.abs(trace.qd[-1, [3, 5]]).max() > 10 * np.abs(trace.qd[1, [3, 5]]).max()
    assert np.isfinite(trace.kappa).all() and np.isfinite(trace.qd).all()


@pytest.mark.parametrize("name", ["planar2", "planar3", "elbow3r", "panda"])
def test_stretch_presets_stop_at_the_boundary_and_say_why(name):
    state = reduce(preset(fresh(name)), Play(True, "resolved_rate"))
    end = run(state, 900)[-1]
    assert not end.playing
    assert "stopped:" in end.stopped
    trace = end.motion.trace
    assert trace.sigma_min[-1] < 0.3 * trace.sigma_min[0]


def test_step_reset_and_play_without_a_twist():
    state = fresh("puma560")
    refused = reduce(state, Play(True, "resolved_rate"))
    assert not refused.playing and "tool velocity" in refused.stopped
    state = preset(state)
    start = np.array(state.q)
    stepped = reduce(reduce(state, StepOnce("resolved_rate")), StepOnce("resolved_rate"))
    assert len(stepped.motion.trace) == 3 and not stepped.playing
    rows = list(task_rows(state.robot))
    # Two Euler steps of q̇ = J⁻¹ v, done here independently.
    q = start.copy()
    for _ in range(2):
        q = q + FRAME_DT * np.linalg.solve(jacobian(state.robot, q)[rows], np.array(state.v_desired)[rows])
    assert np.array(stepped.q) == pytest.approx(q, abs=1e-12)
    back = reduce(stepped, ResetMotion())
    assert np.array(back.q) == pytest.approx(start) and back.motion.trace is None and back.time == 0.0


def test_a_tool_twist_in_tool_axes_is_held_in_the_moving_tool_frame():
    state = reduce(preset(fresh("puma560")), SetOption("twist_frame", "tool"))
    after = reduce(state, StepOnce("resolved_rate"))
    R = fk(state.robot, state.q)[:3, :3]
    dp = fk(state.robot, after.q)[:3, 3] - fk(state.robot, state.q)[:3, 3]
    assert dp == pytest.approx(R @ np.array(state.v_desired[:3]) * FRAME_DT, abs=1e-5)


def test_dragging_the_tool_solves_ik_to_the_target():
    state = fresh("puma560")
    robot = state.robot
    q_goal = np.array(state.q) + np.radians([8, -6, 5, 10, -7, 4])
    T = fk(robot, q_goal)
    state = reduce(state, SetOption("gizmo", True))
    for mode in ("position", "pose"):
        s = reduce(reduce(state, SetOption("ik_mode", mode)), DriveTool(tuple(T.ravel())))
        got = fk(robot, s.q)
        assert got[:3, 3] == pytest.approx(T[:3, 3], abs=1e-6)
        if mode == "pose":
            assert got[:3, :3] == pytest.approx(T[:3, :3], abs=1e-6)
        assert s.motion.ik.converged and s.motion.ik.departure < 1e-6


def test_an_unreachable_target_leaves_the_tool_short_and_finite():
    state = reduce(fresh("planar2"), SetOption("gizmo", True))
    T = np.eye(4)
    T[:3, 3] = [5.0, 5.0, 0.0]  # far beyond the 2 m reach
    for method in ("dls", "newton"):
        s = reduce(reduce(state, SetOption("ik_method", method)), DriveTool(tuple(T.ravel())))
        assert np.isfinite(s.q).all()
        ik = s.motion.ik
        assert not ik.converged and ik.departure > 1.0
        reach = np.linalg.norm(fk(s.robot, s.q)[:2, 3])
        assert reach == pytest.approx(2.0, abs=0.05)  # stretched towards it
    with pytest.raises(InvalidAction, match="16 finite numbers"):
        reduce(state, DriveTool((math.nan,) * 16))


@pytest.mark.parametrize("name", ["panda", "iiwa14", "planar3"])
def test_self_motion_moves_the_arm_with_the_tool_held(name):
    state = fresh(name)
    rows = list(redundancy_rows(state.robot))
    T0 = fk(state.robot, state.q)
    s = state
    for value in (0.1, 0.3, 0.6, 0.2):
        s = reduce(s, SelfMove(value))
        e = fk(s.robot, s.q)
        err = np.r_[e[:3, 3] - T0[:3, 3], 0.5 * np.cross(T0[:3, :3].T[0], e[:3, :3].T[0])]
        assert np.abs(e[:3, 3] - T0[:3, 3])[[r for r in rows if r < 3]].max() < 1e-5, err
        if any(r >= 3 for r in rows):
            assert e[:3, :3] == pytest.approx(T0[:3, :3], abs=1e-5)
    assert np.linalg.norm(np.array(s.q) - state.q) > 0.05  # the elbow moved
    assert s.motion.anchor is not None and len(s.motion.self_trace) == 5
    # w along the way is the manipulability of J at the configuration reached.
    assert s.motion.self_trace[-1, 1] == pytest.approx(
        float(manipulability(jacobian(s.robot, s.q), tuple(rows)))
    )
    # Moving a joint by hand starts a new self-motion (the ghost goes).
    moved = reduce(s, SetJoint(0, float(s.q[0]) + 0.1))
    assert moved.motion.anchor is None and moved.motion.s == 0.0


def test_self_motion_is_refused_without_redundancy():
    with pytest.raises(InvalidAction, match="no self-motion"):
        reduce(fresh("puma560"), SelfMove(0.2))


@pytest.mark.parametrize("name", ["panda", "planar3"])
def test_the_climb_raises_w_with_the_tool_held(name):
    state = reduce(fresh(name), SelfMove(0.8))  # off the symmetric home, where w is already highest
    rows = tuple(redundancy_rows(state.robot))
    T0 = fk(state.robot, state.q)
    state = reduce(state, Play(True, "climb"))
    states = run(state, 3000)
    ws = [float(manipulability(jacobian(s.robot, s.q), rows)) for s in states]
    assert all(b >= a - 1e-12 for a, b in zip(ws, ws[1:], strict=False))
    assert ws[-1] > ws[0]
    end_state = states[-1]
    assert "maximum" in end_state.stopped
    # A local maximum along the self-motion (the climb slows as ∇w → 0 and stops when a step
    # gains less than 1e-6 of w): a small self-motion either way gains less than 1e-4 of w.
    for ds in (-0.05, 0.05):
        nearby = reduce(end_state, SelfMove(end_state.motion.s + ds))
        assert float(manipulability(jacobian(nearby.robot, nearby.q), rows)) <= ws[-1] * (1 + 1e-4)
    end = fk(states[-1].robot, states[-1].q)
    assert end[:3, 3][[r for r in rows if r < 3]] == pytest.approx(
        T0[:3, 3][[r for r in rows if r < 3]], abs=1e-5
    )


def test_after_a_climb_the_self_motion_reads_where_the_climb_went():
    """The climb moves along the self-motion curve: s grows by the joint-space length climbed, the (s, w)
    chart holds the climb's points (not the old ones), and sliding s back to 0 returns to the start."""
    start = reduce(fresh("planar3"), SelfMove(0.8))
    rows = tuple(redundancy_rows(start.robot))
    climbing = reduce(start, Play(True, "climb"))
    states = run(climbing, 3000)
    end = states[-1]
    qs = np.array([start.q] + [s.q for s in states])
    climbed = float(np.linalg.norm(np.diff(qs, axis=0), axis=1).sum())
    assert end.motion.s == pytest.approx(climbed, rel=1e-9) and end.motion.s > 0.05
    s, w = end.motion.self_trace[-1]
    assert s == end.motion.s and w == pytest.approx(float(manipulability(jacobian(end.robot, end.q), rows)))
    assert end.motion.self_trace[0][0] == 0.0 and len(end.motion.self_trace) == len(states)  # start + steps
    back = reduce(end, SelfMove(0.0))
    np.testing.assert_allclose(back.q, start.q, atol=2e-3)
    assert "w of the held rows (vx, vy)" in end.stopped


@pytest.mark.parametrize(("name", "named"), [("planar3", True), ("panda", False)])
def test_the_readout_says_which_rows_the_climb_measures(name, named):
    """Issue 21, item 5: the 3R planar arm climbs w of the rows it holds (vx, vy) while the banner's κ
    is of all its task rows (vx, vy, ωz); the readout's κ is the climb's, labelled with its rows. The
    Panda holds all its task rows: nothing to say."""
    from app.views.panel.live import live_html
    from kinematics.analysis import condition_number

    start = reduce(fresh(name), SelfMove(0.8))
    end = run(reduce(start, Play(True, "climb")), 400)[-1]
    html = live_html(end)
    rows = tuple(redundancy_rows(end.robot))
    assert (rows != task_rows(end.robot)) == named
    label = "κ<small>(v<sub>x</sub>, v<sub>y</sub>)</small>"
    assert (label in html) == named, html
    shown = re.search(r"κ(?:<small>.*?</small>)? <b>([0-9.]+)</b>", html)
    assert shown is not None, html
    assert float(shown.group(1)) == pytest.approx(
        condition_number(jacobian(end.robot, end.q), rows), rel=5e-3
    )
