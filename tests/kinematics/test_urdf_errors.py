"""Broken and hostile URDF input: every valid XML header opens; everything else is a UrdfError that says where."""

from __future__ import annotations

import os
import signal
import stat

import numpy as np
import pytest

from kinematics import fk
from kinematics.errors import JacobianLabError, UrdfError
from kinematics.files import MAX_FILE_BYTES
from kinematics.urdf import MAX_LINKS, robot_from_urdf, robot_from_urdf_string

ARM = (
    '<robot name="arm"><link name="a"/><link name="b"/>'
    '<joint name="j1" type="revolute"><parent link="a"/><child link="b"/>'
    '<origin xyz="0.4 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1"/>{extra}</joint></robot>'
)


def arm(extra: str = "") -> str:
    return ARM.format(extra=extra)


# ------------------------------------------------------------------ valid headers
@pytest.mark.parametrize(
    "data",
    [
        b'<?xml version="1.0" encoding="utf-8"?>\n' + ARM.format(extra="").encode(),
        b'<?xml version="1.0" encoding="UTF-8" standalone="yes"?>' + ARM.format(extra="").encode(),
        b'<?xml version="0.0"?>' + ARM.format(extra="").encode(),
        b'\n\n  <?xml version="1.0"?>\n' + ARM.format(extra="").encode(),
        ARM.format(extra="").encode() + b"\x00",
        ARM.format(extra="").encode() + b"\n\x00\x00\n",
        b"\xef\xbb\xbf" + ARM.format(extra="").encode(),  # a UTF-8 byte-order mark
        b"<!-- made by hand -->\n" + ARM.format(extra="").encode(),
    ],
    ids=[
        "xacro-utf8",
        "standalone",
        "version-0.0",
        "blank-lines-first",
        "trailing-nul",
        "nuls",
        "bom",
        "comment",
    ],
)
def test_valid_headers_open(tmp_path, data):
    path = tmp_path / "arm.urdf"
    path.write_bytes(data)
    robot = robot_from_urdf(path)
    assert robot.name == "arm" and robot.joint_names == ("j1",)
    np.testing.assert_allclose(fk(robot, [np.pi / 2])[:3, 3], [0.4, 0.0, 0.0], atol=1e-15)


# ------------------------------------------------------------------ messages
BAD = [
    (
        arm().replace('<axis xyz="0 0 1"/>', '<axis xyz="1 0"/>'),
        r"joint 'j1' \(line 1\): <axis xyz=\"1 0\">: expected 3 numbers, found 2",
    ),
    (
        arm().replace('<axis xyz="0 0 1"/>', '<axis xyz="1 0 0 0"/>'),
        r"joint 'j1' \(line 1\): <axis xyz=\"1 0 0 0\">: expected 3 numbers, found 4",
    ),
    (
        arm().replace('rpy="0 0 0"', 'rpy="0 0 0 1"'),
        r"joint 'j1' .*<origin rpy=\"0 0 0 1\">: expected 3 numbers, found 4",
    ),
    (
        arm().replace('xyz="0.4 0 0"', 'xyz="0.4, 0, 0"'),
        r"joint 'j1' .*<origin xyz=\"0.4, 0, 0\">: numbers must be separated by spaces, not commas",
    ),
    (
        arm().replace('xyz="0.4 0 0"', 'xyz="0.4 nan 0"'),
        r"joint 'j1' .*<origin xyz=.*'nan' is not a finite number",
    ),
    (arm().replace('xyz="0.4 0 0"', 'xyz="1e400 0 0"'), r"'1e400' is not a finite number"),
    (arm().replace('xyz="0.4 0 0"', 'xyz="0.4 zero 0"'), r"'zero' is not a number"),
    (
        arm().replace('xyz="0.4 0 0"', 'xyz="1e308 0 0"'),
        r"<origin xyz=\"1e308 0 0\">: '1e308' is beyond ±1e\+06",
    ),
    (
        arm().replace('<axis xyz="0 0 1"/>', '<axis xyz="1e308 1e308 0"/>'),
        r"<axis xyz=.*'1e308' is beyond ±1e\+06",
    ),
    (
        arm(extra='<mimic joint="j0" multiplier="1e300"/>'),
        r"<mimic multiplier=\"1e300\">: expected a number within ±1e\+06",
    ),
    (
        arm().replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 0"/>'),
        r"joint 'j1' .*<axis xyz>: the axis .* has zero length",
    ),
    (
        arm(extra='<mimic joint="j0" multiplier="nan"/>'),
        r"joint 'j1' .*<mimic multiplier=\"nan\">: expected a finite number",
    ),
    (
        arm(extra='<mimic joint="j0" multiplier="inf"/>'),
        r"<mimic multiplier=\"inf\">: expected a finite number",
    ),
    (arm(extra='<mimic joint="j0" offset="-inf"/>'), r"<mimic offset=\"-inf\">: expected a finite number"),
    (arm(extra="<mimic/>"), r"joint 'j1' .*<mimic> has no joint attribute"),
    (arm().replace('lower="-1"', 'lower="nan"'), r"<limit lower=\"nan\">: expected a finite number"),
    (
        arm().replace('type="revolute"', 'type="hinge"'),
        r"joint 'j1' .*type 'hinge' is not one of revolute, continuous",
    ),
    (arm().replace('<parent link="a"/>', ""), r"joint 'j1' .*expected one <parent link=...>, found 0"),
    (
        arm().replace('<child link="b"/>', '<child link="b"/><child link="a"/>'),
        r"expected one <child link=...>, found 2",
    ),
    (arm().replace('<child link="b"/>', '<child link="zz"/>'), r"joint 'j1' .*refers to unknown link 'zz'"),
    (arm().replace('<link name="b"/>', '<link name="b"/><link name="b"/>'), r"two links named 'b'"),
    (arm().replace('<link name="b"/>', "<link/>"), r"<link> at line 1: missing or empty name"),
    ('<robot name="empty"></robot>', r"URDF has no <link>: expected at least one link"),
    ("<robot/>", r"URDF has no <link>"),
    ("<robots><link name='a'/></robots>", r"the root element is <robots>, expected <robot>"),
    (
        "<robot name='r'>\n<link name='a'>\n</robot>",
        r"cannot parse URDF: line 3, column \d+: Opening and ending tag mismatch",
    ),
    (
        "<robot name='r'>\n  <link name='a'/>\n  <joint name='j' type='fixed'\n</robot>",
        r"cannot parse URDF: line 4, column \d+",
    ),
    ("", r"cannot parse URDF: line 1"),
    ('<!DOCTYPE r [<!ENTITY x "y">]><robot name="&x;"/>', r"must not contain a DOCTYPE or ENTITY"),
    (
        '<?xml version="1.0"?><!DOCTYPE robot SYSTEM "file:///etc/passwd"><robot/>',
        r"must not contain a DOCTYPE",
    ),
    ("<a>" * 300 + "</a>" * 300, r"cannot parse URDF: .*Excessive depth"),
    (
        arm().replace('<link name="a"/>', '<link name="a"/><link name="c"/>'),
        r"exactly one root link, found 2: a, c",
    ),
    (
        '<robot name="c"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>'
        '<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 0 1"/></joint>'
        '<joint name="j3" type="revolute"><parent link="c"/><child link="b"/><axis xyz="0 0 1"/></joint></robot>',
        r"not a tree: link 'b' is the child of joints 'j1' and 'j3'",
    ),
    (
        '<robot name="c"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j1" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 0 1"/></joint>'
        '<joint name="j2" type="revolute"><parent link="c"/><child link="b"/><axis xyz="0 0 1"/></joint></robot>',
        r"links 'b', 'c' are not connected to the root 'a' \(their joints form a cycle\)",
    ),
    (
        '<robot name="c"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><mimic joint="j2"/></joint>'
        '<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 0 1"/><mimic joint="j1"/></joint>'
        "</robot>",
        r"mimic joints form a cycle: j1 -> j2 -> j1",
    ),
]


@pytest.mark.parametrize(("text", "message"), BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_urdf_message(text, message):
    with pytest.raises(UrdfError, match=message):
        robot_from_urdf_string(text)


def test_a_mimic_multiplier_that_overflows_when_chained():
    """60 mimic joints each following the previous one ×1e6: the composed factor of j2 (1e12) is already
    beyond what the model accepts (|multiplier| ≤ 1e6), long before it would overflow to ∞."""
    n = 60
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 2))
    joints = (
        '<joint name="j0" type="revolute"><parent link="l0"/><child link="l1"/><axis xyz="0 0 1"/></joint>'
    )
    joints += "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/><axis xyz="0 0 1"/>'
        f'<mimic joint="j{i - 1}" multiplier="1e6"/></joint>'
        for i in range(1, n + 1)
    )
    with pytest.raises(JacobianLabError, match=r"axis 'j2', multiplier: 1e\+12 +is out of range"):
        robot_from_urdf_string(f'<robot name="c">{links}{joints}</robot>', tip_link=f"l{n + 1}")


def test_links_beyond_the_cap_are_refused_at_once():
    links = "".join(f'<link name="l{i}"/>' for i in range(MAX_LINKS + 1))
    with pytest.raises(
        UrdfError, match=rf"URDF has {MAX_LINKS + 1} links; Jacobian Lab reads at most {MAX_LINKS}"
    ):
        robot_from_urdf_string(f'<robot name="big">{links}</robot>')


@pytest.mark.slow
def test_a_chain_of_the_maximum_length_loads():
    n = MAX_LINKS - 1
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin xyz="0.001 0 0"/><axis xyz="0 0 1"/></joint>'
        for i in range(n)
    )
    robot = robot_from_urdf_string(f'<robot name="long">{links}{joints}</robot>')
    assert robot.dof == n
    np.testing.assert_allclose(fk(robot, np.zeros(n))[:3, 3], [0.001 * n, 0, 0], atol=1e-9)


# ------------------------------------------------------------------ files that are not URDF text
def test_non_utf8_file_names_line_and_column(tmp_path):
    path = tmp_path / "latin1.urdf"
    path.write_bytes(b'<robot name="r">\n  <link name="caf\xe9"/>\n</robot>')
    with pytest.raises(UrdfError, match=r"not UTF-8 text: byte 0xe9 at line 2, column 18"):
        robot_from_urdf(path)


def test_missing_file(tmp_path):
    with pytest.raises(UrdfError, match=r"cannot read URDF '.*nope.urdf': No such file"):
        robot_from_urdf(tmp_path / "nope.urdf")


def test_directory_is_refused(tmp_path):
    folder = tmp_path / "folder.urdf"
    folder.mkdir()
    with pytest.raises(UrdfError, match=r"it is a directory, not a regular file"):
        robot_from_urdf(folder)


def test_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "pipe.urdf"
    os.mkfifo(fifo)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)

    def hung(*_):
        raise TimeoutError("reading the FIFO blocked")

    old = signal.signal(signal.SIGALRM, hung)
    signal.setitimer(signal.ITIMER_REAL, 5.0)  # opening a FIFO with no writer would block for ever
    try:
        with pytest.raises(UrdfError, match=r"it is a FIFO \(named pipe\), not a regular file"):
            robot_from_urdf(fifo)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def test_device_is_refused():
    with pytest.raises(UrdfError, match=r"'/dev/urandom': it is a character device, not a regular file"):
        robot_from_urdf("/dev/urandom")


def test_file_over_the_size_cap_is_refused_unread(tmp_path):
    path = tmp_path / "huge.urdf"
    with open(path, "wb") as f:  # sparse: no disk space used
        f.truncate(MAX_FILE_BYTES + 1)
    with pytest.raises(UrdfError, match=rf"is {MAX_FILE_BYTES + 1} bytes; the limit is {MAX_FILE_BYTES}"):
        robot_from_urdf(path)


def test_wrong_argument_type():
    with pytest.raises(UrdfError, match="expected str or bytes, got int"):
        robot_from_urdf_string(42)  # type: ignore[arg-type]
