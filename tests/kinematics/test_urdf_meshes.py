"""Mesh files of a URDF: found in its folder tree and its ROS packages, never anywhere else."""

from __future__ import annotations

import os

import locations
import pytest

from kinematics.urdf import mesh_filename_handler, mesh_report, resolve_mesh

DATA = locations.DATA / "urdf" / "mesh_arm"
ARM = DATA / "urdf" / "arm.urdf"
HOSTILE = DATA / "urdf" / "hostile.urdf"


@pytest.fixture(autouse=True)
def no_ros_environment(monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)


def test_package_uri_resolves_to_the_enclosing_package_folder():
    found = resolve_mesh(ARM, "package://mesh_arm/meshes/link.stl")
    assert found == (DATA / "meshes" / "link.stl").resolve()


def test_relative_path_resolves_against_the_urdf_folder():
    assert (
        resolve_mesh(ARM, "meshes_local/hand.stl") == (DATA / "urdf" / "meshes_local" / "hand.stl").resolve()
    )
    assert resolve_mesh(ARM, str((DATA / "urdf" / "meshes_local" / "hand.stl").resolve())) is not None
    assert resolve_mesh(ARM, (DATA / "urdf" / "meshes_local" / "hand.stl").resolve().as_uri()) is not None


def test_mesh_report_splits_found_and_missing_in_file_order():
    resolved, unresolved = mesh_report(ARM)
    assert resolved == {
        "package://mesh_arm/meshes/link.stl": (DATA / "meshes" / "link.stl").resolve(),
        "meshes_local/hand.stl": (DATA / "urdf" / "meshes_local" / "hand.stl").resolve(),
    }
    # missing.stl does not exist; ../meshes/link.stl exists but lies outside the URDF's folder tree.
    assert unresolved == ["package://mesh_arm/meshes/missing.stl", "../meshes/link.stl"]


@pytest.mark.parametrize(
    "uri",
    [
        "/etc/passwd",
        "../../x.stl",
        "file:///etc/passwd",
        "package://../../etc/x",
        "package://mesh_arm/../../../../../../etc/passwd",
        "package://etc/passwd",
        "package://mesh_arm/../urdf/../../../../../../../../etc/hosts",
        "http://example.invalid/x.stl",
        "file://otherhost/etc/passwd",
        "meshes_local/../../meshes/link.stl",
        "package:///etc/passwd",
        "package://",
        "",
        "meshes_local/hand.stl\x00.png",
    ],
)
def test_hostile_names_never_resolve(uri):
    assert resolve_mesh(ARM, uri) is None


def test_every_mesh_of_the_hostile_file_is_unresolved():
    resolved, unresolved = mesh_report(HOSTILE)
    assert resolved == {}
    assert "/etc/passwd" in unresolved and "package://../../etc/x" in unresolved and len(unresolved) == 8


def test_symlinks_that_leave_the_folder_are_not_followed(tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.stl").write_text("solid s\nendsolid s\n")
    robot_dir = tmp_path / "robot"
    (robot_dir / "meshes").mkdir(parents=True)
    urdf = robot_dir / "r.urdf"
    urdf.write_text("<robot name='r'><link name='a'/></robot>")
    (robot_dir / "meshes" / "link.stl").symlink_to(outside / "secret.stl")
    (robot_dir / "meshes" / "up").symlink_to(outside)
    (robot_dir / "meshes" / "own.stl").write_text("solid o\nendsolid o\n")
    (robot_dir / "meshes" / "alias.stl").symlink_to(robot_dir / "meshes" / "own.stl")
    assert resolve_mesh(urdf, "meshes/link.stl") is None
    assert resolve_mesh(urdf, "meshes/up/secret.stl") is None
    assert resolve_mesh(urdf, "meshes/alias.stl") == (robot_dir / "meshes" / "own.stl").resolve()


def test_only_mesh_file_types_are_returned(tmp_path):
    (tmp_path / "notes.txt").write_text("not a mesh")
    (tmp_path / "LINK.STL").write_text("solid l\nendsolid l\n")
    urdf = tmp_path / "r.urdf"
    urdf.write_text("<robot name='r'><link name='a'/></robot>")
    assert resolve_mesh(urdf, "notes.txt") is None
    assert resolve_mesh(urdf, "LINK.STL") == (tmp_path / "LINK.STL").resolve()
    assert resolve_mesh(urdf, ".") is None  # the folder itself


def test_ros_package_path_and_ament_prefix_and_package_dirs(tmp_path, monkeypatch):
    urdf_dir = tmp_path / "elsewhere"
    urdf_dir.mkdir()
    urdf = urdf_dir / "r.urdf"
    urdf.write_text("<robot name='r'><link name='a'/></robot>")
    ros = tmp_path / "ros_ws" / "src"
    (ros / "arm_description" / "meshes").mkdir(parents=True)
    (ros / "arm_description" / "meshes" / "a.stl").write_text("solid a\nendsolid a\n")
    ament = tmp_path / "install"
    (ament / "share" / "hand_description").mkdir(parents=True)
    (ament / "share" / "hand_description" / "h.dae").write_text("<COLLADA/>")
    extra = tmp_path / "extra" / "gripper_pkg"
    extra.mkdir(parents=True)
    (extra / "g.obj").write_text("v 0 0 0\n")
    assert resolve_mesh(urdf, "package://arm_description/meshes/a.stl") is None
    monkeypatch.setenv("ROS_PACKAGE_PATH", os.pathsep.join(["/nonexistent", str(ros)]))
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(ament))
    assert (
        resolve_mesh(urdf, "package://arm_description/meshes/a.stl")
        == (ros / "arm_description" / "meshes" / "a.stl").resolve()
    )
    assert (
        resolve_mesh(urdf, "package://hand_description/h.dae")
        == (ament / "share" / "hand_description" / "h.dae").resolve()
    )
    assert resolve_mesh(urdf, "package://gripper_pkg/g.obj") is None
    assert (
        resolve_mesh(urdf, "package://gripper_pkg/g.obj", package_dirs=[extra]) == (extra / "g.obj").resolve()
    )
    assert (
        resolve_mesh(urdf, "package://gripper_pkg/g.obj", package_dirs=[extra.parent])
        == (extra / "g.obj").resolve()
    )
    # A package folder is a boundary too: its meshes cannot reach a sibling package by "..".
    assert (
        resolve_mesh(urdf, "package://arm_description/../../../install/share/hand_description/h.dae") is None
    )


def test_a_package_folder_beside_the_urdf(tmp_path):
    (tmp_path / "robot" / "my_pkg" / "meshes").mkdir(parents=True)
    (tmp_path / "robot" / "my_pkg" / "meshes" / "m.stl").write_text("solid m\nendsolid m\n")
    urdf = tmp_path / "robot" / "urdf" / "r.urdf"
    urdf.parent.mkdir()
    urdf.write_text("<robot name='r'><link name='a'/></robot>")
    assert (
        resolve_mesh(urdf, "package://my_pkg/meshes/m.stl")
        == (tmp_path / "robot" / "my_pkg" / "meshes" / "m.stl").resolve()
    )


def test_yourdfpy_with_our_handler_loads_only_the_resolved_meshes():
    import yourdfpy

    urdf = yourdfpy.URDF.load(
        str(ARM), build_scene_graph=True, load_meshes=True, filename_handler=mesh_filename_handler(ARM)
    )
    assert len(urdf.scene.geometry) == 2  # link.stl via package://, hand.stl beside the URDF
    hostile = yourdfpy.URDF.load(
        str(HOSTILE),
        build_scene_graph=True,
        load_meshes=True,
        filename_handler=mesh_filename_handler(HOSTILE),
    )
    assert len(hostile.scene.geometry) == 0
    handler = mesh_filename_handler(ARM)
    assert handler(fname="/etc/passwd") == "" and handler(fname="meshes_local/hand.stl").endswith("hand.stl")


def _file(path, text="solid x\nendsolid x\n"):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def test_an_empty_package_name_takes_the_first_part_as_the_package(tmp_path):
    """example-robot-data's Talos: package:///example-robot-data/robots/talos_data/meshes/... from
    share/example-robot-data/robots/talos_data/robots/talos.urdf (50 meshes were missing)."""
    top = tmp_path / "share" / "example-robot-data"
    mesh = _file(top / "robots" / "talos_data" / "meshes" / "torso" / "torso_1.STL")
    urdf = _file(top / "robots" / "talos_data" / "robots" / "talos.urdf", "<robot/>")
    uri = "package:///example-robot-data/robots/talos_data/meshes/torso/torso_1.STL"
    assert resolve_mesh(urdf, uri) == mesh.resolve()
    assert resolve_mesh(urdf, "package:///example-robot-data/../../secret.stl") is None
    _file(tmp_path / "secret.stl")
    assert resolve_mesh(urdf, "package:///../secret.stl") is None


def test_a_path_from_the_package_top_resolves_inside_the_folder_it_names(tmp_path):
    """pybullet_data/differential/diff_ring.urdf names differential/diff_ring.stl (pybullet reads it
    from its data folder); the file must lie inside the folder whose name the path starts with."""
    data = tmp_path / "pybullet_data"
    mesh = _file(data / "differential" / "diff_ring.stl")
    urdf = _file(data / "differential" / "diff_ring.urdf", "<robot/>")
    assert resolve_mesh(urdf, "differential/diff_ring.stl") == mesh.resolve()
    _file(data / "other" / "x.stl")
    assert resolve_mesh(urdf, "differential/../other/x.stl") is None  # outside the named folder
    assert resolve_mesh(urdf, "other/x.stl") is None  # a sibling folder is not the URDF's
