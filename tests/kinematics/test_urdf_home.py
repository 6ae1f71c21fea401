"""A URDF robot opens at a start pose the app calls regular (κ ≤ 50 of the task rows, within the limits)
when one is near the file's zero, and its description says which pose and its κ."""

from __future__ import annotations

import re

import numpy as np
import pytest
from locations import DATA

import kinematics
import robots
from kinematics.analysis import condition_number, task_rows
from kinematics.urdf import robot_from_urdf_string, to_urdf
from kinematics.urdf.build import HOME_GOOD_RATIO


def kappa(robot, q) -> float:
    return float(condition_number(kinematics.jacobian(robot, q), task_rows(robot)))


@pytest.mark.parametrize("name", ["iiwa14_like.urdf", "xarm7_like.urdf"])
def test_singular_zero_poses_open_regular_and_say_so(name):
    robot = robots.load(DATA / name)
    home = robot.configurations[0]
    assert home.name == "home"
    k = kappa(robot, home.q)
    assert k <= 1 / HOME_GOOD_RATIO  # κ ≤ 50: no amber banner on opening
    lo, hi = robot.qlim
    assert np.all(home.q >= lo) and np.all(home.q <= hi)
    assert kappa(robot, np.zeros(robot.dof)) > 1e6  # the file's zero is singular (a straight arm)
    said = re.search(r"moved to κ = ([0-9.e+]+)", home.description)
    assert said and float(said.group(1)) == pytest.approx(k, rel=5e-3)
    assert "singular" in home.description  # what the zero pose was
    assert all(
        f"{j} " in home.description for j in robot.joint_names if home.q[robot.joint_names.index(j)] != 0
    )


@pytest.mark.parametrize("name", ["puma560", "ur5", "panda", "stanford"])
def test_urdf_of_a_library_robot_starts_regular(name):
    """URDFs written from the library's DH robots: the start pose is regular and near the zero pose."""
    robot = robot_from_urdf_string(to_urdf(robots.load(name)))
    home = robot.configurations[0]
    assert kappa(robot, home.q) <= 50
    assert np.abs(home.q).max() <= 1.0 or kappa(robot, np.zeros(robot.dof)) <= 50


def test_start_pose_is_deterministic():
    a = robots.load(DATA / "iiwa14_like.urdf").configurations[0].q
    b = robots.load(DATA / "iiwa14_like.urdf").configurations[0].q
    np.testing.assert_array_equal(a, b)
