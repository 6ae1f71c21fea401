""".xacro robot descriptions: expanded without ROS, $(find PKG) and package:// resolved like meshes
(a folder named after the package, or one whose package.xml names it), arguments given, errors in words;
the same robot as the URDF written by hand; the command line and the app's catalogue take them; an
uploaded xacro is refused."""

from __future__ import annotations

import numpy as np
import pytest

import kinematics
import robots
from app.cli.export import main as export_main
from app.services.catalog import RobotCatalog
from app.tab.robots import TabCatalog
from kinematics.errors import UrdfError
from kinematics.urdf import chains, expand_xacro, mesh_report, parse_xacro_args

MACROS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="link_with_mesh" params="name">
    <link name="${name}">
      <visual><geometry><mesh filename="package://two_link_description/meshes/${name}.stl"/></geometry></visual>
    </link>
  </xacro:macro>
  <xacro:macro name="revolute" params="name parent child x">
    <joint name="${name}" type="revolute">
      <parent link="${parent}"/><child link="${child}"/>
      <origin xyz="${x} 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
      <limit lower="${-pi/2}" upper="${pi/2}" effort="1" velocity="1"/>
    </joint>
  </xacro:macro>
</robot>
"""

ARM = """<?xml version="1.0"?>
<robot name="two_link" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default=""/>
  <xacro:arg name="l1" default="0.5"/>
  <xacro:property name="p" value="$(arg prefix)"/>
  <xacro:include filename="$(find two_link_description)/urdf/macros.xacro"/>
  <xacro:link_with_mesh name="${p}base"/>
  <xacro:link_with_mesh name="${p}upper"/>
  <xacro:link_with_mesh name="${p}lower"/>
  <link name="${p}tool0"/>
  <xacro:revolute name="${p}shoulder" parent="${p}base" child="${p}upper" x="0"/>
  <xacro:revolute name="${p}elbow" parent="${p}upper" child="${p}lower" x="$(arg l1)"/>
  <joint name="${p}flange" type="fixed">
    <parent link="${p}lower"/><child link="${p}tool0"/><origin xyz="0.4 0 0"/>
  </joint>
</robot>
"""


def hand_written(l1: float, prefix: str = "") -> str:
    """The URDF the xacro file should expand to, written out by hand."""
    link = '<link name="{0}"><visual><geometry><mesh filename="x.stl"/></geometry></visual></link>'
    joint = (
        '<joint name="{0}" type="revolute"><parent link="{1}"/><child link="{2}"/>'
        '<origin xyz="{3} 0 0"/><axis xyz="0 0 1"/>'
        '<limit lower="-1.5707963267948966" upper="1.5707963267948966" effort="1" velocity="1"/></joint>'
    )
    p = prefix
    return (
        '<robot name="two_link">'
        + "".join(link.format(p + n) for n in ("base", "upper", "lower"))
        + f'<link name="{p}tool0"/>'
        + joint.format(p + "shoulder", p + "base", p + "upper", 0)
        + joint.format(p + "elbow", p + "upper", p + "lower", l1)
        + f'<joint name="{p}flange" type="fixed"><parent link="{p}lower"/><child link="{p}tool0"/>'
        '<origin xyz="0.4 0 0"/></joint></robot>'
    )


@pytest.fixture
def workspace(tmp_path):
    """A ROS-like workspace: the package's folder is not named after the package (package.xml is)."""
    pkg = tmp_path / "src" / "two-link-pkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "package.xml").write_text("<package><name>two_link_description</name></package>")
    (pkg / "urdf" / "macros.xacro").write_text(MACROS)
    (pkg / "urdf" / "arm.urdf.xacro").write_text(ARM)
    for name in ("base", "upper", "lower"):
        (pkg / "meshes" / f"{name}.stl").write_text("solid x\nendsolid x\n")
    return pkg / "urdf" / "arm.urdf.xacro"


def test_expands_and_is_the_hand_written_robot(workspace, tmp_path):
    robot = robots.load(workspace)
    manual = kinematics.urdf.robot_from_urdf_string(hand_written(0.5))
    assert robot.joint_names == ("shoulder", "elbow") and robot.dof == 2
    for q in np.random.default_rng(0).uniform(-1.5, 1.5, (5, 2)):
        np.testing.assert_allclose(kinematics.fk(robot, q), kinematics.fk(manual, q), atol=1e-15)
        np.testing.assert_allclose(kinematics.jacobian(robot, q), kinematics.jacobian(manual, q), atol=1e-15)
    np.testing.assert_allclose(robot.qlim, [[-np.pi / 2] * 2, [np.pi / 2] * 2])


def test_arguments_change_the_robot(workspace):
    robot = robots.load(workspace, xacro_args={"prefix": "left_", "l1": "0.75"})
    manual = kinematics.urdf.robot_from_urdf_string(hand_written(0.75, "left_"))
    assert robot.joint_names == ("left_shoulder", "left_elbow")
    q = np.array([0.3, -0.7])
    np.testing.assert_allclose(kinematics.jacobian(robot, q), kinematics.jacobian(manual, q), atol=1e-15)
    assert parse_xacro_args(["prefix:=left_", "l1:=0.75"]) == {"prefix": "left_", "l1": "0.75"}
    with pytest.raises(UrdfError, match="NAME:=VALUE"):
        parse_xacro_args(["prefix=left_"])


def test_meshes_resolve_through_package_xml(workspace):
    robots.load(workspace)
    found, missing = mesh_report(workspace)
    assert missing == [] and len(found) == 3
    assert all(path.parent.name == "meshes" for path in found.values())
    assert [c.tip_link for c in chains(workspace)][:1] == ["tool0"]


def test_errors_name_what_is_missing(workspace, tmp_path):
    text = ARM.replace('<xacro:arg name="l1" default="0.5"/>', "")
    bad = workspace.with_name("no_default.urdf.xacro")
    bad.write_text(text)
    with pytest.raises(
        UrdfError, match=r"no_default.urdf.xacro: xacro argument l1 is not defined.*--xacro-arg l1:="
    ):
        robots.load(bad)
    unknown_pkg = workspace.with_name("elsewhere.urdf.xacro")
    unknown_pkg.write_text(ARM.replace("$(find two_link_description)", "$(find no_such_pkg)"))
    with pytest.raises(UrdfError, match=r"\$\(find no_such_pkg\): no package 'no_such_pkg'"):
        robots.load(unknown_pkg)
    no_macro = workspace.with_name("no_macro.urdf.xacro")
    no_macro.write_text(
        ARM.replace('<xacro:revolute name="${p}shoulder"', '<xacro:rotary name="${p}shoulder"')
    )
    with pytest.raises(UrdfError, match="rotary"):
        robots.load(no_macro)
    broken = workspace.with_name("broken.urdf.xacro")
    broken.write_text("<robot><link name='a'>")
    with pytest.raises(UrdfError, match="broken.urdf.xacro"):
        expand_xacro(broken)


def test_command_line_exports_a_xacro_robot_with_arguments(workspace, tmp_path, capsys):
    out = tmp_path / "J.json"
    argv = [
        str(workspace),
        "-f",
        "json",
        "-o",
        str(out),
        "--xacro-arg",
        "prefix:=r_",
        "--xacro-arg",
        "l1:=0.6",
    ]
    assert export_main(argv) == 0
    assert '"name": "r_shoulder"' in out.read_text()
    assert export_main([str(workspace), "--xacro-arg", "oops"]) == 1
    assert "NAME:=VALUE" in capsys.readouterr().err


def test_the_app_catalogue_lists_a_xacro_file(workspace):
    catalog = RobotCatalog([workspace], xacro_args={"prefix": "a_"})
    name = catalog.default()
    robot = catalog.load(name)
    assert robot.joint_names == ("a_shoulder", "a_elbow")
    assert [c.tip_link for c in catalog.chains(name)][0] == "a_tool0"
    assert catalog.meshes(name) == (
        0,
        [f"package://two_link_description/meshes/a_{n}.stl" for n in ("base", "upper", "lower")],
    )
    catalog = RobotCatalog([workspace], xacro_args={"l1": "0.6"})
    assert catalog.meshes(catalog.default()) == (3, [])


def test_an_uploaded_xacro_is_refused_in_words(workspace):
    tab = TabCatalog(RobotCatalog())
    with pytest.raises(UrdfError, match="never expands an uploaded xacro"):
        tab.add_upload("arm.urdf.xacro", workspace.read_bytes())
    with pytest.raises(UrdfError, match="never expands an uploaded xacro"):
        tab.add_upload("arm.urdf", workspace.read_bytes())  # renamed, still xacro
