"""Real-world URDF patterns (tests/data/urdf/): each opens with no tip, on the right chain, with exact kinematics.

References are independent of our reader: yourdfpy's own scene graph for fk (its parser, its
transforms), central finite differences of that for J, and numbers derived by hand from the files.
"""

from __future__ import annotations

import functools
import logging
import math
from pathlib import Path

import locations
import numpy as np
import pytest

import robots
from kinematics import Robot, fk, jacobian
from kinematics.errors import UrdfError
from kinematics.urdf import chains, robot_from_urdf, robot_from_urdf_string

DATA = locations.DATA / "urdf"
logging.getLogger("yourdfpy").setLevel(logging.ERROR)


@functools.cache
def _yourdfpy(path: Path):
    import yourdfpy

    return yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=False)


def reference_fk(path: Path, robot: Robot, q: np.ndarray, base: str, tip: str) -> np.ndarray:
    """T_base_tip from yourdfpy's scene graph (the joint values by name; mimic joints follow)."""
    urdf = _yourdfpy(path)
    urdf.update_cfg({name: float(v) for name, v in zip(robot.joint_names, q, strict=True)})
    return urdf.get_transform(frame_to=tip, frame_from=base)


def reference_jacobian(path: Path, robot: Robot, q: np.ndarray, base: str, tip: str, h=1e-6) -> np.ndarray:
    """Central differences of the yourdfpy transforms: position rows and ω from Ṙ Rᵀ."""
    J = np.zeros((6, robot.dof))
    for k in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[k] = h
        Tp = reference_fk(path, robot, q + dq, base, tip)
        Tm = reference_fk(path, robot, q - dq, base, tip)
        J[:3, k] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ reference_fk(path, robot, q, base, tip)[:3, :3].T
        J[3:, k] = [W[2, 1], W[0, 2], W[1, 0]]
    return J


def check_against_yourdfpy(path: Path, robot: Robot, base: str, tip: str, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    for _ in range(3):
        q = rng.uniform(-1, 1, robot.dof) * np.where(np.array(robot.joint_types) == "revolute", 1.0, 0.02)
        np.testing.assert_allclose(fk(robot, q), reference_fk(path, robot, q, base, tip), atol=1e-12)
        np.testing.assert_allclose(
            jacobian(robot, q), reference_jacobian(path, robot, q, base, tip), atol=1e-8
        )


# ------------------------------------------------------------------ xacro output, tool0
def test_xacro_header_file_opens_at_tool0_with_six_joints():
    path = DATA / "ur5_xacro.urdf"
    robot = robot_from_urdf(path)
    assert robot.name == "ur5" and robot.dof == 6
    assert robot.joint_names[0] == "shoulder_pan_joint" and robot.joint_names[-1] == "wrist_3_joint"
    assert "'base_link' to link 'tool0'" in robot.description and "tool0" in robot.description
    # By hand from the file at q = 0: the two pitches of π/2 (shoulder_lift, wrist_1) turn z into
    # x and then into −z, so x = 0.425 + 0.39225, y = 0.13585 − 0.1197 + 0.093 + 0.0823,
    # z = 0.089159 − 0.09465 (UR's published zero pose: a2 + a3, d4 + d6, d1 − d5 in magnitude),
    # and R = Ry(π) Rx(−π/2) with tool0's roll of −π/2.
    T = fk(robot, np.zeros(6))
    np.testing.assert_allclose(T[:3, 3], [0.81725, 0.19145, -0.005491], atol=1e-9)
    np.testing.assert_allclose(T[:3, :3], [[-1, 0, 0], [0, 0, 1], [0, 1, 0]], atol=1e-9)
    check_against_yourdfpy(path, robot, "base_link", "tool0")


def test_robots_load_passes_the_chain_ends_through():
    path = DATA / "ur5_xacro.urdf"
    robot = robots.load(path, base_link="shoulder_link", tip_link="wrist_2_link")
    assert robot.joint_names == ("shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint")
    check_against_yourdfpy(path, robot, "shoulder_link", "wrist_2_link")


# ------------------------------------------------------------------ sibling-branch mimic gripper
def test_gripper_default_chain_ends_at_the_hand_not_a_finger():
    robot = robot_from_urdf(DATA / "gripper_arm.urdf")
    assert robot.joint_names == ("j1", "j2", "j3")
    assert "to link 'hand'" in robot.description


def test_chains_lists_the_default_and_every_leaf():
    infos = chains(DATA / "gripper_arm.urdf")
    assert [(c.tip_link, c.dof, c.is_default) for c in infos] == [
        ("hand", 3, True),
        ("left_finger", 4, False),
        ("right_finger", 4, False),
    ]
    assert infos[2].joints == ("j1", "j2", "j3", "finger_joint1")
    assert all(c.base_link == "base" for c in infos)


def test_finger_on_the_mimic_branch_is_driven_by_its_leader():
    """right_finger moves by finger_joint2 = 1.5 · finger_joint1 + 0.01 along −y of the hand."""
    path = DATA / "gripper_arm.urdf"
    robot = robot_from_urdf(path, tip_link="right_finger")
    assert robot.joint_names == ("j1", "j2", "j3", "finger_joint1") and robot.dof == 4
    assert [ax.name for ax in robot.axes] == ["j1", "j2", "j3", "finger_joint2"]
    finger = robot.axes[3]
    assert (finger.joint_index, finger.multiplier, finger.offset) == (3, 1.5, 0.01)
    q = np.array([0.3, -0.4, 0.5, 0.02])
    hand = robot_from_urdf(path)  # the same chain up to the hand
    R_hand = fk(hand, q[:3])[:3, :3]
    slide = 1.5 * 0.02 + 0.01
    expected = fk(hand, q[:3])[:3, 3] + R_hand @ np.array([0.0, -slide, 0.06])
    np.testing.assert_allclose(fk(robot, q)[:3, 3], expected, atol=1e-12)
    # Its column: 1.5 × the finger's unit axis (−y of the hand) in base axes; no rotation.
    np.testing.assert_allclose(
        jacobian(robot, q)[:, 3], np.r_[1.5 * (R_hand @ [0, -1.0, 0]), 0, 0, 0], atol=1e-12
    )
    check_against_yourdfpy(path, robot, "base", "right_finger")


def test_chained_mimic_multiplies_through():
    text = """<robot name="m"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
      <joint name="lead" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
      <joint name="f1" type="revolute"><parent link="a"/><child link="c"/><axis xyz="0 0 1"/>
        <mimic joint="lead" multiplier="2" offset="0.1"/></joint>
      <joint name="f2" type="revolute"><parent link="c"/><child link="d"/><origin xyz="1 0 0"/><axis xyz="0 0 1"/>
        <mimic joint="f1" multiplier="-3" offset="0.2"/></joint></robot>"""
    robot = robot_from_urdf_string(text, tip_link="d")
    # f1 = 2 lead + 0.1; f2 = −3 f1 + 0.2 = −6 lead − 0.1.
    assert robot.joint_names == ("lead",)
    assert [(ax.multiplier, ax.offset) for ax in robot.axes] == [(2.0, 0.1), (-6.0, pytest.approx(-0.1))]
    q = 0.25
    angle = 2 * q + 0.1  # the tip sits at the end of f1's unit link
    np.testing.assert_allclose(fk(robot, [q])[:2, 3], [math.cos(angle), math.sin(angle)], atol=1e-12)


# ------------------------------------------------------------------ geometry the kinematics ignores
def test_capsule_plane_and_unknown_tags_do_not_matter():
    robot = robot_from_urdf(DATA / "odd_geometry.urdf")
    assert robot.name == "odd geometry & <tags>"  # from <robot name>, not the file stem
    assert robot.joint_names == ("j1", "j2") and robot.joints[0].qlim is None  # continuous
    np.testing.assert_allclose(fk(robot, [math.pi / 2, 0.0])[:3, 3], [0.0, 0.5, 0.0], atol=1e-12)


# ------------------------------------------------------------------ ±1e16 sentinels, no home at zero
def test_sentinel_limits_mean_unlimited_and_continuous_loads():
    robot = robot_from_urdf(DATA / "sentinel_limits.urdf")
    assert [j.qlim for j in robot.joints] == [None, None, None]
    assert robot.joint_types == ("revolute", "revolute", "prismatic")
    assert np.isfinite(robot.home).all()


def _task_ratio(robot: Robot, q: np.ndarray) -> float:
    s = np.linalg.svd(jacobian(robot, q)[:3], compute_uv=False)  # 3 joints: the task is the position
    return s[-1] / s[0]


def test_no_home_at_a_singular_zero_pose():
    robot = robot_from_urdf(DATA / "singular_at_zero.urdf")
    assert _task_ratio(robot, np.zeros(3)) < 1e-12  # the file's zero pose is singular...
    home = robot.configuration("home")
    assert _task_ratio(robot, home) > 1e-3  # ...the start pose is not
    lo, hi = robot.qlim
    assert np.all(lo <= home) and np.all(home <= hi)
    assert np.abs(home).max() < 1.0  # a nudge, not a random pose
    assert np.array_equal(robot_from_urdf(DATA / "singular_at_zero.urdf").home, home)  # deterministic


def test_a_regular_zero_pose_is_kept_as_home():
    text = """<robot name="bent"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
      <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
      <joint name="j2" type="revolute"><parent link="b"/><child link="c"/><origin xyz="1 0 0" rpy="0 0 0.5"/>
        <axis xyz="0 0 1"/></joint>
      <joint name="t" type="fixed"><parent link="c"/><child link="d"/><origin xyz="1 0 0"/></joint></robot>"""
    robot = robot_from_urdf_string(text)
    s = np.linalg.svd(jacobian(robot, np.zeros(2))[:2], compute_uv=False)  # det = sin(0.5): regular
    assert s[-1] / s[0] > 1e-3
    np.testing.assert_array_equal(robot.home, np.zeros(2))
    assert robot.configurations[0].description.startswith("Start pose: the file's zero joint values (κ = ")


def test_a_home_clipped_into_limits_that_exclude_zero():
    text = """<robot name="z"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
      <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <limit lower="0.5" upper="1.5"/></joint>
      <joint name="j2" type="revolute"><parent link="b"/><child link="c"/><origin xyz="1 0 0"/><axis xyz="0 0 1"/>
        <limit lower="-1.0" upper="-0.001"/></joint>
      <joint name="t" type="fixed"><parent link="c"/><child link="d"/><origin xyz="1 0 0"/></joint></robot>"""
    robot = robot_from_urdf_string(text)
    lo, hi = robot.qlim
    assert np.all(lo <= robot.home) and np.all(robot.home <= hi)
    # Clipped zeros (0.5, −0.001) are nearly stretched (σmin/σmax ≈ 2.5e-4); the nudge bends the elbow.
    s = np.linalg.svd(jacobian(robot, robot.home)[:2], compute_uv=False)  # vz ≡ 0: the x-y rows
    assert s[-1] / s[0] > 1e-3
    s0 = np.linalg.svd(jacobian(robot, [0.5, -0.001])[:2], compute_uv=False)
    assert s0[-1] / s0[0] < 1e-3


# ------------------------------------------------------------------ which tip by default
def _tree(*leaves: str, extra: str = "") -> str:
    """base → j1 → a → j2 → b, then one revolute joint from b to each leaf (3 moving joints each)."""
    links = "".join(f'<link name="{n}"/>' for n in ("base", "a", "b", *leaves))
    joints = (
        '<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/></joint>'
        '<joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="1 0 0"/><axis xyz="0 1 0"/></joint>'
    )
    joints += "".join(
        f'<joint name="to_{n}" type="revolute"><parent link="b"/><child link="{n}"/><origin xyz="0 0 {i + 1}"/>'
        f'<axis xyz="1 0 0"/></joint>'
        for i, n in enumerate(leaves)
    )
    return f'<robot name="t">{links}{joints}{extra}</robot>'


@pytest.mark.parametrize(
    ("leaves", "tip"),
    [
        (("zeta", "TOOL0", "panda_hand", "arm_tcp"), "TOOL0"),
        (("zeta", "flange", "panda_hand", "arm_tcp"), "arm_tcp"),
        (("zeta", "ee_link", "panda_hand", "flange"), "flange"),
        (("zeta", "left_hand", "ee_link"), "ee_link"),
        (("zeta", "left_hand", "alpha"), "left_hand"),
        (("zeta", "alpha"), "zeta"),  # no name: equal joint counts, the first leaf in file order
        (("finger_left", "omega"), "omega"),  # a finger never ends the arm
    ],
)
def test_default_tip_preference(leaves, tip):
    robot = robot_from_urdf_string(_tree(*leaves))
    assert f"to link '{tip}'" in robot.description
    assert robot.dof == 3


def test_a_floating_root_joint_moves_the_default_base_below_it():
    extra = '<link name="world"/><joint name="float" type="floating"><parent link="world"/><child link="base"/></joint>'
    robot = robot_from_urdf_string(_tree("tool0", extra=extra))
    assert "from link 'base' to link 'tool0'" in robot.description and robot.dof == 3
    with pytest.raises(UrdfError, match="joint 'float' is floating: only revolute"):
        robot_from_urdf_string(_tree("tool0", extra=extra), base_link="world")


def test_a_leaf_with_more_moving_joints_wins_without_names():
    text = _tree("short", "long_base").replace("</robot>", "") + (
        '<link name="long_end"/><joint name="j9" type="prismatic"><parent link="long_base"/>'
        '<child link="long_end"/><axis xyz="0 0 1"/><limit lower="0" upper="1"/></joint></robot>'
    )
    robot = robot_from_urdf_string(text)
    assert robot.joint_names == ("j1", "j2", "to_long_base", "j9")
