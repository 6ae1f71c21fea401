"""The default chain of real robots' trees, rebuilt with their link and joint names (no network): a
humanoid's ``middle_*`` spine is no finger, and PR2, pybullet's Panda, TIAGo and the Interbotix arms
open at their tool frame, not at a palm or an arm link."""

from __future__ import annotations

import numpy as np
import pytest

from kinematics import fk, jacobian
from kinematics.urdf import chains, robot_from_urdf_string

_AXES = ("0 0 1", "0 1 0", "1 0 0")


def _urdf(name: str, joints: list[tuple[str, str, str, str]]) -> str:
    """A URDF of ``(joint, type, parent, child)``, each child 0.1 m along z (and a little x) from its
    parent, axes cycling z, y, x; prismatic joints limited to [0, 0.05] m."""
    links = []
    for _, _, parent, child in joints:
        for link in (parent, child):
            if link not in links:
                links.append(link)
    out = [f'<robot name="{name}">', *(f'<link name="{link}"/>' for link in links)]
    for i, (joint, kind, parent, child) in enumerate(joints):
        limit = '<limit lower="0" upper="0.05"/>' if kind == "prismatic" else ""
        limit = '<limit lower="-2" upper="2"/>' if kind == "revolute" else limit
        out.append(
            f'<joint name="{joint}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="0.02 0 0.1"/><axis xyz="{_AXES[i % 3]}"/>{limit}</joint>'
        )
    out.append("</robot>")
    return "".join(out)


def _arm(prefix: str, parent: str, names: list[str], last: str) -> list[tuple[str, str, str, str]]:
    """Revolute joints ``prefix + name`` from ``parent``, link ``prefix + name + _link``, the last link named ``last``."""
    out, at = [], parent
    for k, n in enumerate(names):
        child = last if k == len(names) - 1 else f"{prefix}{n}_link"
        out.append((f"{prefix}{n}_joint", "revolute", at, child))
        at = child
    return out


def _opens(text: str, tip: str, joints: tuple[str, ...]) -> None:
    robot = robot_from_urdf_string(text)
    assert f"to link '{tip}'" in robot.description, robot.description
    assert robot.joint_names == joints
    default = chains_of(text)[0]
    assert default.is_default and default.tip_link == tip
    q = np.random.default_rng(0).uniform(-0.5, 0.5, robot.dof)
    assert np.isfinite(jacobian(robot, q)).all() and np.isfinite(fk(robot, q)).all()


def chains_of(text: str):
    import os
    import tempfile

    with tempfile.NamedTemporaryFile("w", suffix=".urdf", delete=False) as f:
        f.write(text)
    try:
        return chains(f.name)
    finally:
        os.unlink(f.name)


def _humanoid() -> list[tuple[str, str, str, str]]:
    """pybullet_data's human.urdf shape: legs from the pelvis, a ``middle_*`` spine up to the chest, two
    arms ending at a hand and a neck from the chest."""
    j = [
        ("middle_spine_1_joint", "revolute", "pelvis", "middle_body_1"),
        ("middle_spine_2_joint", "revolute", "middle_body_1", "chest"),
        ("neck_joint", "revolute", "chest", "head"),
    ]
    for side in ("left", "right"):  # legs: three moving joints each, more than the arm's chain below
        j += _arm(f"{side}_", "pelvis", ["hip_x", "hip_y", "hip_z", "knee", "ankle"], f"{side}_foot")
        j += _arm(f"{side}_", "chest", ["shoulder", "elbow", "wrist"], f"{side}_hand")
    return j


def test_a_humanoids_middle_spine_is_no_finger_the_arm_through_it_opens():
    _opens(
        _urdf("human", _humanoid()),
        "left_hand",
        (
            "middle_spine_1_joint",
            "middle_spine_2_joint",
            "left_shoulder_joint",
            "left_elbow_joint",
            "left_wrist_joint",
        ),
    )


def test_a_hands_fingers_named_only_index_middle_ring_are_still_fingers():
    joints = _arm("", "base", ["j1", "j2", "j3"], "palm")
    for finger in ("index", "middle", "ring", "little"):
        joints += [
            (f"{finger}_1_joint", "revolute", "palm", f"{finger}_1"),
            (f"{finger}_2_joint", "revolute", f"{finger}_1", f"{finger}_2"),
        ]
    _opens(_urdf("hand_arm", joints), "palm", ("j1_joint", "j2_joint", "j3_joint"))


def _pr2() -> list[tuple[str, str, str, str]]:
    j = [
        ("base_footprint_joint", "fixed", "base_footprint", "base_link"),
        ("torso_lift_joint", "prismatic", "base_link", "torso_lift_link"),
        ("head_pan_joint", "revolute", "torso_lift_link", "head_pan_link"),
        ("head_tilt_joint", "revolute", "head_pan_link", "head_tilt_link"),
    ]
    for s in ("r", "l"):
        names = [
            "shoulder_pan",
            "shoulder_lift",
            "upper_arm_roll",
            "elbow_flex",
            "forearm_roll",
            "wrist_flex",
        ]
        j += _arm(f"{s}_", "torso_lift_link", [*names, "wrist_roll"], f"{s}_wrist_roll_link")
        j += [
            (f"{s}_gripper_palm_joint", "fixed", f"{s}_wrist_roll_link", f"{s}_gripper_palm_link"),
            (
                f"{s}_gripper_l_finger_joint",
                "revolute",
                f"{s}_gripper_palm_link",
                f"{s}_gripper_l_finger_link",
            ),
            (
                f"{s}_gripper_l_finger_tip_joint",
                "revolute",
                f"{s}_gripper_l_finger_link",
                f"{s}_gripper_l_finger_tip_link",
            ),
            (
                f"{s}_gripper_r_finger_joint",
                "revolute",
                f"{s}_gripper_palm_link",
                f"{s}_gripper_r_finger_link",
            ),
            (f"{s}_gripper_tool_joint", "fixed", f"{s}_gripper_palm_link", f"{s}_gripper_tool_frame"),
        ]
    return j


def test_pr2_opens_at_a_gripper_tool_frame_with_the_torso_and_seven_arm_joints():
    names = ["shoulder_pan", "shoulder_lift", "upper_arm_roll", "elbow_flex", "forearm_roll", "wrist_flex"]
    arm = tuple(f"l_{n}_joint" for n in [*names, "wrist_roll"])
    _opens(_urdf("pr2", _pr2()), "l_gripper_tool_frame", ("torso_lift_joint", *arm))


def test_pybullets_panda_opens_at_its_grasp_target_below_the_hand():
    j = _arm("panda_", "panda_link0", [f"j{k}" for k in range(1, 8)], "panda_link7")
    j += [
        ("panda_joint8", "fixed", "panda_link7", "panda_link8"),
        ("panda_hand_joint", "fixed", "panda_link8", "panda_hand"),
        ("panda_finger_joint1", "prismatic", "panda_hand", "panda_leftfinger"),
        ("panda_finger_joint2", "prismatic", "panda_hand", "panda_rightfinger"),
        ("panda_grasptarget_hand", "fixed", "panda_hand", "panda_grasptarget"),
    ]
    _opens(_urdf("panda", j), "panda_grasptarget", tuple(f"panda_j{k}_joint" for k in range(1, 8)))


def test_tiago_opens_at_arm_tool_link():
    j = [
        ("base_footprint_joint", "fixed", "base_footprint", "base_link"),
        ("wheel_left_joint", "continuous", "base_link", "wheel_left_link"),
        ("wheel_right_joint", "continuous", "base_link", "wheel_right_link"),
        ("torso_lift_joint", "prismatic", "base_link", "torso_lift_link"),
        ("head_1_joint", "revolute", "torso_lift_link", "head_1_link"),
        ("head_2_joint", "revolute", "head_1_link", "head_2_link"),
    ]
    j += _arm("arm_", "torso_lift_link", [str(k) for k in range(1, 8)], "arm_7_link")
    j += [
        ("arm_tool_joint", "fixed", "arm_7_link", "arm_tool_link"),
        ("wrist_ft_joint", "fixed", "arm_tool_link", "wrist_ft_link"),
        ("gripper_joint", "fixed", "wrist_ft_link", "gripper_link"),
        ("gripper_left_finger_joint", "prismatic", "gripper_link", "gripper_left_finger_link"),
        ("gripper_right_finger_joint", "prismatic", "gripper_link", "gripper_right_finger_link"),
        ("gripper_grasping_frame_joint", "fixed", "gripper_link", "gripper_grasping_frame"),
    ]
    _opens(_urdf("tiago", j), "arm_tool_link", ("torso_lift_joint", *(f"arm_{k}_joint" for k in range(1, 8))))


def test_an_interbotix_arm_opens_at_ee_gripper_link_past_its_gripper_joint():
    p = "wx250s/"
    names = ["waist", "shoulder", "elbow", "forearm_roll", "wrist_angle", "wrist_rotate"]
    j = [
        (n, "revolute", f"{p}base_link" if k == 0 else f"{p}{names[k - 1]}_link", f"{p}{n}_link")
        for k, n in enumerate(names)
    ]
    j += [
        ("ee_arm", "fixed", f"{p}wrist_rotate_link", f"{p}ee_arm_link"),
        ("gripper", "continuous", f"{p}ee_arm_link", f"{p}gripper_prop_link"),
        ("gripper_bar", "fixed", f"{p}ee_arm_link", f"{p}gripper_bar_link"),
        ("ee_bar", "fixed", f"{p}gripper_bar_link", f"{p}fingers_link"),
        ("left_finger", "prismatic", f"{p}fingers_link", f"{p}left_finger_link"),
        ("right_finger", "prismatic", f"{p}fingers_link", f"{p}right_finger_link"),
        ("ee_gripper", "fixed", f"{p}fingers_link", f"{p}ee_gripper_link"),
    ]
    _opens(_urdf("wx250s", j), f"{p}ee_gripper_link", tuple(names))


@pytest.mark.parametrize(
    "tip", ["r_gripper_tool_frame", "arm_tool_link", "ee_gripper_link", "panda_grasptarget", "tool_frame"]
)
def test_a_tool_frame_ranks_below_ee_link_and_above_a_hand(tip):
    j = _arm("", "base", ["a", "b"], "wrist")
    j += [(f"to_{tip}", "fixed", "wrist", tip), ("to_hand", "revolute", "wrist", "left_hand")]
    _opens(_urdf("t", j), tip, ("a_joint", "b_joint"))
    j += [("to_ee", "fixed", "wrist", "ee_link")]
    _opens(_urdf("t", j), "ee_link", ("a_joint", "b_joint"))


def test_a_hand_whose_fingers_hang_from_a_fixed_thumb_base_opens_at_the_hands_frame():
    """example-robot-data's alex_psyonic_hands.urdf: the arm ends at LeftGripperYawLink, the hand's frame
    LeftPsyonicAbilityBaseLink is fixed below it, and a fixed Left_thumb_base below that carries every
    finger (index/middle/ring/pinky/thumb). The chain opened ends at the hand's frame, not at a link named
    after the thumb."""
    names = [
        "ShoulderPitch",
        "ShoulderRoll",
        "ShoulderYaw",
        "ElbowPitch",
        "WristYaw",
        "WristRoll",
        "GripperYaw",
    ]
    j, at = [], "Torso"
    for n in names:
        j.append((f"Left{n}", "revolute", at, f"Left{n}Link"))
        at = f"Left{n}Link"
    j += [
        ("leftGrippertAttachmentFixedJoint", "fixed", at, "LeftPsyonicAbilityBaseLink"),
        ("Left_wrist2thumb", "fixed", "LeftPsyonicAbilityBaseLink", "Left_thumb_base"),
    ]
    for finger in ("index", "middle", "ring", "pinky", "thumb"):
        j += [
            (f"Left_{finger}_q1", "revolute", "Left_thumb_base", f"Left_{finger}_L1"),
            (f"Left_{finger}_q2", "revolute", f"Left_{finger}_L1", f"Left_{finger}_L2"),
        ]
    text = _urdf("alex", j)
    _opens(text, "LeftPsyonicAbilityBaseLink", tuple(f"Left{n}" for n in names))
    listed = [(c.tip_link, c.dof) for c in chains_of(text)]
    assert ("Left_thumb_base", 7) not in listed and listed[0] == ("LeftPsyonicAbilityBaseLink", 7)
    # the finger chains are still offered, whole
    assert ("Left_index_L2", 9) in listed and ("Left_thumb_L2", 9) in listed
