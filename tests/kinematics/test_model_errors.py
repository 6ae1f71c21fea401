"""Every bad input to the model raises a project error whose message names the problem."""

from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np
import pytest

from kinematics import (
    ConfigurationError,
    JacobianLabError,
    Joint,
    NamedConfiguration,
    OptionError,
    Robot,
    RobotDefinitionError,
    UrdfError,
    fk,
    jacobian,
)
from kinematics.urdf import robot_from_urdf, robot_from_urdf_string

ROW = dict(joint="revolute", a=0.5, alpha=0.0, d=0.0, theta=0.0)


def with_(**changes):
    row = dict(ROW)
    row.update(changes)
    return row


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        ([], "empty"),
        ("not rows", "sequence of mappings"),
        ([ROW, {k: v for k, v in ROW.items() if k != "alpha"}], r"DH row 2: missing key\(s\) 'alpha'"),
        (
            [with_(joint="spherical")],
            "DH row 1, key 'joint': expected one of 'revolute', 'prismatic', got 'spherical'",
        ),
        ([with_(a=float("nan"))], "DH row 1, key 'a': expected a finite number, got nan"),
        ([with_(d=math.inf)], "DH row 1, key 'd': expected a finite number"),
        ([with_(theta="90")], "DH row 1, key 'theta': expected a number, got '90'"),
        ([with_(alpha=True)], "DH row 1, key 'alpha': expected a number"),
        ([with_(qlim=(1.0, -1.0))], "lower limit 1.0 must be below upper limit -1.0"),
        ([with_(qlim=(0.0,))], r"DH row 1, key 'qlim': expected \(lower, upper\)"),
        ([with_(length=1.0)], "DH row 1: unknown key\\(s\\) 'length'"),
        ([42], "DH row 1: expected a mapping"),
        ([with_(name="a"), with_(name="a")], "joint names are not unique"),
    ],
)
def test_bad_dh_rows(rows, message):
    with pytest.raises(RobotDefinitionError, match=message):
        Robot.from_dh(rows)


def test_bad_convention():
    with pytest.raises(
        RobotDefinitionError, match="DH convention: expected one of 'standard', 'modified', got 'craig'"
    ):
        Robot.from_dh([ROW], convention="craig")


@pytest.mark.parametrize(
    ("T", "message"),
    [
        (np.eye(3), r"tool: expected a 4×4 homogeneous transform, got shape \(3, 3\)"),
        (np.diag([2.0, 1, 1, 1]), "tool: the upper-left 3×3 block is not a rotation"),
        (np.diag([-1.0, 1, 1, 1]), "tool: the upper-left 3×3 block is not a rotation"),
        (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1.0]]), "last row must be"),
        (np.full((4, 4), np.nan), "tool: contains a non-finite number"),
        ("eye", "tool: expected a 4×4 numeric matrix"),
    ],
)
def test_bad_tool_transform(T, message):
    with pytest.raises(RobotDefinitionError, match=message):
        Robot.from_dh([ROW], tool=T)


def test_bad_base_is_named():
    with pytest.raises(RobotDefinitionError, match="^base: "):
        Robot.from_dh([ROW], base=np.zeros((4, 4)))


@pytest.mark.parametrize(
    ("q", "message"),
    [
        ([0.0, 0.0, 0.0], r"q has shape \(3,\); robot 'two' expects \(2,\) or \(N, 2\)"),
        ([[[0.0, 0.0]]], r"q has shape \(1, 1, 2\)"),
        ([0.0, float("nan")], "q contains NaN or infinity"),
        (["a", "b"], "q must hold ints or floats, got strings"),
    ],
)
def test_bad_configuration(q, message):
    robot = Robot.from_dh([ROW, ROW], name="two")
    with pytest.raises(ConfigurationError, match=message):
        jacobian(robot, q)
    with pytest.raises(ConfigurationError):
        fk(robot, q)


def test_errors_are_value_errors():
    assert issubclass(JacobianLabError, ValueError)
    assert issubclass(UrdfError, RobotDefinitionError)


def test_bad_frame_argument():
    with pytest.raises(OptionError, match="frame must be one of 'base', 'tool' .*, got 'world'"):
        jacobian(Robot.from_dh([ROW]), [0.0], frame="world")


@pytest.mark.parametrize(
    ("row_changes", "message"),
    [
        (
            {"a": 10**400},
            r"DH row 1, key 'a': expected a finite number, got 1000.*beyond the range of a float",
        ),
        ({"d": "1e400"}, r"DH row 1, key 'd': expected a number, got '1e400' \(a string\)"),
        ({"alpha": b"0"}, r"DH row 1, key 'alpha': expected a number, got b'0' \(a bytes value\)"),
        ({"theta": np.bool_(True)}, r"DH row 1, key 'theta': expected a number, got np.True_ \(a bool\)"),
        ({"a": None}, r"DH row 1, key 'a': expected a number, got None \(a NoneType\)"),
        ({"a": 1 + 0j}, r"DH row 1, key 'a': expected a number, got \(1\+0j\) \(a complex\)"),
        ({"theta": -math.inf}, "DH row 1, key 'theta': expected a finite number, got -inf"),
        ({"a": 2e15}, r"DH row 1, key 'a': 2e\+15 m is out of range; expected \|value\| ≤ 1e\+15 m"),
        (
            {"alpha": 1e19},
            r"DH row 1, key 'alpha': 1e\+19 rad is out of range; expected \|value\| ≤ 1e\+18 rad",
        ),
        ({"alfa": 0.0}, r"DH row 1: unknown key\(s\) 'alfa' \(did you mean 'alpha'\?\); allowed: joint, a"),
        ({1: 0.0}, "DH row 1: keys must be strings, got 1; expected joint, a, alpha, d, theta"),
        (
            {"joint": "revolut"},
            "DH row 1, key 'joint': expected one of 'revolute', 'prismatic', got 'revolut' "
            r"\(did you mean 'revolute'\?\)",
        ),
        ({"joint": 1}, "DH row 1, key 'joint': expected one of 'revolute', 'prismatic', got 1$"),
        ({"name": 5}, "DH row 1, key 'name': expected a string, got 5"),
        ({"qlim": (float("nan"), 1.0)}, "DH row 1, key 'qlim': expected a number, got NaN"),
        (
            {"qlim": (math.inf, math.inf)},
            "DH row 1, key 'qlim': lower limit inf must be below upper limit inf",
        ),
        ({"qlim": "ab"}, r"DH row 1, key 'qlim': expected \(lower, upper\), got 'ab'"),
        ({"qlim": (0, "1")}, r"DH row 1, key 'qlim': expected a number, got '1' \(a string\)"),
    ],
)
def test_bad_dh_values_name_row_key_and_expectation(row_changes, message):
    row = {**ROW, **row_changes}
    with pytest.raises(RobotDefinitionError, match=message):
        Robot.from_dh([row])


def test_the_row_number_is_counted_from_one():
    with pytest.raises(RobotDefinitionError, match="^DH row 3, key 'd': expected a finite number, got nan$"):
        Robot.from_dh([ROW, ROW, with_(d=math.nan)])


def test_exact_numbers_of_any_numeric_type_are_accepted():
    """ints, Fractions and NumPy numbers are numbers: the tool lands where the DH table says."""
    rows = [with_(a=Fraction(1, 2)), with_(a=np.int64(2), d=np.float32(0.25))]
    robot = Robot.from_dh(rows)
    np.testing.assert_allclose(fk(robot, [0.0, 0.0])[:3, 3], [2.5, 0.0, 0.25], atol=1e-15)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"convention": 3}, "DH convention: expected one of 'standard', 'modified', got 3"),
        ({"convention": "modifed"}, r"got 'modifed' \(did you mean 'modified'\?\)"),
        (
            {"task": "position"},
            "robot '', task: expected one of 'auto', 'full', 'linear', 'angular', 'planar'",
        ),
        ({"planar": "yes"}, "robot '', planar: expected true or false, got 'yes'"),
        ({"name": 7}, "robot name: expected a string, got 7"),
        (
            {"base": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2e15], [0, 0, 0, 1]]},
            r"base: translation \[0.0, 0.0, 2000000000000000.0\] m is out of range",
        ),
        ({"tool": np.eye(4, dtype=bool)}, "tool: expected a 4×4 numeric matrix of ints or floats, got bools"),
        (
            {"tool": [[1, 0, 0, 10**400], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]},
            "tool: expected a 4×4 numeric matrix of ints or floats, got objects",
        ),
    ],
)
def test_bad_robot_options(kwargs, message):
    with pytest.raises(RobotDefinitionError, match=message):
        Robot.from_dh([ROW], **kwargs)


@pytest.mark.parametrize(
    ("q", "message"),
    [
        ([0.0, math.nan], r"configuration 'c', q\[1\]: expected a finite number, got nan"),
        ([0.0, "1"], r"configuration 'c', q\[1\]: expected a number, got '1' \(a string\)"),
        ([0.0], r"configuration 'c' has 1 values, expected 2 \(one per joint\)"),
        (
            [0.0, 2e15],
            r"configuration 'c', joint 'slide': 2e\+15 m is out of range; expected \|q\| ≤ 1e\+15 m",
        ),
        ("00", "configuration 'c': q must be a sequence of numbers, got '00'"),
    ],
)
def test_bad_named_configurations(q, message):
    rows = [ROW, with_(joint="prismatic", name="slide")]
    with pytest.raises(RobotDefinitionError, match=message):
        Robot.from_dh(rows, configurations=[NamedConfiguration("c", q)])


def test_configuration_names_are_unique():
    confs = [NamedConfiguration("home", [0.0]), NamedConfiguration("home", [1.0])]
    with pytest.raises(RobotDefinitionError, match="configuration 'home' is named twice"):
        Robot.from_dh([ROW], configurations=confs)


LINK = '<link name="{}"/>'


def joint(name, parent, child, kind="revolute", extra=""):
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{extra}</joint>'
    )


def urdf(*parts):
    return '<robot name="r">' + "".join(parts) + "</robot>"


@pytest.mark.parametrize(
    ("text", "kwargs", "message"),
    [
        (
            urdf(LINK.format("a"), LINK.format("b"), joint("j1", "a", "b")),
            {"tip_link": "hand"},
            "unknown tip_link 'hand'; links: a, b",
        ),
        (
            urdf(LINK.format("a"), LINK.format("b"), joint("j1", "a", "b")),
            {"base_link": "world"},
            "unknown base_link 'world'",
        ),
        (
            urdf(LINK.format("a"), LINK.format("b"), joint("j1", "a", "b", kind="floating")),
            {},
            "joint 'j1' is floating",
        ),
        (
            urdf(LINK.format("a"), LINK.format("b"), joint("j1", "a", "b", kind="planar")),
            {},
            "joint 'j1' is planar",
        ),
        (
            urdf(
                LINK.format("a"),
                LINK.format("b"),
                LINK.format("c"),
                joint("j1", "a", "b"),
                joint("j2", "c", "b"),
            ),
            {},
            "not a tree",
        ),
        (
            urdf(LINK.format("a"), LINK.format("b"), joint("j1", "a", "b", kind="fixed")),
            {},
            "no moving joint",
        ),
        (
            urdf(
                LINK.format("a"),
                LINK.format("b"),
                LINK.format("c"),
                joint("j1", "a", "b"),
                joint("j2", "b", "c"),
            ),
            {"base_link": "c", "tip_link": "a"},
            "tip_link 'a' is not below base_link 'c'",
        ),
        ("<robot name='r'><link name='a'>", {}, "cannot parse URDF"),
        ('<!DOCTYPE r [<!ENTITY x "y">]><robot name="r"/>', {}, "must not contain a DOCTYPE"),
        (
            urdf(LINK.format("a"), LINK.format("b"), joint("j1", "a", "b", extra='<mimic joint="nope"/>')),
            {},
            "mimics 'nope', which is not an actuated joint",
        ),
    ],
)
def test_bad_urdf(text, kwargs, message):
    with pytest.raises(UrdfError, match=message):
        robot_from_urdf_string(text, **kwargs)


def test_missing_urdf_file(tmp_path):
    with pytest.raises(UrdfError, match="cannot read URDF"):
        robot_from_urdf(tmp_path / "nope.urdf")


def test_urdf_chain_without_meshes(tmp_path):
    """A URDF with mesh references that do not exist still loads (only the tree is needed)."""
    text = urdf(
        '<link name="base"><visual><geometry><mesh filename="package://missing/base.stl"/></geometry></visual></link>',
        LINK.format("l1"),
        LINK.format("l2"),
        LINK.format("tip"),
        joint("shoulder", "base", "l1"),
        '<joint name="slide" type="prismatic"><parent link="l1"/><child link="l2"/><origin xyz="0.5 0 0" rpy="0 1.5707963267948966 0"/>'
        '<axis xyz="1 0 0"/><limit lower="0" upper="0.3" effort="1" velocity="1"/></joint>',
        '<joint name="flange" type="fixed"><parent link="l2"/><child link="tip"/><origin xyz="0 0 0.1"/></joint>',
    )
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    robot = robot_from_urdf(str(path))
    assert robot.joint_names == ("shoulder", "slide") and robot.joint_types == ("revolute", "prismatic")
    assert robot.joints[1].qlim == (0.0, 0.3)
    # Tool: after the slide (along the l1 x axis rotated by pitch 90° → along -z of l1), then 0.1 along l2 z.
    T = fk(robot, [0.0, 0.2])
    # slide axis x of l2-frame-before-motion = Ry(90°)·x = -z; tool offset z of l2 = Ry(90°)·z = +x.
    np.testing.assert_allclose(T[:3, 3], [0.5 + 0.1, 0.0, -0.2], atol=1e-12)


@pytest.mark.parametrize(
    ("qlim", "expected"),
    [
        ((-1.0, 2.0), (-1.0, 2.0)),
        ((-1e16, 1e16), None),  # URDF sentinels for "unlimited"
        ((-1e308, 1e308), None),
        ((-math.inf, math.inf), None),
        ((-999e12, 999e12), (-999e12, 999e12)),  # just below the sentinel threshold: kept
        (None, None),
    ],
)
def test_huge_limits_mean_unlimited_in_every_loader(qlim, expected):
    assert Joint("j", "revolute", qlim).qlim == expected
    robot = Robot.from_dh([with_(qlim=qlim)])
    assert robot.joints[0].qlim == expected
    lo, hi = expected if expected is not None else (-math.inf, math.inf)
    assert robot.qlim[:, 0].tolist() == [lo, hi]
    assert robot.home.tolist() == [0.0 if expected is None else (lo + hi) / 2]


@pytest.mark.parametrize(
    ("qlim", "words"),
    [
        ((0.0, math.inf), "upper unlimited, the other 0"),
        ((-math.inf, 0.0), "lower unlimited, the other 0"),
        ((-(10**400), 0.5), "lower unlimited, the other 0.5"),  # beyond float range is beyond 1e15 too
    ],
)
def test_a_limit_on_one_side_only_is_refused_in_words_not_dropped(qlim, words):
    """Issue 18, point 11: DH qlim (-inf, 0) silently lost its finite bound."""
    with pytest.raises(RobotDefinitionError, match=re.escape(words)):
        Robot.from_dh([with_(qlim=qlim)])


def test_a_60_kB_number_in_a_urdf_is_refused_in_a_short_message():
    digits = "1" + "0" * 60_000
    for where in (f'xyz="{digits} 0 0"', None):
        text = urdf(LINK.format("a"), LINK.format("b"), joint("j1", "a", "b"))
        text = (
            text.replace("<parent", f"<origin {where}/><parent")
            if where
            else text.replace('lower="-1"', f'lower="-{digits}"')
        )
        with pytest.raises(UrdfError, match="a number of 6000[12] characters") as error:
            robot_from_urdf_string(text)
        assert len(str(error.value)) < 300


def test_urdf_sentinel_limits_mean_unlimited():
    text = urdf(
        LINK.format("a"),
        LINK.format("b"),
        joint("j1", "a", "b").replace('lower="-1" upper="1"', 'lower="-1e16" upper="1e16"'),
    )
    robot = robot_from_urdf_string(text)
    assert robot.joints[0].qlim is None
    assert np.all(np.isinf(robot.qlim)) and robot.home.tolist() == [0.0]
