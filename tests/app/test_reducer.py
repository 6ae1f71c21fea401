"""The pure reducer: every action, on frozen states, without a server or a clock."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import robots
from app.core.actions import (
    ClearWrench,
    GoTo,
    Play,
    ReplaceState,
    SetConfiguration,
    SetDesired,
    SetJoint,
    SetOption,
    SetRate,
    SetRobot,
    SetWrench,
    Step,
    StopRates,
)
from app.core.commands import ChooseRobot, RequestDownload
from app.core.ranges import SNAP_DEGREES, joint_ranges, rate_ranges, twist_ranges
from app.core.reducer import InvalidAction, reduce
from app.core.state import LabState


@pytest.fixture(scope="module")
def puma():
    return robots.load("puma560")


@pytest.fixture
def state(puma):
    return LabState.initial("puma560", puma)


def test_state_is_frozen(state):
    with pytest.raises(ValueError):
        state.q[0] = 1.0  # read-only array
    with pytest.raises(dataclasses.FrozenInstanceError):
        state.q = np.zeros(6)  # type: ignore[misc]
    with pytest.raises(ValueError, match="finite"):
        state.replace(qd=np.full(6, np.nan))


def test_set_joint_returns_a_new_state_and_leaves_the_old_one(state):
    new = reduce(state, SetJoint(1, 0.3))
    assert new is not state
    assert new.q[1] == 0.3 and state.q[1] == pytest.approx(state.robot.home[1])
    assert new.configuration == "" and state.configuration == "home"
    np.testing.assert_array_equal(np.delete(new.q, 1), np.delete(state.q, 1))


def test_a_typed_value_beyond_the_slider_is_clamped_in_the_maths(state):
    r = joint_ranges(state.robot)[0]
    new = reduce(state, SetJoint(0, math.radians(r.hi + 50)))
    assert new.q[0] == pytest.approx(math.radians(r.hi))


def test_joint_snaps_onto_a_named_configuration(state, puma):
    """Arriving within the snapping tolerance of a named value the joint lands on it exactly (the name
    follows); fine steps away from it are kept."""
    near = math.radians(SNAP_DEGREES * 0.6)
    new = reduce(state, SetJoint(4, near))  # wrist_singular is home with q5 = 0
    assert new.q[4] == 0.0
    assert new.configuration == "wrist_singular"
    far = reduce(state, SetJoint(4, math.radians(SNAP_DEGREES * 2)))
    assert far.q[4] == pytest.approx(math.radians(SNAP_DEGREES * 2)) and far.configuration == ""
    leaving = reduce(new, SetJoint(4, math.radians(0.1)))  # a fine step off the singularity
    assert leaving.q[4] == pytest.approx(math.radians(0.1)) and leaving.configuration == ""
    back = reduce(leaving, SetJoint(4, 0.0))
    assert back.configuration == "wrist_singular"


def test_go_to_and_set_configuration(state, puma):
    new = reduce(state, GoTo("elbow_singular"))
    np.testing.assert_allclose(new.q, puma.configuration("elbow_singular"))
    assert new.configuration == "elbow_singular"
    back = reduce(new, SetConfiguration(tuple(puma.home)))
    assert back.configuration == "home"
    with pytest.raises(InvalidAction, match="no configuration 'nowhere'"):
        reduce(state, GoTo("nowhere"))
    with pytest.raises(InvalidAction, match="needs 6 joint values, got 2"):
        reduce(state, SetConfiguration((0.0, 1.0)))


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, "1e400", "abc", None, 1e400])
def test_nonfinite_and_nonnumeric_values_are_refused_with_the_input_named(state, bad):
    with pytest.raises(InvalidAction, match="joint q2 shoulder"):
        reduce(state, SetJoint(1, bad))
    with pytest.raises(InvalidAction, match="rate"):
        reduce(state, SetRate(0, bad))
    with pytest.raises(InvalidAction, match="tool velocity"):
        reduce(state, SetDesired(0, bad))
    with pytest.raises(InvalidAction, match="force"):
        reduce(state, SetWrench(0, bad))


@pytest.mark.parametrize("index", [-1, 6, 2.5, True, "1"])
def test_bad_indices_are_refused(state, index):
    with pytest.raises(InvalidAction, match="index"):
        reduce(state, SetJoint(index, 0.0))


def test_rates_desired_twist_and_wrench(state):
    s = reduce(state, SetRate(2, 0.5))
    s = reduce(s, SetDesired(0, 0.2))
    s = reduce(s, SetWrench(5, 3.0))
    assert s.qd[2] == 0.5 and s.v_desired[0] == 0.2 and s.wrench[5] == 3.0
    s = reduce(reduce(s, StopRates()), ClearWrench())
    assert not s.qd.any() and not s.wrench.any() and s.v_desired[0] == 0.2


def test_ranges_hold_the_course_trr_example():
    """The course's TRR numbers fit the inputs: q1 = 15 m, q̇1 = 0.5 m/s, v = 17.256 m/s."""
    trr = robots.load("trr")
    s = LabState.initial("trr", trr)
    s = reduce(s, SetJoint(0, 15.0))
    assert s.q[0] == 15.0
    s = reduce(s, SetRate(0, 0.5))
    assert s.qd[0] == 0.5
    s = reduce(s, SetDesired(0, 17.256))
    assert s.v_desired[0] == 17.256
    assert rate_ranges(trr)[1].hi == 180.0 and twist_ranges(trr)[0].hi >= 17.256


def test_options(state):
    s = reduce(state, SetOption("frames", True))
    assert s.options.frames and not state.options.frames
    assert reduce(state, SetOption("scale", 99.0)).options.scale == 3.0
    with pytest.raises(InvalidAction, match="unknown display option 'colour'"):
        reduce(state, SetOption("colour", True))
    with pytest.raises(InvalidAction, match="jacobian_frame must be one of"):
        reduce(state, SetOption("jacobian_frame", "world"))
    with pytest.raises(InvalidAction, match="on or off"):
        reduce(state, SetOption("frames", "yes"))
    with pytest.raises(InvalidAction, match="finite"):
        reduce(state, SetOption("damping", math.nan))


def test_robot_switch_keeps_display_choices_and_sets_glyphs_for_the_task(state):
    s = reduce(state, SetOption("scale", 2.0))
    s = reduce(s, SetOption("jacobian_frame", "tool"))
    wrist = robots.load("wrist")
    w = reduce(s, SetRobot("wrist", wrist))
    assert w.robot is wrist and w.configuration == "home"
    assert w.options.scale == 2.0 and w.options.jacobian_frame == "tool"
    # The wrist's task is orientation: rotational glyphs by default, translational ones off.
    assert w.options.rotational_ellipsoid and w.options.angular_columns
    assert not w.options.velocity_ellipsoid and not w.options.columns
    back = reduce(w, SetRobot("puma560", state.robot))
    assert back.options.velocity_ellipsoid and back.options.columns


def test_commands_are_not_reduced(state):
    for action in (ChooseRobot("panda"), RequestDownload("JSON")):
        with pytest.raises(InvalidAction, match="command"):
            reduce(state, action)


def test_replace_state(state):
    other = reduce(state, SetJoint(0, 0.1))
    assert reduce(state, ReplaceState(other)) is other


def test_time_moves_the_joints_at_their_rates_and_stops_at_the_slider_end(state):
    s = reduce(state, SetRate(0, 1.0))
    assert reduce(s, Step(0.1)) is s  # not playing: time does nothing
    s = reduce(s, Play(True))
    moved = reduce(s, Step(0.1))
    assert moved.q[0] == pytest.approx(s.q[0] + 0.1) and moved.time == pytest.approx(0.1)
    hi = math.radians(joint_ranges(state.robot)[0].hi)
    far = moved
    for _ in range(100):
        far = reduce(far, Step(0.1))
    assert far.q[0] == pytest.approx(hi) and not far.playing
    assert "q1 waist reached the end of its range" in far.stopped


def test_play_without_rates_says_why(state):
    s = reduce(state, Play(True))
    assert not s.playing and "joint rate" in s.stopped
