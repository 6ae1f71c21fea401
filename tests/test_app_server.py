"""Server-level tests of the browser app: set inputs through the handles, check scene handles and readouts.

One lab (viser server on a free port) and one headless websocket client
serve the whole module; every message the client receives is finally
scanned for non-finite numbers and "nan"/"inf" text.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
import viser
from app_helpers import gui_contents, nonfinite_paths, running_lab, scene_props, wait_until

import robots
from app import fmt
from app.panel.joints import from_slider
from app.scene.geometry import TINY
from app.wsclient import ViserWsClient
from kinematics import jacobian
from kinematics.analysis import task_rows


@pytest.fixture(scope="module")
def lab_client():
    with running_lab() as (lab, session, ws):
        yield lab, session, ws


@pytest.fixture
def session(lab_client):
    """The module's session, back on the default robot at home with nothing applied."""
    lab, session, _ = lab_client
    with session.lock:
        session.set_robot(lab.default_robot)
        session.go_to("home")
        session.stop_rates()
        session.clear_wrench()
        session.state.v_desired[:] = 0
        session.set_option(
            frames=False,
            force_ellipsoid=False,
            rotational_ellipsoid=False,
            jacobian_frame="base",
            damping=0.0,
        )
    return session


def assert_all_finite(session) -> None:
    bad = nonfinite_paths(scene_props(session)) + nonfinite_paths(gui_contents(session))
    assert not bad, bad


def singular_configurations():
    out = []
    for name in robots.names():
        for conf in robots.load(name).configurations:
            if conf.singular:
                out.append(pytest.param(name, conf.name, id=f"{name}-{conf.name}"))
    return out


# ------------------------------------------------------------------ formatting
def test_numbers_are_formatted_for_humans():
    assert fmt.number(math.inf) == "∞"
    assert fmt.number(-math.inf) == "−∞"
    assert fmt.number(math.nan) == "—"
    assert fmt.number(0.0786123) == "0.0786"
    assert fmt.number(-12.345) == "−12.3"
    assert fmt.number(12345.0) == "12300" or fmt.number(12345.0) == "12345"
    assert fmt.number(2.5e7) == "2.5×10⁷"
    assert fmt.number(1e-15) == "0"
    assert fmt.quantity(3.0, "m/s") == "3\u2009m/s"
    assert fmt.quantity(90.0, "°/s") == "90°/s"
    assert fmt.fixed(-0.0001) == "0"
    assert fmt.fixed(-0.7071) == "−0.707"


# ------------------------------------------------------------------ the session
def test_default_robot_is_drawn_and_read_out(session):
    assert session.state.robot_name == "puma560"
    assert len(session.panel.joints.sliders) == 6
    assert "regular" in session.panel.status.content
    names = scene_props(session)
    assert "/lab/arm/cylinders" in names and "/lab/jacobian/velocity_ellipsoid" in names
    assert session.client.scene._handle_from_node_name["/lab/jacobian/velocity_ellipsoid"].visible
    assert_all_finite(session)


def test_slider_change_updates_scene_and_readouts_once(session):
    slider = session.panel.joints.sliders[1]
    before = session.refreshes
    positions = session.scene.arm.cylinders.batched_positions.copy()
    matrix = session.panel.matrix.numeric.content
    slider.value = 30.0  # as the browser would: callbacks run
    assert session.refreshes == before + 1
    assert session.state.q[1] == pytest.approx(math.radians(30.0))
    J = jacobian(session.state.robot, session.state.q)
    np.testing.assert_allclose(session.snapshot.J_base, J)
    assert not np.allclose(session.scene.arm.cylinders.batched_positions, positions)
    assert session.panel.matrix.numeric.content != matrix
    assert fmt.fixed(J[0, 0]) in session.panel.matrix.numeric.content
    assert_all_finite(session)


def test_configuration_button_moves_every_slider_with_one_redraw(session):
    robot = session.state.robot
    name = next(c.name for c in robot.configurations if c.singular)
    before = session.refreshes
    session.panel.joints.buttons[name].value = True  # a click
    assert session.refreshes == before + 1
    np.testing.assert_allclose(session.state.q, robot.configuration(name))
    for slider, joint, q in zip(
        session.panel.joints.sliders, robot.joints, robot.configuration(name), strict=True
    ):
        assert from_slider(joint.kind, slider.value) == pytest.approx(q, abs=1e-9)


@pytest.mark.parametrize(("robot_name", "conf_name"), singular_configurations())
def test_singular_configurations_are_drawn_and_read_out(session, robot_name, conf_name):
    session.panel.robot.value = robot_name  # the dropdown: rebuilds scene and panel
    assert session.state.robot_name == robot_name
    session.panel.joints.buttons[conf_name].value = True
    snap = session.snapshot
    report = snap.report
    assert report.status == "singular", report.text()
    assert math.isinf(report.condition)
    assert snap.rank < min(len(snap.rows), session.state.robot.dof)
    status = session.panel.status.content
    assert fmt.escape(report.text()) in status and "∞" in status
    assert "∞" in session.panel.measures.content
    if snap.det is not None:
        assert abs(snap.det) < 1e-9
    # The lost direction is drawn, the ellipsoid is flat but present, nothing is non-finite.
    overlays = session.scene.overlays
    assert overlays.lost_v.node.visible or overlays.lost_w.node.visible
    assert any(label.visible for label in overlays.lost_labels)
    ellipsoid = overlays.velocity.node
    assert ellipsoid.visible
    scale = np.asarray(ellipsoid.scale)
    assert np.isfinite(scale).all() and scale.min() >= TINY * 0.999
    assert_all_finite(session)
    # Force ellipsoid at a singularity: capped, never infinite.
    session.set_option(force_ellipsoid=True)
    force = np.asarray(overlays.force.node.scale)
    assert np.isfinite(force).all() and overlays.force.node.visible
    assert_all_finite(session)


def test_robot_switch_rebuilds_scene_and_panel(session):
    old_slider = session.panel.joints.sliders[0]
    session.panel.robot.value = "planar2"
    assert session.state.robot.dof == 2
    assert len(session.panel.joints.sliders) == 2
    assert old_slider._impl.removed
    assert len(session.scene.overlays.columns) == 2
    assert "v<sub>z</sub>" in session.panel.matrix.numeric.content
    late = viser.GuiEvent(session.client, session.client.client_id, old_slider)
    for callback in old_slider._impl.update_cb:  # a late event from a removed slider is ignored
        callback(late)
    assert session.state.robot_name == "planar2"
    assert_all_finite(session)


def test_every_library_robot_loads_at_home(session):
    for name in robots.names():
        session.panel.robot.value = name
        assert session.state.robot_name == name
        assert session.errors == 0
        assert_all_finite(session)


def test_rates_twist_and_torques(session):
    robot = session.state.robot
    session.panel.velocity.rate_sliders[0].value = 45.0  # °/s
    qd = np.zeros(robot.dof)
    qd[0] = math.radians(45.0)
    J = jacobian(robot, session.state.q)
    np.testing.assert_allclose(session.snapshot.twist, J @ qd)
    assert fmt.quantity(float((J @ qd)[0]), "m/s") in session.panel.velocity.twist.content
    session.panel.force.sliders[2].value = 10.0  # Fz [N]
    F = np.zeros(6)
    F[2] = 10.0
    np.testing.assert_allclose(session.snapshot.torques, J.T @ F)
    assert "N·m" in session.panel.force.torques.content
    assert session.scene.overlays.twist_v.node.visible and session.scene.overlays.force_arrow.node.visible


def test_joint_rates_blow_up_near_a_singularity(session):
    robot = session.state.robot
    q = robot.configuration("elbow_singular").copy()
    q[2] += math.radians(0.5)  # near, not at, the elbow singularity
    session.set_configuration(q)
    assert session.snapshot.report.status == "near singular"
    rows = task_rows(robot)
    direction = session.snapshot.report.lost_twist[list(rows)]
    row = rows[int(np.argmax(np.abs(direction)))]
    slider = session.panel.velocity.v_sliders[row]
    slider.value = slider.max / 2
    assert np.abs(session.snapshot.rates).max() > math.radians(180.0)
    assert "jl-bar over" in session.panel.velocity.rates.content
    session.panel.velocity.damping.value = 0.1  # damped least squares bounds them
    assert np.abs(session.snapshot.rates).max() < 1 / (2 * 0.1) * 0.5 + 1e-9
    assert_all_finite(session)


def test_options_toggle_nodes(session):
    session.panel.toggles["frames"].value = True
    assert session.scene.arm.frames.visible
    session.panel.toggles["columns"].value = False
    assert not any(a.node.visible for a in session.scene.overlays.columns)
    session.panel.toggles["columns"].value = True
    session.panel.scale.value = 2.0
    assert session.state.options.scale == 2.0
    session.panel.frame.value = "tool"
    J_tool = jacobian(session.state.robot, session.state.q, "tool")
    np.testing.assert_allclose(session.snapshot.J_shown, J_tool)
    assert "tool axes" in session.panel.matrix.numeric.content
    session.panel.scale.value = 1.0


def test_enlarged_matrix_follows_the_sliders(session):
    session.panel.matrix.open_large()
    big = session.panel.matrix._modal_html
    assert big is not None and "jl-big" in big.content
    session.panel.joints.sliders[0].value = 20.0
    assert fmt.fixed(session.snapshot.J_shown[0, 0]) in big.content
    session.panel.matrix.close_large()


def test_symbolic_form_or_a_visible_note(session):
    session.panel.robot.value = "planar2"  # small: a quick symbolic form
    wait_until(lambda: "computing" not in session.panel.matrix.symbolic.content, timeout=60)
    content = session.panel.matrix.symbolic.content
    assert "<math" in content or "not available" in content


def test_download_sends_a_file_or_says_why_not(lab_client, session):
    _, _, ws = lab_client
    session.panel.robot.value = "planar2"  # small: a quick symbolic export
    mark = ws.mark()
    errors = session.errors
    session.panel.matrix.download.value = "JSON"  # a click on "JSON"

    def outcome(m):
        return m["type"] == "FileTransferStartDownload" or (
            m["type"] == "NotificationShowMessage" and m["props"]["title"] == "Download not available"
        )

    _, msg = ws.wait_for(outcome, after=mark, timeout=90)
    if msg["type"] == "FileTransferStartDownload":
        assert msg["filename"] == "planar2_J_base.json"
        _, part = ws.wait_for(lambda m: m["type"] == "FileTransferPart", after=mark)
        content = bytes(part["content"])
        assert content.lstrip().startswith(b"{")
    assert session.errors == errors


def test_callback_error_is_shown_to_that_client_only(lab_client, session, monkeypatch):
    lab, _, ws = lab_client
    import app.session as session_module

    def broken(state):
        raise RuntimeError("deliberate failure")

    monkeypatch.setattr(session_module, "compute", broken)
    mark = ws.mark()
    errors = session.errors
    session.panel.joints.sliders[0].value = 12.0
    assert session.errors == errors + 1
    _, msg = ws.wait_for(lambda m: m["type"] == "NotificationShowMessage", after=mark)
    assert "deliberate failure" in msg["props"]["body"]
    monkeypatch.undo()
    session.panel.joints.sliders[0].value = 13.0  # the session carries on
    assert session.errors == errors + 1
    # And another client is served independently.
    with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as other:
        wait_until(lambda: len(lab.sessions) == 2)
        second = lab.session()
        assert second is not session and second.errors == 0
        second.panel.joints.sliders[0].value = -40.0
        assert session.state.q[0] == pytest.approx(math.radians(13.0))
        assert other.wait_for(lambda m: m["type"] == "SceneNodeUpdateMessage")
    wait_until(lambda: len(lab.sessions) == 1)


def test_a_nonfinite_value_from_the_page_is_refused(lab_client, session):
    _, _, ws = lab_client
    q = session.state.q.copy()
    errors = session.errors
    ws.set_value(session.panel.joints.sliders[2]._impl.uuid, math.nan)
    wait_until(lambda: session.errors == errors + 1)
    np.testing.assert_array_equal(session.state.q, q)
    session.panel.joints.sliders[0].value = 5.0  # the next event redraws as usual
    assert session.errors == errors + 1
    assert_all_finite(session)


def test_no_nonfinite_value_reached_the_client(lab_client):
    _, _, ws = lab_client
    time.sleep(0.2)
    messages = [m for _, m in ws.messages]
    assert len(messages) > 100
    bad = nonfinite_paths(messages)
    assert not bad, bad[:10]


# ------------------------------------------------------------------ URDF robots
URDF = """<?xml version="1.0"?>
<robot name="two_link">
  <link name="base"><visual><geometry><cylinder radius="0.05" length="0.1"/></geometry></visual></link>
  <link name="upper"><visual><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.04 0.04"/></geometry></visual></link>
  <link name="fore"><visual><origin xyz="0.1 0 0"/><geometry>FORE</geometry></visual></link>
  <link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="fore"/><child link="tool"/><origin xyz="0.2 0 0"/></joint>
</robot>
"""


@pytest.mark.parametrize(
    ("fore", "meshes"),
    [('<box size="0.2 0.03 0.03"/>', True), ('<mesh filename="meshes/missing.stl"/>', False)],
    ids=["meshes-present", "mesh-missing"],
)
def test_urdf_robot_drawn_with_its_meshes_or_generated_geometry(tmp_path, fore, meshes):
    path = tmp_path / "two_link.urdf"
    path.write_text(URDF.replace("FORE", fore))
    with running_lab(urdf=str(path)) as (lab, session, _):
        assert session.state.robot_name == "two_link"
        assert (session.scene.arm._meshes is not None) == meshes
        assert session.panel.robot.options[0] == "two_link" and "puma560" in session.panel.robot.options
        session.panel.joints.sliders[1].value = -30.0
        assert session.state.q[1] == pytest.approx(math.radians(-30.0))
        assert session.errors == 0
        assert_all_finite(session)


def test_serve_prints_the_url_and_stops(capsys):
    from app.server import serve

    lab = serve(port=0, block=False)
    try:
        out = capsys.readouterr().out
        assert f"http://127.0.0.1:{lab.port}" in out and "puma560" in out
    finally:
        lab.stop()


def test_an_unknown_robot_is_refused_before_the_server_starts():
    from app.server import Lab
    from kinematics.errors import UnknownRobotError

    with pytest.raises(UnknownRobotError, match="puma560"):
        Lab(robot="no_such_robot", port=0)
