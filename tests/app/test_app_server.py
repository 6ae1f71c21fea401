"""Server-level tests of the browser app: dispatch actions or set handles, check snapshots and scene nodes.

One lab (viser server on a free port) and one headless websocket client
serve the module; every test starts from a fresh state (a ReplaceState of
the default robot at home), so the tests stand alone in any order. Every
message the client received is finally scanned for non-finite numbers and
"nan"/"inf" text.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from app_helpers import assert_all_finite, scene_node
from fakes import poll

import robots
from app.core.actions import GoTo, SetDesired, SetJoint, SetOption, SetRate, SetWrench
from app.core.commands import ChooseRobot
from app.core.ranges import joint_ranges, to_display
from app.views import fmt
from app.views.palette import LOST_RGB, joint_color
from app.views.scene.geometry import TINY, wxyz, wxyz_one
from app.views.scene.labels import label_anchor
from app.views.scene.overlays import LINEAR_SECONDS
from app.viser_adapter import is_removed
from kinematics import jacobian, joint_frames, link_frames
from kinematics.analysis import task_rows


def singular_configurations():
    out = []
    for name in robots.names():
        for conf in robots.load(name).configurations:
            if conf.singular:
                out.append(pytest.param(name, conf.name, id=f"{name}-{conf.name}"))
    return out


def test_default_robot_is_drawn_and_read_out(session):
    assert session.state.robot_name == "puma560"
    assert len(session.panel.joints.sliders) == 6
    assert "regular" in session.panel.status.content
    assert scene_node(session, "/lab/jacobian/velocity_ellipsoid").visible
    assert scene_node(session, "/lab/arm/cylinders") is not None
    assert_all_finite(session)


def test_slider_change_is_one_redraw_with_the_new_jacobian(session):
    slider = session.panel.joints.sliders[1]
    cylinders = scene_node(session, "/lab/arm/cylinders")
    positions = np.array(cylinders.batched_positions)
    matrix = session.panel.matrix.numeric.content
    before = session.redraws
    slider.value = 30.0  # as if the user typed 30 in the box
    session.settle()
    assert session.redraws == before + 1
    assert session.state.q[1] == pytest.approx(math.radians(30.0))
    J = jacobian(session.state.robot, session.state.q)
    np.testing.assert_allclose(session.snapshot.J_base, J)
    assert not np.allclose(cylinders.batched_positions, positions)
    assert session.panel.matrix.numeric.content != matrix
    assert fmt.fixed(J[0, 0]) in session.panel.matrix.numeric.content
    assert_all_finite(session)


def _chain_points(robot, q) -> np.ndarray:
    """The drawn chain, worked out directly: frame 0; per axis its origin, its corners, its link frame; the tool."""
    L, W = link_frames(robot, q), joint_frames(robot, q)
    pts = [L[0, :3, 3]]
    for k, ax in enumerate(robot.axes):
        pts.append(W[k, :3, 3])
        moved = L[k + 1] @ np.linalg.inv(ax.T_joint_child)
        pts += [(moved @ np.append(c, 1.0))[:3] for c in np.asarray(ax.corners, float).reshape(-1, 3)]
        pts.append(L[k + 1, :3, 3])
    pts.append(L[-1, :3, 3])
    return np.array(pts)


@pytest.mark.parametrize("robot_name", ["puma560", "panda"])
def test_links_axes_and_labels_are_where_the_kinematics_puts_them(session, robot_name):
    """One batched node holds every link and revolute axis: its instances sit on the chain's points."""
    session.dispatch(ChooseRobot(robot_name))
    session.settle()
    session.dispatch(SetJoint(1, 0.7))
    session.settle()
    robot, q = session.state.robot, session.state.q
    pts = _chain_points(robot, q)
    W = joint_frames(robot, q)
    cylinders = scene_node(session, "/lab/arm/cylinders")
    n_links = len(pts) - 1
    positions = np.asarray(cylinders.batched_positions).reshape(-1, 3)
    np.testing.assert_allclose(positions[:n_links], (pts[:-1] + pts[1:]) / 2, atol=1e-5)
    lengths = np.asarray(cylinders.batched_scales).reshape(-1, 3)[:n_links, 2]
    np.testing.assert_allclose(
        lengths, np.maximum(np.linalg.norm(np.diff(pts, axis=0), axis=1), TINY), atol=1e-5
    )
    revolute = [k for k, ax in enumerate(robot.axes) if ax.kind == "revolute"]
    np.testing.assert_allclose(positions[n_links:], W[revolute, :3, 3], atol=1e-5)  # axes centred on joints
    size = session.scene.size
    for j, label in enumerate(session.scene.arm.labels):
        k = next(k for k, ax in enumerate(robot.axes) if ax.joint_index == j)
        beyond = 0.17 * size * (1.0 + 0.1 * k) / 2 + 0.02 * size
        # Its anchor: the label itself is moved along the screen off another's box (the Panda's q1 and q2
        # share a point), which tests/app/test_screen_labels.py checks.
        np.testing.assert_allclose(label_anchor(label), W[k, :3, 3] + W[k, :3, 2] * beyond, atol=1e-5)


def test_column_arrows_travel_with_their_joint_colours(lab_client, session):
    """The arrows' points and colours reach the browser in one message: its arrow meshes take
    per-instance colours only when the colour array matches the instance count, so a colour
    message ahead of a points message of a new length left arrows uncoloured."""
    _, _, ws = lab_client
    mark = ws.mark()
    session.dispatch(ChooseRobot("panda"))  # a new arrows node: its first columns and colours
    session.settle()
    session.dispatch(SetJoint(3, -1.0))
    session.settle()
    J = session.snapshot.J_base
    node = scene_node(session, "/lab/jacobian/columns")
    lengths = np.linalg.norm(J[:3].T * LINEAR_SECONDS * session.state.options.scale, axis=1)
    drawn = np.flatnonzero(lengths > max(1e-3, session.scene.overlays.columns.radius))
    points = np.asarray(node.points).reshape(-1, 2, 3)
    assert len(points) == len(drawn)
    np.testing.assert_allclose(points[:, 1] - points[:, 0], (J[:3].T * LINEAR_SECONDS)[drawn], atol=1e-5)
    expected = np.array([joint_color(int(i)) for i in drawn], np.uint8)
    np.testing.assert_array_equal(np.asarray(node.colors).reshape(-1, 3), expected)
    _, message = ws.wait_for(
        lambda m: (
            m.get("name") == "/lab/jacobian/columns"
            and m["type"] == "SceneNodeUpdateMessage"
            and "colors" in m["updates"]
        ),
        after=mark,
    )
    assert "points" in message["updates"]  # in the same message as the colours
    assert len(message["updates"]["points"]) == 6 * len(message["updates"]["colors"]) // 3


def test_one_quaternion_is_the_batched_one_up_to_sign():
    rng = np.random.default_rng(7)
    samples = [np.eye(3), np.diag([1.0, -1.0, -1.0]), np.diag([-1.0, 1.0, -1.0]), np.diag([-1.0, -1.0, 1.0])]
    samples += [np.linalg.qr(rng.normal(size=(3, 3)))[0] for _ in range(200)]
    for R in samples:
        R = R * np.sign(np.linalg.det(R))  # a rotation
        a, b = wxyz(R), np.array(wxyz_one(R))
        assert min(np.abs(a - b).max(), np.abs(a + b).max()) < 1e-12
    assert wxyz_one(np.full((3, 3), np.nan)) == (1.0, 0.0, 0.0, 0.0)


def test_a_burst_of_actions_is_coalesced_into_few_redraws(session):
    """Actions that arrive while the tab is busy are queued and reduced together: the last value wins."""
    before = session.redraws
    with session.lock:  # hold the tab as a long redraw would
        session.dispatch(SetJoint(0, 0.5))
        poll(lambda: session.queued == 0)  # the renderer took it and waits for the lock
        for k in range(200):
            session.dispatch(SetJoint(0, 0.001 * k))  # returns at once: queued for the next visit
        assert session.queued == 200 and session.pending
    session.settle()
    assert session.state.q[0] == pytest.approx(0.199)
    assert session.redraws - before <= 2


def test_typed_value_beyond_the_slider_is_clamped_in_box_and_maths(session):
    r = joint_ranges(session.state.robot)[0]
    slider = session.panel.joints.sliders[0]
    slider.value = r.hi + 100.0
    session.settle()
    assert session.state.q[0] == pytest.approx(math.radians(r.hi))
    assert slider.value == pytest.approx(r.hi)


def test_configuration_menu_moves_every_slider_with_one_redraw(session):
    robot = session.state.robot
    before = session.redraws
    session.panel.joints.configuration.value = "elbow singular (singular)"
    session.settle()
    assert session.redraws == before + 1
    np.testing.assert_allclose(session.state.q, robot.configuration("elbow_singular"))
    for slider, r, q in zip(session.panel.joints.sliders, joint_ranges(robot), session.state.q, strict=True):
        assert slider.value == pytest.approx(to_display(r, q), abs=1e-6)
    description = robot.configurations[
        [c.name for c in robot.configurations].index("elbow_singular")
    ].description
    assert fmt.escape(description[:30]) in session.panel.status.content
    # Moving a joint away says so in the menu.
    session.panel.joints.sliders[0].value = 40.0
    session.settle()
    assert session.panel.joints.configuration.value == "— (moved)"


def test_slider_lands_exactly_on_a_singularity(session):
    """The wrist bend typed as 0.4° snaps to 0: the arm is exactly at its wrist singularity."""
    session.panel.joints.sliders[4].value = 0.4
    session.settle()
    assert session.state.q[4] == 0.0
    assert session.snapshot.report.status == "singular" and session.state.configuration == "wrist_singular"


@pytest.mark.parametrize(("robot_name", "conf_name"), singular_configurations())
def test_singular_configurations_are_drawn_and_read_out(session, robot_name, conf_name):
    session.dispatch(ChooseRobot(robot_name))
    session.dispatch(GoTo(conf_name))
    session.settle()
    assert session.state.robot_name == robot_name and session.state.configuration == conf_name
    snap = session.snapshot
    report = snap.report
    assert report.status == "singular", report.text()
    assert math.isinf(report.condition)
    assert snap.rank < min(len(snap.rows), session.state.robot.dof)
    status = session.panel.status.content
    assert "singular: " in status and "∞" in status
    assert all(kind in status for kind in report.kinds)  # what the geometry finds, and the file's word:
    word = next(c.singular for c in session.state.robot.configurations if c.name == conf_name)
    assert word in status
    assert "∞" in session.panel.matrix.measures.content
    if snap.det is not None:
        assert abs(snap.det) < 1e-9
    # Every lost direction is drawn as what it is (tests/test_singularity_picture.py checks where).
    planar = session.state.robot.planar
    arrow = scene_node(session, "/lab/jacobian/lost_translation")
    axis = scene_node(session, "/lab/jacobian/lost_rotation")
    moved = [x for x in snap.losses if x.translation_share >= 0.1 or (planar and x.translation_share > 0)]
    turned = [x for x in snap.losses if x.rotation_share >= 0.1 and not planar]
    assert snap.losses and arrow.visible == bool(moved) and axis.visible == bool(turned)
    if arrow.visible:
        points = np.array(arrow.points)
        assert len(points) == len(moved)
        for (start, end), loss in zip(points, moved, strict=True):
            assert (end - start) @ loss.translation == pytest.approx(np.linalg.norm(end - start), rel=1e-4)
        assert tuple(arrow.colors[0]) == LOST_RGB
    assert "Measured at the tool point" in status or "Decoupled at the wrist centre" in status
    # The ellipsoid flattens but never disappears, and nothing non-finite reaches the scene.
    rows = task_rows(session.state.robot)
    ellipsoid = scene_node(session, "/lab/jacobian/velocity_ellipsoid")
    rotational = scene_node(session, "/lab/jacobian/rotational_ellipsoid")
    blocks = [scene_node(session, f"/lab/jacobian/{part}_ellipsoid") for part in ("arm", "wrist")]
    shown = next((e for e in (ellipsoid, rotational, *blocks) if e.visible), ellipsoid)
    assert shown.visible, rows
    scale = np.asarray(shown.scale)
    assert np.isfinite(scale).all() and scale.min() >= TINY * 0.999
    session.dispatch(SetOption("force_ellipsoid", True))
    session.settle()
    force = np.asarray(scene_node(session, "/lab/jacobian/force_ellipsoid").scale)
    assert np.isfinite(force).all() and scene_node(session, "/lab/jacobian/force_ellipsoid").visible
    assert_all_finite(session)


def test_wrist_singularity_of_the_puma_is_a_lost_rotation_axis_at_the_wrist_centre(session):
    """Decoupled at the wrist centre, the Puma's q5 = 0 loses one rotation and nothing else."""
    session.dispatch(GoTo("wrist_singular"))
    session.settle()
    (loss,) = session.snapshot.losses
    assert loss.part == "wrist" and loss.translation_share == 0.0
    z4 = session.snapshot.joint_frames[3, :3, 2]
    z5 = session.snapshot.joint_frames[4, :3, 2]
    # The wrist cannot turn about the axis normal to the aligned z4 = z6 and z5: the lost rotation is along it.
    normal = np.cross(z4, z5) / np.linalg.norm(np.cross(z4, z5))
    assert abs(loss.rotation @ normal) > 1 - 1e-9
    assert scene_node(session, "/lab/jacobian/lost_rotation").visible
    assert not scene_node(session, "/lab/jacobian/lost_translation").visible


def test_robot_switch_rebuilds_scene_and_panel(session):
    old_slider = session.panel.joints.sliders[0]
    session.panel.robot.value = "planar2"
    session.settle()
    assert session.state.robot.dof == 2
    assert len(session.panel.joints.sliders) == 2
    assert is_removed(old_slider)
    assert len(np.asarray(scene_node(session, "/lab/jacobian/columns").points)) == 2
    assert "v<sub>z</sub>" in session.panel.matrix.numeric.content
    session.panel.joints.sliders[1].value = 0.3  # snaps to the stretched singularity at 0
    session.settle()
    assert session.snapshot.report.status == "singular"
    assert_all_finite(session)


def test_wrist_robot_shows_rotational_glyphs(session):
    session.dispatch(ChooseRobot("wrist"))
    session.settle()
    assert scene_node(session, "/lab/jacobian/rotational_ellipsoid").visible
    assert scene_node(session, "/lab/jacobian/angular_columns").visible
    assert not scene_node(session, "/lab/jacobian/velocity_ellipsoid").visible
    assert not scene_node(session, "/lab/jacobian/columns").visible
    assert session.panel.toggles["rotational_ellipsoid"].value


def test_every_library_robot_loads_at_home(session):
    for name in robots.names():
        session.panel.robot.value = name
        session.settle()
        assert session.state.robot_name == name
        assert session.errors == 0
        assert_all_finite(session)


def test_rates_twist_and_torques(session):
    J = session.snapshot.J_base
    qd = np.array([0.2, -0.1, 0.3, 0.0, 0.1, 0.0])
    for i, x in enumerate(qd):
        session.dispatch(SetRate(i, x))
    F = np.array([1.0, 2.0, -3.0, 0.5, 0.0, 1.0])
    for r, x in enumerate(F):
        session.dispatch(SetWrench(r, x))
    session.settle()
    np.testing.assert_allclose(session.snapshot.twist, J @ qd, atol=1e-12)
    np.testing.assert_allclose(session.snapshot.torques, J.T @ F, atol=1e-12)
    assert fmt.number(float((J @ qd)[0])) in session.panel.forward.twist.content
    assert "N·m" in session.panel.force.torques.content
    motion = scene_node(session, "/lab/jacobian/twist_and_force")
    assert motion.visible and len(np.asarray(motion.points)) == 4  # v, ω, force, moment (no desired v)


def test_pseudo_inverse_at_a_singularity_says_what_is_lost(session):
    """At the exact singularity J⁺ drops the lost direction: the panel shows J q̇ and v − J q̇."""
    session.dispatch(ChooseRobot("planar2"))
    session.dispatch(GoTo("stretched"))
    session.dispatch(SetDesired(0, 0.3))  # along the stretched arm: exactly the lost direction
    session.dispatch(SetDesired(1, 0.2))
    session.settle()
    snap = session.snapshot
    J = snap.J_base[list(snap.rows)]
    np.testing.assert_allclose(snap.produced[list(snap.rows)], J @ snap.rates, atol=1e-12)
    np.testing.assert_allclose(snap.shortfall[:2], [0.3, 0.0], atol=1e-9)  # the radial part is lost
    result = session.panel.inverse.result.content
    assert "v − J q̇" in result and "not produced" in result and "singular" in result
    # Damping: bounded rates, and the price is visible as a shortfall too.
    session.dispatch(GoTo("home"))
    session.dispatch(SetOption("damping", 0.2))
    session.settle()
    assert np.linalg.norm(session.snapshot.shortfall) > 1e-3
    assert "damping trades accuracy" in session.panel.inverse.result.content


def test_joint_rates_blow_up_near_a_singularity(session):
    session.dispatch(GoTo("wrist_singular"))
    session.dispatch(SetJoint(4, math.radians(2.0)))
    session.dispatch(SetDesired(3, 0.5))
    session.dispatch(SetDesired(4, 0.5))
    session.settle()
    assert session.snapshot.report.status == "near singular"
    assert np.abs(session.snapshot.rates).max() > math.radians(180.0)
    assert "jl-bar over" in session.panel.inverse.rates.content
    session.dispatch(SetOption("damping", 0.1))
    session.settle()
    assert np.abs(session.snapshot.rates).max() < np.abs(session.state.v_desired).sum() / (2 * 0.1) + 1e-9
    assert_all_finite(session)


def test_no_float_noise_reaches_the_readouts(session):
    """Rates that are round-off next to large ones read 0, not −5×10⁻¹² °/s."""
    session.dispatch(SetDesired(0, 0.1))
    session.settle()
    content = session.panel.inverse.rates.content
    assert "×10⁻¹" not in content and "×10⁻⁹" not in content


def test_options_toggle_nodes(session):
    session.panel.toggles["frames"].value = True
    session.settle()
    assert scene_node(session, "/lab/arm/frames").visible
    session.panel.toggles["columns"].value = False
    session.settle()
    assert not scene_node(session, "/lab/jacobian/columns").visible
    session.panel.scale.value = 2.0
    session.settle()
    assert session.state.options.scale == 2.0
    session.panel.matrix.frame.value = "tool"
    session.settle()
    J_tool = jacobian(session.state.robot, session.state.q, "tool")
    np.testing.assert_allclose(session.snapshot.J_shown, J_tool)
    assert "tool axes" in session.panel.matrix.numeric.content


def test_matrix_headers_are_short_with_names_on_hover(session):
    content = session.panel.matrix.numeric.content
    for i, joint in enumerate(session.state.robot.joints):
        assert f">q{i + 1}</th>" in content and f'title="{fmt.escape(joint.name)}"' in content


def test_enlarged_matrix_follows_the_sliders_and_closes(session):
    session.panel.matrix.open_large()
    big = session.panel.matrix._modal_html
    assert big is not None and "jl-big" in big.content and "jl-close-x" in big.content
    session.panel.joints.sliders[0].value = 20.0
    session.settle()
    assert fmt.fixed(session.snapshot.J_shown[0, 0]) in big.content
    session.panel.matrix.close_large()
    assert not session.panel.matrix.enlarged
