"""One name per joint: a URDF joint's own name (the slider's) in every code export, beside its symbol,
and the notes' quotes and arrows kept in C and MATLAB comments."""

from __future__ import annotations

import json

import pytest

from kinematics.symbolic.typeset import export as ex
from kinematics.urdf import robot_from_urdf_string

NAMES = ("wx250s/waist", "shoulder_lift_joint", "arm[2]'s elbow")
URDF = (
    '<robot name="named"><link name="base"/><link name="a"/><link name="b"/><link name="tip"/>'
    f'<joint name="{NAMES[0]}" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>'
    '<limit lower="-3" upper="3"/></joint>'
    f'<joint name="{NAMES[1]}" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.3" rpy="1.5708 0 0"/>'
    '<axis xyz="0 0 1"/><limit lower="-3" upper="3"/></joint>'
    f'<joint name="{NAMES[2].replace(chr(39), "&apos;")}" type="revolute"><parent link="b"/><child link="tip"/>'
    '<origin xyz="0.4 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3"/></joint></robot>'
)


@pytest.fixture(scope="module")
def robot():
    return robot_from_urdf_string(URDF)


def test_the_robot_and_its_sliders_carry_the_urdf_names(robot):
    assert robot.joint_names == NAMES


@pytest.mark.parametrize(
    ("fmt", "listed"),
    [("c", "q[{k}] {name} [rad]"), ("matlab", "q({k1}) {name} [rad]"), ("python", "q{k1} {name} [rad]")],
)
def test_each_code_export_lists_every_joint_by_its_urdf_name(robot, fmt, listed):
    text = ex.export(robot, fmt)
    for k, name in enumerate(NAMES):
        assert listed.format(k=k, k1=k + 1, name=name) in text, (fmt, name)
    if fmt in ("c", "matlab"):  # the snap note of rpy 1.5708 keeps its quotes and arrow
        assert f"joint '{NAMES[1]}': fixed rotation: rpy (1.5708, 0, 0) -> rpy (pi/2, 0, 0)" in text


def test_json_and_latex_name_the_same_joints(robot):
    doc = json.loads(ex.export(robot, "json"))
    assert [j["name"] for j in doc["joints"]] == list(NAMES)
    latex = ex.export(robot, "latex")
    assert "\\text{: wx250s/waist}" in latex and "\\text{: shoulder\\_lift\\_joint}" in latex
