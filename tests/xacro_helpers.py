"""A small xacro package laid out as the Robotics Toolbox's KUKA files are (package ``kuka_kr6_support``
in a folder ``kuka_kr6`` without a package.xml, ``kuka_resources`` beside it), for the tests of
``--package`` / ``package_dirs`` (tests/kinematics/test_xacro_packages.py, tests/app/test_cli_packages.py)."""

from __future__ import annotations

from pathlib import Path

COMMON = """<?xml version="1.0"?>
<robot xmlns:xacro="http://wiki.ros.org/xacro">
  <xacro:property name="reach" value="0.45"/>
</robot>
"""

MACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://wiki.ros.org/xacro">
  <xacro:include filename="$(find kuka_resources)/urdf/common.xacro"/>
  <xacro:macro name="kr6" params="prefix">
    <link name="${prefix}base_link">
      <visual><geometry><mesh filename="package://kuka_kr6_support/meshes/base.stl"/></geometry></visual>
    </link>
    <link name="${prefix}link_1">
      <visual><geometry><mesh filename="$(find kuka_kr6_support)/meshes/link_1.stl"/></geometry></visual>
    </link>
    <link name="${prefix}tool0"/>
    <joint name="${prefix}joint_a1" type="revolute">
      <parent link="${prefix}base_link"/><child link="${prefix}link_1"/>
      <origin xyz="0 0 0.4"/><axis xyz="0 0 -1"/>
      <limit lower="-2.9" upper="2.9" effort="0" velocity="6"/>
    </joint>
    <joint name="${prefix}joint_a6" type="revolute">
      <parent link="${prefix}link_1"/><child link="${prefix}tool0"/>
      <origin xyz="${reach} 0 0"/><axis xyz="1 0 0"/>
      <limit lower="-6.1" upper="6.1" effort="0" velocity="10"/>
    </joint>
  </xacro:macro>
</robot>
"""

ROBOT = """<?xml version="1.0"?>
<robot name="kuka_kr6" xmlns:xacro="http://wiki.ros.org/xacro">
  <xacro:arg name="prefix" default=""/>
  <xacro:include filename="$(find kuka_kr6_support)/urdf/kr6_macro.xacro"/>
  <xacro:kr6 prefix="$(arg prefix)"/>
</robot>
"""


def hand_written(prefix: str = "") -> str:
    """The URDF ROBOT expands to, written out."""
    p = prefix
    return f"""<robot name="kuka_kr6"><link name="{p}base_link"/><link name="{p}link_1"/><link name="{p}tool0"/>
      <joint name="{p}joint_a1" type="revolute"><parent link="{p}base_link"/><child link="{p}link_1"/>
      <origin xyz="0 0 0.4"/><axis xyz="0 0 -1"/><limit lower="-2.9" upper="2.9" effort="0" velocity="6"/></joint>
      <joint name="{p}joint_a6" type="revolute"><parent link="{p}link_1"/><child link="{p}tool0"/>
      <origin xyz="0.45 0 0"/><axis xyz="1 0 0"/><limit lower="-6.1" upper="6.1" effort="0" velocity="10"/></joint>
      </robot>"""


def make_kuka(tmp_path: Path) -> Path:
    """rtb-data's layout: kuka_description/kuka_kr6 holds package kuka_kr6_support, no package.xml;
    kuka_resources beside it (found near the file)."""
    top = tmp_path / "rtbdata" / "xacro" / "kuka_description"
    pkg, res = top / "kuka_kr6", top / "kuka_resources"
    for folder in (pkg / "urdf", pkg / "meshes", res / "urdf"):
        folder.mkdir(parents=True)
    (res / "urdf" / "common.xacro").write_text(COMMON)
    (pkg / "urdf" / "kr6_macro.xacro").write_text(MACRO)
    (pkg / "urdf" / "kr6.xacro").write_text(ROBOT)
    for name in ("base", "link_1"):
        (pkg / "meshes" / f"{name}.stl").write_text("solid x\nendsolid x\n")
    return pkg / "urdf" / "kr6.xacro"
