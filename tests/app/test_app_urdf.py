"""The app with robots from URDF files: meshes or generated geometry, the chain picker, hostile mesh
paths, the listing name, and the serve entry point."""

from __future__ import annotations

import math

import locations
import pytest
from app_helpers import assert_all_finite, running_lab, scene_props

DATA = locations.DATA / "urdf"


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
    ("fore", "meshes", "links"),
    [('<box size="0.2 0.03 0.03"/>', True, False), ('<mesh filename="meshes/missing.stl"/>', True, True)],
    ids=["meshes-present", "mesh-missing"],
)
def test_urdf_robot_drawn_with_its_meshes_or_generated_geometry(tmp_path, fore, meshes, links):
    """Every visual found: the URDF's geometry alone. One missing: the ones found are drawn, and the
    generated links too, so the arm never has a hole."""
    path = tmp_path / "arm_file.urdf"  # listed under its <robot name>, not the file stem
    path.write_text(URDF.replace("FORE", fore))
    with running_lab(urdf=str(path)) as (lab, session, _):
        assert session.state.robot_name == "two_link"
        props = scene_props(session)
        assert any(name.startswith("/lab/arm/urdf") for name in props) == meshes
        cylinders = props["/lab/arm/cylinders"]  # the generated links and the two revolute axes
        assert (len(cylinders["batched_positions"]) > 2) == links
        assert session.panel.robot.options[0] == "two_link"
        assert "Unimation PUMA 560 (puma560)" in session.panel.robot.options
        session.panel.joints.sliders[1].value = -30.0
        session.settle()
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


def test_urdf_with_several_chains_offers_a_chain_picker():
    """A gripper arm opens at its hand (no jaw as a 4th joint); the picker switches to a finger chain."""
    with running_lab(urdf=str(DATA / "gripper_arm.urdf")) as (lab, session, _):
        assert session.state.robot.dof == 3
        chain = session.panel.chain
        assert chain is not None and len(chain.options) == 3
        assert "hand" in chain.value and "chain" in session.panel.source.content
        finger = next(o for o in chain.options if "left_finger" in o)
        chain.value = finger
        session.settle()
        assert session.state.robot.dof == 4 and session.state.chain == "left_finger"
        assert session.panel.chain is not None and session.panel.chain.value == finger
        assert "left_finger" in session.panel.source.content
        assert session.errors == 0
        assert_all_finite(session)


def test_hostile_mesh_paths_are_listed_not_read():
    """Mesh names that point outside the URDF's folders are never opened: the panel lists them as not found."""
    with running_lab(urdf=str(DATA / "mesh_arm" / "urdf" / "hostile.urdf")) as (lab, session, _):
        content = session.panel.source.content
        assert "mesh files not found" in content and "/etc/passwd" in content
        # Generated geometry: no mesh node, nothing read from outside.
        assert not any(name.startswith("/lab/arm/urdf") for name in scene_props(session))
        assert session.errors == 0
