"""xacro without a ROS workspace (issue 30): ``package_dirs={NAME: DIR}`` / ``--package NAME=DIR`` and
``package_path`` / ``--package-path DIR`` find ``$(find NAME)`` and ``package://NAME`` where nothing near
the file does (the Robotics Toolbox's KUKA files: package ``kuka_kr6_support`` kept in a folder ``kuka_kr6``
without a package.xml); a package not found is named with every place looked and the option that maps
it; a misspelt xacro argument is refused naming those the file declares; a file of macros only and a .urdf
with xacro left in it say so. Small packages built in tmp_path, no network data."""

from __future__ import annotations

import numpy as np
import pytest
from xacro_helpers import ROBOT, hand_written, make_kuka

import kinematics
import robots
from kinematics.errors import UrdfError
from kinematics.urdf import chains, mesh_report, resolve_mesh, robot_from_urdf_string


@pytest.fixture
def kuka(tmp_path):
    return make_kuka(tmp_path)


@pytest.fixture(autouse=True)
def no_ros(monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)


def same_robot(robot, prefix: str = "") -> None:
    manual = robot_from_urdf_string(hand_written(prefix))
    assert robot.joint_names == manual.joint_names
    for q in np.random.default_rng(3).uniform(-2, 2, (4, 2)):
        np.testing.assert_allclose(kinematics.jacobian(robot, q), kinematics.jacobian(manual, q), atol=1e-15)


def test_a_package_not_found_is_named_with_every_place_looked_and_the_option(kuka):
    with pytest.raises(UrdfError) as err:
        robots.load(kuka)
    text = str(err.value)
    assert "kr6.xacro: $(find kuka_kr6_support): no package 'kuka_kr6_support' found" in text
    assert f"the folders enclosing the file up to {kuka.parents[6]}" in text
    assert f"the folders inside {kuka.parent} up to {kuka.parents[3]}" in text
    assert "--package-path: (none given)" in text
    assert "ROS_PACKAGE_PATH: (not set)" in text and "AMENT_PREFIX_PATH: (not set)" in text
    assert "--package kuka_kr6_support=DIR" in text and "package_dirs={'kuka_kr6_support': DIR}" in text


def test_package_dirs_maps_a_package_to_a_folder_of_another_name(kuka):
    folder = kuka.parents[1]
    robot = robots.load(kuka, package_dirs={"kuka_kr6_support": folder}, xacro_args={"prefix": "r_"})
    same_robot(robot, "r_")
    found, missing = mesh_report(kuka)  # the meshes of the robot as opened: with its packages
    assert missing == []
    assert sorted(p.name for p in found.values()) == ["base.stl", "link_1.stl"]
    assert all(p.parent == (folder / "meshes").resolve() for p in found.values())
    assert [c.tip_link for c in chains(kuka, package_dirs={"kuka_kr6_support": folder})][0] == "r_tool0"


def test_package_path_finds_a_package_xml_naming_a_folder_of_another_name_nested(kuka, tmp_path):
    folder = kuka.parents[1]
    (folder / "package.xml").write_text("<package><name>kuka_kr6_support</name></package>")
    elsewhere = tmp_path / "elsewhere" / "arm.xacro"  # far from the package: only the path finds it
    elsewhere.parent.mkdir()
    elsewhere.write_text(ROBOT)
    with pytest.raises(UrdfError, match="no package 'kuka_kr6_support'"):
        robots.load(elsewhere)
    # kuka_description/kuka_kr6: two levels below the path's entry, in a folder not named after it
    same_robot(robots.load(elsewhere, package_path=[tmp_path / "rtbdata" / "xacro"]))
    # ... and kuka_resources, needed by the macro file, is found near the macro file
    with pytest.raises(UrdfError, match="no package 'kuka_kr6_support'"):
        robots.load(elsewhere, package_path=[tmp_path / "elsewhere"])  # the wrong folder


def test_a_mapped_package_still_never_lets_a_mesh_out(kuka, tmp_path):
    folder = kuka.parents[1]
    (tmp_path / "secret.stl").write_text("solid s\nendsolid s\n")
    (folder / "meshes" / "link.stl").symlink_to(tmp_path / "secret.stl")
    named = {"kuka_kr6_support": folder}
    robots.load(kuka, package_dirs=named)
    assert resolve_mesh(kuka, "package://kuka_kr6_support/meshes/base.stl") == (folder / "meshes/base.stl")
    for uri in (
        "package://kuka_kr6_support/../../../../secret.stl",
        "package://kuka_kr6_support/meshes/link.stl",  # a link that points outside
        "package://kuka_kr6_support/urdf/kr6.xacro",  # not a mesh
        f"file://{tmp_path}/secret.stl",
    ):
        assert resolve_mesh(kuka, uri) is None, uri


def test_a_misspelt_xacro_argument_is_refused_naming_those_the_file_declares(kuka):
    named = {"kuka_kr6_support": kuka.parents[1]}
    with pytest.raises(UrdfError) as err:
        robots.load(kuka, package_dirs=named, xacro_args={"prefx": "r_"})
    assert (
        str(err.value)
        == "kr6.xacro: xacro argument prefx is not an argument of the file; it declares: prefix"
    )
    same_robot(robots.load(kuka, package_dirs=named, xacro_args={"prefix": "l_"}), "l_")


def test_a_file_of_macros_only_says_so_and_names_the_file_that_uses_it(kuka, monkeypatch):
    monkeypatch.chdir(kuka.parents[1])
    with pytest.raises(UrdfError) as err:
        robots.load(kuka.with_name("kr6_macro.xacro"))
    text = str(err.value)
    assert text.startswith(
        "kr6_macro.xacro: a xacro file of macros only: it defines the macro(s) kr6 but no robot"
    )
    assert "open the xacro file that uses them, e.g. urdf/kr6.xacro" in text
    assert "URDF has no <link>" not in text


@pytest.mark.parametrize(
    ("leftover", "piece"),
    [
        ("$(optenv ARM_X 0.1) 0 0", "$(optenv ARM_X 0.1)"),  # "expected 3 numbers, found 5" before
        ("$(find arm_description)/x 0 0", "$(find arm_description)"),
        ("${0.1 * 2} 0 0", "${0.1 * 2}"),
    ],
)
def test_a_urdf_with_xacro_left_in_it_says_it_is_xacro_and_what_to_do(tmp_path, leftover, piece):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(hand_written().replace('<origin xyz="0.45 0 0"/>', f'<origin xyz="{leftover}"/>'))
    with pytest.raises(UrdfError) as err:
        robots.load(urdf)
    text = str(err.value)
    assert text.startswith(f"arm.urdf is not expanded xacro: it still holds {piece!r}, which only xacro")
    assert (
        "only xacro replaces" in text
        and "--urdf arm.urdf.xacro" in text
        and "xacro arm.urdf.xacro > " in text
    )
    assert "xyz" in text  # the parser's own words follow
    with pytest.raises(UrdfError, match="this URDF is not expanded xacro"):
        robot_from_urdf_string(urdf.read_text())
    good = tmp_path / "good.urdf"
    good.write_text(hand_written())
    same_robot(robots.load(good))


def test_xacro_1_s_unprefixed_property_tag_is_read(kuka):
    """KUKA's kr210l150_macro.xacro writes <property name="deg" …/>, as xacro 1 allowed."""
    macro = kuka.with_name("kr6_macro.xacro")
    macro.write_text(
        macro.read_text()
        .replace('<xacro:include filename="$(find kuka_resources)/urdf/common.xacro"/>', "")
        .replace('<xacro:macro name="kr6"', '<property name="reach" value="0.45"/><xacro:macro name="kr6"')
        .replace('upper="2.9"', 'upper="${170*deg}"')
        .replace("<xacro:macro", '<property name="deg" value="0.017453293"/><xacro:macro', 1)
    )
    robot = robots.load(kuka, package_dirs={"kuka_kr6_support": kuka.parents[1]})
    assert robot.qlim[1][0] == pytest.approx(170 * 0.017453293, abs=1e-12)
    assert kinematics.fk(robot, np.zeros(2))[0, 3] == pytest.approx(0.45)
