"""Server-level tests of the singularity explorer: the Motion and Maps tabs' handles dispatch actions,
the snapshot and scene follow, charts get finite data, and long work (the nearest singularity) runs off
the drawing thread. Each test starts from a fresh state of the default robot (the ``session`` fixture).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from app_helpers import assert_all_finite, scene_node
from fakes import poll

import robots
from app.core.actions import Play, SetOption, Step
from app.core.commands import ChooseRobot, FindSingularity
from app.core.motion_rules import FRAME_DT
from app.core.ranges import joint_ranges
from app.tab.ticker import Ticker
from app.views.panel.motion import OWN_TWIST
from kinematics import fk, jacobian
from kinematics.analysis import manipulability, singular_values, task_rows


def choose(session, name: str) -> None:
    session.dispatch(ChooseRobot(name))
    session.settle()
    assert session.state.robot_name == name


def test_a_preset_from_the_dropdown_then_play_moves_the_arm_and_feeds_the_charts(session, monkeypatch):
    motion = session.panel.motion
    name = robots.motions("puma560")[0].name
    assert motion.preset.value == name  # shown first; picked again after "your own v", as a user would
    motion.preset.value = OWN_TWIST
    motion.preset.value = name
    session.settle()
    state = session.state
    assert state.motion.preset == name and state.motion.kind == "resolved_rate"
    assert np.array(state.q) == pytest.approx(robots.motions("puma560")[0].q)
    # The test is the clock: the tab's ticker goes nowhere, steps are dispatched by hand.
    monkeypatch.setattr(session, "ticker", Ticker(lambda action: None))
    session.dispatch(Play(True, "resolved_rate"))
    for _ in range(40):
        session.dispatch(Step(FRAME_DT))
    session.settle()
    state = session.state
    assert state.time == pytest.approx(40 * FRAME_DT)
    # The tool moved along v for 40 frames; the chart holds the trace, all finite.
    p0 = fk(state.robot, robots.motions("puma560")[0].q)[:3, 3]
    assert fk(state.robot, state.q)[:3, 3] == pytest.approx(
        p0 + np.array(state.v_desired[:3]) * state.time,
        abs=2e-3,  # Euler steps' first-order error
    )
    # Paused, the charts hold the whole trace (while playing they follow every third frame).
    session.dispatch(Play(False))
    session.settle()
    assert not session.ticker.running
    t, sigma, w = motion.measures.data
    assert len(t) == 41 and np.isfinite(sigma).all() and np.isfinite(w).all()
    J = jacobian(state.robot, state.q)
    assert sigma[-1] == pytest.approx(singular_values(J, task_rows(state.robot))[-1])
    assert len(motion.rates.data) == 1 + state.robot.dof
    assert_all_finite(session)


def test_the_play_buttons_drive_the_ticker(session):
    motion = session.panel.motion
    # A fresh tab: the dropdown shows the first preset, not yet applied; Play applies it and runs it.
    first = robots.motions("puma560")[0]
    assert motion.preset.value == first.name and session.state.motion.preset == ""
    start = np.array(first.q)
    q_seen = []
    _click(motion.buttons, "Play")
    session.settle()
    assert session.state.playing and session.ticker.running
    poll(lambda: len(session.state.motion.trace) > 5)  # moving by itself on the tab's ticker
    q_seen.append(np.array(session.state.q))
    _click(motion.buttons, "Pause")
    session.settle()
    assert not session.state.playing and not session.ticker.running
    n = len(session.state.motion.trace)
    _click(motion.buttons, "Step")
    session.settle()
    assert len(session.state.motion.trace) == n + 1 and not session.state.playing
    _click(motion.buttons, "Reset")
    session.settle()
    assert np.array(session.state.q) == pytest.approx(start)
    assert motion.preset.value != OWN_TWIST


def _click(buttons, label: str) -> None:
    """A click on ``label``: viser sets the group's value and always runs its callbacks (a button)."""
    buttons.value = label


@pytest.mark.slow
def test_the_nearest_singularity_is_found_off_the_drawing_thread_and_played_back(session):
    assert session.snapshot.report.status == "regular"  # the Puma at home
    session.dispatch(FindSingularity())
    poll(lambda: session.state.motion.kind == "path")
    poll(lambda: not session.state.playing)
    state = session.state
    assert state.stopped.startswith("found:") and "singularity" in state.stopped
    J = jacobian(state.robot, state.q)
    sigma = singular_values(J, task_rows(state.robot))
    assert sigma[-1] / sigma[0] < 1e-6
    assert_all_finite(session)


def test_dragging_the_handle_moves_the_arm(session):
    session.panel.motion.gizmo.value = True
    session.settle()
    gizmo = scene_node(session, "/lab/drive/handle")
    assert gizmo.visible
    T0 = fk(session.state.robot, session.state.q)
    assert np.asarray(gizmo.position) == pytest.approx(T0[:3, 3], abs=1e-6)
    from app.core.actions import DriveTool

    T = T0.copy()
    T[:3, 3] += [0.05, -0.03, 0.02]
    session.dispatch(DriveTool(tuple(T.ravel())))
    session.settle()
    assert fk(session.state.robot, session.state.q)[:3, 3] == pytest.approx(T[:3, 3], abs=1e-6)
    assert "iterations" in session.panel.motion.ik.content


def test_the_ik_readout_counts_the_iterations_of_the_drag_not_of_its_release(session):
    """A drag ends with the handle's release at the pose already reached: the readout keeps the count of
    the solve that moved the arm (the same count as ik.solve from the same start), not "0 iterations"."""
    from app.core.actions import DriveTool
    from app.core.motion_rules import IK_DAMPING, IK_ITERATIONS, IK_STEP
    from kinematics.motion import ik

    session.panel.motion.gizmo.value = True
    session.settle()
    robot, q0 = session.state.robot, np.array(session.state.q)
    T = fk(robot, q0)
    T[:3, 3] += [0.08, -0.05, 0.04]
    expected = ik.solve(
        robot,
        T[:3, 3],
        q0,
        method="dls",
        damping=max(session.state.options.damping, IK_DAMPING),
        max_iterations=IK_ITERATIONS,
        step_limit=IK_STEP,
    ).iterations
    assert expected >= 2
    session.dispatch(DriveTool(tuple(T.ravel())))  # the drag's last update
    session.settle()
    session.dispatch(DriveTool(tuple(T.ravel())))  # the release, at the same pose
    session.settle()
    assert session.state.motion.ik.iterations == expected
    assert f"{expected} iterations" in session.panel.motion.ik.content
    assert "0 iterations" not in session.panel.motion.ik.content


def test_self_motion_slider_and_ghost_on_the_panda(session):
    choose(session, "panda")
    motion = session.panel.motion
    assert motion.self_slider is not None
    T0 = fk(session.state.robot, session.state.q)
    motion.self_slider.value = 0.5
    session.settle()
    state = session.state
    assert fk(state.robot, state.q)[:3, 3] == pytest.approx(T0[:3, 3], abs=1e-5)
    ghost = scene_node(session, "/lab/drive/ghost")
    assert ghost.visible and np.asarray(ghost.position) == pytest.approx(T0[:3, 3], abs=1e-6)
    s, w = motion.self_chart.data
    assert s[-1] == pytest.approx(0.5) and w[-1] == pytest.approx(
        float(manipulability(jacobian(state.robot, state.q), task_rows(state.robot)))
    )


def test_the_puma_has_no_redundancy_controls(session):
    assert session.panel.motion.self_slider is None


def test_joint_map_values_and_click_target(session):
    maps = session.panel.maps
    maps.show_map.value = True
    session.settle()
    snap = session.snapshot
    jm = snap.joint_map
    assert jm is not None and jm.w.shape == (48, 48)
    # A cell of the map is w of J with joints i, j set to that cell's values, the others held.
    k, m = 10, 37
    qi = np.radians(np.linspace(jm.lo[0], jm.hi[0], 48))[m]
    qj = np.radians(np.linspace(jm.lo[1], jm.hi[1], 48))[k]
    q = np.array(session.state.q)
    q[[jm.i, jm.j]] = qi, qj
    w = float(manipulability(jacobian(session.state.robot, q), task_rows(session.state.robot)))
    assert jm.w[k, m] == pytest.approx(w, rel=1e-9, abs=1e-12)
    html = maps.map.content
    assert 'class="jl-map"' in html and "data:image/png;base64," in html
    assert_all_finite(session)
    session.dispatch(SetOption("map_j", 4))
    session.settle()
    assert session.snapshot.joint_map.j == 4


def _spans(html: str, cls: str) -> list[str]:
    block = re.search(rf'<div class="{cls}">(.*?)</div>', html).group(1)
    return re.findall(r"<span>(.*?)</span>", block)


def test_the_joint_map_has_axes_with_joint_names_ticks_and_a_colour_bar_of_w(session):
    """Item 15: the map says which joint is on which axis (name and unit), the values at its ends and
    middle (the sliders' range, in degrees), and what its colours mean (a bar from w = 0 to w_max in
    the colours the cells are painted with)."""
    from app.core.snapshot.maps import colormap
    from app.views.panel.maps import COLOUR_STOPS

    maps = session.panel.maps
    maps.show_map.value = True
    session.settle()
    robot, jm = session.state.robot, session.snapshot.joint_map
    html = maps.map.content
    ranges = joint_ranges(robot)
    assert re.search(r'class="xlabel">q2 shoulder \[°\]<', html) and robot.joints[jm.i].name == "q2 shoulder"
    assert re.search(r'class="ylabel">q3 elbow \[°\]<', html) and robot.joints[jm.j].name == "q3 elbow"
    lo_i, hi_i = (math.degrees(ranges[jm.i].clamp_si(x)) for x in (-math.inf, math.inf))
    lo_j, hi_j = (math.degrees(ranges[jm.j].clamp_si(x)) for x in (-math.inf, math.inf))
    assert [float(t.replace("−", "-")) for t in _spans(html, "xticks")] == pytest.approx(
        [lo_i, (lo_i + hi_i) / 2, hi_i], abs=0.5
    )
    assert [float(t.replace("−", "-")) for t in _spans(html, "yticks")] == pytest.approx(
        [hi_j, (lo_j + hi_j) / 2, lo_j],
        abs=0.5,  # top to bottom: j grows upwards, as the cells
    )
    w_ticks = [float(t) for t in _spans(html, "wticks")]
    assert w_ticks == pytest.approx([jm.w_max, jm.w_max / 2, 0.0], rel=2e-3)
    assert jm.w_max == pytest.approx(float(jm.w.max()))
    # The bar's colours are the cells' colours at w = 0 … w_max.
    ends = colormap(np.array([0.0, 1.0]))
    assert COLOUR_STOPS[0] == "#{:02x}{:02x}{:02x}".format(*ends[0])
    assert COLOUR_STOPS[-1] == "#{:02x}{:02x}{:02x}".format(*ends[1])
    assert f"linear-gradient(to top, {', '.join(COLOUR_STOPS)})" in html
    assert 'class="jl-map" data-i=' in html  # the click target keeps its data


def test_the_workspace_cloud_has_a_legend_of_its_colours(session):
    from app.views.panel.maps import COLOUR_STOPS

    key = session.panel.maps.cloud_key
    assert key.content == ""
    session.panel.maps.cloud.value = True
    session.settle()
    cloud = session.snapshot.cloud
    assert "coloured by w" in key.content and "20\u2009000 random configurations" in key.content
    assert f"linear-gradient(to right, {', '.join(COLOUR_STOPS)})" in key.content
    shown = re.findall(r"<span>(.*?)</span>", key.content)
    assert shown[0] == "w = 0" and float(shown[1]) == pytest.approx(cloud.w_max, rel=2e-3)
    # both kinds of critical points (002): the singular ones and those on the joint-limit boundary
    assert "Critical points:" in key.content and "2 000 points with a joint at a limit" in key.content
    robot = session.state.robot
    lo, hi = robot.qlim
    assert cloud.limits == 2000 and (cloud.colors[-cloud.limits :] == (232, 89, 12)).all()
    assert (
        cloud.singular > 0
        and (cloud.colors[: -cloud.limits] == (230, 73, 128)).all(axis=1).sum() == cloud.singular
    )
    session.panel.maps.cloud.value = False
    session.settle()
    assert key.content == ""


def test_the_charts_y_axes_ask_for_ticks_every_14_px(session):
    """uPlot's default (a tick per 30 px at least) left one or two ticks on the 150 px charts: the y axes
    ask for one every 14 px (five on the Puma's joint-rate chart, 1280×720 screenshot), with labels."""
    motion = session.panel.motion
    for chart in (motion.rates, motion.kappa, motion.measures):
        x, y = chart.axes
        assert y["space"] == 14 and y["label"] and x["label"] == "t [s]"
    assert motion.rates.axes[1]["label"] == "q̇ [°/s]"


def test_workspace_cloud_is_drawn_from_tool_points(session):
    session.panel.maps.cloud.value = True
    session.settle()
    cloud = scene_node(session, "/lab/drive/cloud")
    points = np.asarray(cloud.points)
    assert points.shape == (20_000 + 2_000, 3) and np.isfinite(points).all()  # + the joint-limit points
    reach = np.linalg.norm(points - fk(session.state.robot, np.zeros(6))[:3, 3] * 0, axis=1).max()
    assert reach < 1.5  # the Puma reaches under a metre from its base
    session.panel.maps.cloud.value = False
    session.settle()
    assert not cloud.visible


def test_robot_switch_keeps_the_explorer_working(session):
    for name in ("trr", "planar3", "panda"):
        choose(session, name)
        assert session.panel.motion is not None and session.panel.maps is not None
        assert [p.name for p in robots.motions(name)] == list(session.panel.motion.presets)
    assert_all_finite(session)


def test_speed_is_clamped(session):
    session.dispatch(SetOption("speed", 50.0))
    session.settle()
    assert session.state.options.speed == 2.0
    assert math.isclose(session.panel.motion.speed.value, 2.0)
