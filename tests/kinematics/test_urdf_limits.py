"""URDF limits the file does not say plainly: Bullet's lower > upper ("no limit") and lower = upper (a
joint that may not move)."""

from __future__ import annotations

import numpy as np
import pytest

from kinematics import fk, jacobian
from kinematics.urdf import chains, robot_from_urdf_string

_ARM = (
    '<robot name="r"><link name="base"/><link name="a"/><link name="b"/><link name="tip"/>'
    '<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>'
    '<limit lower="{lo1}" upper="{hi1}"/></joint>'
    '<joint name="j2" type="{kind2}"><parent link="a"/><child link="b"/><origin xyz="0.5 0 0"/>'
    '<axis xyz="0 1 0"/><limit lower="{lo2}" upper="{hi2}"/></joint>'
    '<joint name="j3" type="revolute"><parent link="b"/><child link="tip"/><origin xyz="0 0 0.4"/>'
    '<axis xyz="0 1 0"/><limit lower="-1" upper="1"/></joint>'
    '<link name="end"/><joint name="to_end" type="fixed"><parent link="tip"/><child link="end"/>'
    '<origin xyz="0.3 0 0"/></joint></robot>'
)


def _arm(lo1="-1", hi1="1", kind2="revolute", lo2="-1", hi2="1") -> str:
    return _ARM.format(lo1=lo1, hi1=hi1, kind2=kind2, lo2=lo2, hi2=hi2)


def test_bullets_lower_above_upper_is_unlimited_with_a_note():
    robot = robot_from_urdf_string(_arm(lo1="1", hi1="-1"))
    assert robot.joints[0].qlim is None and robot.joints[1].qlim == (-1.0, 1.0)
    assert (
        "Joint 'j1': <limit> lower=1 is above upper=-1 (Bullet's way of writing no limit): read as unlimited."
        in (robot.description)
    )
    assert "Bullet" not in robot_from_urdf_string(_arm()).description


@pytest.mark.parametrize(("kind", "value"), [("revolute", 0.7), ("prismatic", 0.25)])
def test_lower_equal_upper_holds_the_joint_fixed_there(kind, value):
    held = robot_from_urdf_string(_arm(kind2=kind, lo2=str(value), hi2=str(value)))
    assert held.joint_names == ("j1", "j3") and held.dof == 2
    assert f"Joint 'j2': <limit> lower = upper = {value:g}, a joint that may not move: held there" in (
        held.description
    )
    # the same arm with j2 free: the held arm is it with q2 = value, its J the free J without column 2
    free = robot_from_urdf_string(_arm(kind2=kind, lo2="-1", hi2="1"))
    for q in np.random.default_rng(1).uniform(-1, 1, (20, 2)):
        full = np.array([q[0], value, q[1]])
        np.testing.assert_allclose(fk(held, q), fk(free, full), atol=1e-12)
        np.testing.assert_allclose(jacobian(held, q), jacobian(free, full)[:, [0, 2]], atol=1e-12)


def test_a_chain_of_only_held_joints_says_it_has_no_moving_joint(tmp_path):
    text = _arm(lo1="0.2", hi1="0.2", lo2="-0.1", hi2="-0.1").replace(
        'lower="-1" upper="1"/></joint><link name="end"', 'lower="0.4" upper="0.4"/></joint><link name="end"'
    )
    with pytest.raises(ValueError, match="no moving joint"):
        robot_from_urdf_string(text)
    path = tmp_path / "held.urdf"
    path.write_text(_arm(lo2="0.3", hi2="0.3"))
    assert chains(path)[0].joints == ("j1", "j3")


def _pendulum(limit: str) -> str:
    """example-robot-data's double_pendulum.urdf (SolidWorks exporter): two revolute joints, each with
    ``limit`` (there ``<limit lower="0" upper="0" effort="0" velocity="0"/>``)."""
    return (
        '<robot name="double_pendulum"><link name="base_link"/><link name="link1"/><link name="link2"/>'
        '<joint name="joint1" type="revolute"><origin xyz="0.006 0 0.035"/><parent link="base_link"/>'
        f'<child link="link1"/><axis xyz="1 0 0"/>{limit}</joint>'
        '<joint name="joint2" type="revolute"><origin xyz="0.015 0 0.2"/><parent link="link1"/>'
        f'<child link="link2"/><axis xyz="1 0 0"/>{limit}</joint></robot>'
    )


@pytest.mark.parametrize(
    "limit",
    [
        '<limit lower="0" upper="0" effort="0" velocity="0"/>',  # double_pendulum.urdf, written out
        '<limit effort="35" velocity="20.0"/>',  # centauro.urdf's wheels: lower and upper left out
        '<limit lower="-0" upper="0.0" effort="1" velocity="1"/>',
    ],
)
def test_lower_equal_upper_zero_gives_no_range_the_joint_moves_unlimited(limit):
    robot = robot_from_urdf_string(_pendulum(limit))
    assert robot.joint_names == ("joint1", "joint2")
    assert all(j.qlim is None for j in robot.joints)
    assert (
        "Joint 'joint1': <limit> gives no range (lower = upper = 0, or both left out): read as unlimited."
        in robot.description
    )
    # it is the same pendulum as one with its joints written continuous: same fk and J everywhere
    free = robot_from_urdf_string(_pendulum("").replace('type="revolute"', 'type="continuous"'))
    assert "gives no range" not in free.description
    for q in np.random.default_rng(2).uniform(-3, 3, (20, 2)):
        np.testing.assert_allclose(fk(robot, q), fk(free, q), atol=1e-12)
        np.testing.assert_allclose(jacobian(robot, q), jacobian(free, q), atol=1e-12)


def test_a_prismatic_joint_with_no_range_moves_and_a_held_nonzero_one_does_not():
    robot = robot_from_urdf_string(_arm(kind2="prismatic", lo2="0", hi2="0"))
    assert robot.joint_names == ("j1", "j2", "j3") and robot.joints[1].qlim is None
    held = robot_from_urdf_string(_arm(kind2="prismatic", lo2="0.1", hi2="0.1"))
    assert held.joint_names == ("j1", "j3")
