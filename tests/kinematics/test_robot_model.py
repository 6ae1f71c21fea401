"""The Robot model's own checks: axes, the chain, read-only arrays, and the course names of the
symbolic parameters (Robot.param_names, read from the robot files' [symbols] table, checked, and
used by the symbolic model)."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
import sympy as sp

import robots
from kinematics import Axis, Joint, NamedConfiguration, Robot, RobotDefinitionError, symbolic

ROW = dict(joint="revolute", a=0.5, alpha=0.0, d=0.0, theta=0.0)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"multiplier": math.nan}, "axis 'j', multiplier: expected a finite number, got nan"),
        ({"multiplier": 1e7}, r"axis 'j', multiplier: 1e\+07  is out of range; expected \|value\| ≤ 1e\+06"),
        ({"offset": 2e15, "kind": "prismatic"}, r"axis 'j', offset: 2e\+15 m is out of range"),
        ({"kind": "revolve"}, "axis 'j', kind: expected one of 'revolute', 'prismatic', got 'revolve'"),
        ({"joint_index": True}, "axis 'j', joint_index: expected an int, got True"),
        (
            {"T_parent_joint": np.diag([1.0, 1.0, -1.0, 1.0])},
            "axis 'j', T_parent_joint: the upper-left 3×3 block is not a rotation",
        ),
        ({"T_joint_child": np.full((4, 4), np.nan)}, "axis 'j', T_joint_child: contains a non-finite number"),
        ({"corners": ((0.0, math.inf, 0.0),)}, "axis 'j', corners: expected a finite number, got inf"),
    ],
)
def test_bad_axis(changes, message):
    fields = dict(
        name="j",
        kind="revolute",
        joint_index=0,
        multiplier=1.0,
        offset=0.0,
        T_parent_joint=np.eye(4),
        T_joint_child=np.eye(4),
    )
    with pytest.raises(RobotDefinitionError, match=message):
        Axis(**{**fields, **changes})


def test_chain_checks():
    ax = Axis("j", "revolute", 0, 1.0, 0.0, np.eye(4), np.eye(4))
    with pytest.raises(RobotDefinitionError, match="robot 'r': joint\\(s\\) 'idle' drive no axis"):
        Robot("r", (Joint("j", "revolute"), Joint("idle", "revolute")), (ax,))
    with pytest.raises(RobotDefinitionError, match="robot 'r', axes\\[0\\]: expected a Axis, got 'j'"):
        Robot("r", (Joint("j", "revolute"),), ("j",))  # type: ignore[arg-type]
    with pytest.raises(RobotDefinitionError, match="joint name: expected a non-empty string"):
        Joint("", "revolute")
    with pytest.raises(RobotDefinitionError, match="the chain has 1001 moving axes; at most 1000"):
        Robot.from_dh([ROW] * 1001)


def test_model_arrays_are_read_only():
    robot = Robot.from_dh([ROW], configurations=[NamedConfiguration("home", [0.5])], param_names={"a1": "l1"})
    for array in (robot.base, robot.tool, robot.axes[0].T_joint_child, robot.home):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 1.0
    with pytest.raises(TypeError):
        robot.param_names["a1"] = "L1"  # type: ignore[index]


@pytest.mark.parametrize(
    ("names", "message"),
    [
        ({"a_1": "l1"}, "param_names: key 'a_1' is not a parameter name; expected a\\{k\\}"),
        ({"a1": "l 1"}, "param_names, 'a1': expected a letter then up to 15 letters or digits"),
        ({"a1": "q2"}, "param_names, 'a1': .*not a joint symbol q1"),
        ({"a1": "pi"}, "param_names, 'a1': .*nor pi, E, I"),
        ({"a1": "d2"}, "param_names, 'a1': 'd2' is itself a default parameter name"),
        ({"a1": "L", "a2": "L"}, "param_names, 'a2': the name 'L' is given twice"),
        ({"a1": 'l"""'}, "param_names, 'a1': expected a letter"),
        (["a1"], "param_names: expected a mapping of parameter names"),
    ],
)
def test_bad_param_names(names, message):
    with pytest.raises(RobotDefinitionError, match=message):
        Robot.from_dh([ROW, ROW], name="two", param_names=names)


def test_robot_file_symbols_table(tmp_path):
    base = (
        'name = "arm"\ntitle = ""\ndescription = ""\nsource = ""\nconvention = "standard"\n{symbols}\n'
        '[[joints]]\njoint = "revolute"\na = 1.0\nalpha = 0.0\nd = 0.0\ntheta = 0.0\n'
    )
    path = tmp_path / "arm.toml"
    path.write_text(base.format(symbols='[symbols]\na1 = "L"\n'))
    assert dict(robots.load_file(path).param_names) == {"a1": "L"}
    path.write_text(base.format(symbols="[symbols]\na1 = 3\n"))
    with pytest.raises(
        RobotDefinitionError, match="arm.toml, \\[symbols\\] key 'a1': expected a string, got 3"
    ):
        robots.load_file(path)
    path.write_text(base.format(symbols='[symbols]\na1 = "q1"\n'))
    with pytest.raises(RobotDefinitionError, match="^arm.toml: robot 'arm', param_names, 'a1'"):
        robots.load_file(path)


def test_library_course_names_come_from_the_robot_files():
    assert dict(robots.load("trr").param_names) == {"a1": "l1", "a2": "l2", "a3": "l3"}
    assert dict(robots.load("elbow3r").param_names) == {"a1": "L1", "a2": "L2", "xt": "L3"}
    assert dict(robots.load("puma560").param_names) == {}


def test_symbolic_model_uses_the_robot_names_not_the_library_name():
    """A robot called "trr" gets course names only from its own param_names, whatever its name."""
    row = dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)
    q1, q2 = sp.symbols("q1 q2", real=True)
    named = Robot.from_dh([row, row], name="trr", planar=True, param_names={"a1": "L", "a2": "M"})
    L, M = sp.symbols("L M", real=True)
    J = symbolic.jacobian(named, symbolic_params=True, use_cache=False)
    assert sp.simplify(J[0, 0] - (-L * sp.sin(q1) - M * sp.sin(q1 + q2))) == 0
    plain = Robot.from_dh([row, row], name="trr", planar=True)
    a1, a2 = sp.symbols("a1 a2", real=True)
    J = symbolic.jacobian(plain, symbolic_params=True, use_cache=False)
    assert sp.simplify(J[1, 1] - a2 * sp.cos(q1 + q2)) == 0 and J[1, 0].has(a1)


def test_robots_survive_pickling_for_the_worker_process():
    """The symbolic worker receives robots by pickle: every field, course names included, survives."""
    robot = robots.load("elbow3r")
    again = pickle.loads(pickle.dumps(robot))
    assert dict(again.param_names) == {"a1": "L1", "a2": "L2", "xt": "L3"}
    assert again.fingerprint() == robot.fingerprint()
    np.testing.assert_array_equal(again.configuration("home"), robot.configuration("home"))
