"""Fuzzing the readers: mutated URDFs and robot files give a Robot with finite numbers or a JacobianLabError.

A few hundred cases built from valid files by random mutations (dropped attributes, wrong
counts, NaN/inf/1e400 numbers, cycles, duplicate names, empty robots, deep nesting, non-UTF-8
bytes, truncation), each under a time bound; deterministic (fixed seed).
"""

from __future__ import annotations

import random
import re
import signal
import time

import locations
import numpy as np
import pytest

import robots
from kinematics import Robot, fk, jacobian
from kinematics.errors import JacobianLabError
from kinematics.urdf import chains, robot_from_urdf, robot_from_urdf_string

DATA = locations.DATA / "urdf"
SEEDS_URDF = [
    (DATA / name).read_bytes()
    for name in (
        "ur5_xacro.urdf",
        "gripper_arm.urdf",
        "odd_geometry.urdf",
        "sentinel_limits.urdf",
        "singular_at_zero.urdf",
    )
]
SEEDS_TOML = [(robots.DATA_DIR / f"{name}.toml").read_bytes() for name in ("planar2", "puma560", "stanford")]
BAD_NUMBERS = [
    "nan",
    "inf",
    "-inf",
    "1e400",
    "-1e400",
    "1e16",
    "-1e308",
    "1e308",
    "0x10",
    "",
    "1,0",
    "1 2",
    "--1",
    "NaN",
]
NUMBER = re.compile(rb"-?\d+(\.\d+)?([eE][-+]?\d+)?")
TIME_BOUND = 2.0  # [CPU s of this thread] per case: the work a case may cost, whatever the machine's load
HANG_BOUND = 60.0  # [s] wall clock: only a safety net for a case that blocks (a read that never returns)


def mutate_urdf(data: bytes, rng: random.Random) -> bytes:
    kind = rng.randrange(12)
    if kind == 0:  # drop an attribute
        attrs = list(re.finditer(rb'\s[a-z_]+="[^"]*"', data))
        if attrs:
            m = rng.choice(attrs)
            return data[: m.start()] + data[m.end() :]
    if kind == 1:  # a number becomes something else
        nums = list(NUMBER.finditer(data))
        if nums:
            m = rng.choice(nums)
            return data[: m.start()] + rng.choice(BAD_NUMBERS).encode() + data[m.end() :]
    if kind == 2:  # wrong count of numbers
        attrs = list(re.finditer(rb'(xyz|rpy)="([^"]*)"', data))
        if attrs:
            m = rng.choice(attrs)
            values = m.group(2).split()
            values = values + [b"0"] if rng.random() < 0.5 else values[:-1]
            return data[: m.start(2)] + b" ".join(values) + data[m.end(2) :]
    if kind == 3:  # duplicate an element (duplicate names, two parents)
        elems = list(re.finditer(rb"<(link|joint)\b.*?(/>|</\1>)", data, re.DOTALL))
        if elems:
            m = rng.choice(elems)
            return data[: m.end()] + m.group(0) + data[m.end() :]
    if kind == 4:  # swap a joint's parent and child: a cycle or a second root
        joints = list(re.finditer(rb'<parent link="([^"]*)"/>\s*<child link="([^"]*)"/>', data))
        if joints:
            m = rng.choice(joints)
            swapped = b'<parent link="' + m.group(2) + b'"/><child link="' + m.group(1) + b'"/>'
            return data[: m.start()] + swapped + data[m.end() :]
    if kind == 5:  # an empty robot
        return b'<?xml version="1.0"?><robot name="empty"></robot>'
    if kind == 6:  # deep nesting
        depth = rng.choice([10, 200, 300, 5000])
        i = data.find(b"<link")
        return data[:i] + b"<a>" * depth + b"</a>" * depth + data[i:]
    if kind == 7:  # bytes that are not UTF-8
        i = rng.randrange(len(data))
        return data[:i] + rng.choice([b"\xff", b"\xc3\x28", b"\xed\xa0\x80", b"\x00"]) + data[i:]
    if kind == 8:  # truncated
        return data[: rng.randrange(len(data))]
    if kind == 9:  # another joint type
        types = list(re.finditer(rb'type="([a-z]+)"', data))
        if types:
            m = rng.choice(types)
            new = rng.choice(
                [b"floating", b"planar", b"fixed", b"continuous", b"prismatic", b"spherical", b""]
            )
            return data[: m.start(1)] + new + data[m.end(1) :]
    if kind == 10:  # a mimic element, leader random, factors hostile
        ends = list(re.finditer(rb"</joint>", data))
        names = re.findall(rb'<joint name="([^"]*)"', data) + [b"ghost"]
        if ends:
            m = rng.choice(ends)
            factor = rng.choice(BAD_NUMBERS + ["2", "-1", "1e300"]).encode()
            mimic = b'<mimic joint="' + rng.choice(names) + b'" multiplier="' + factor + b'"/>'
            return data[: m.start()] + mimic + data[m.start() :]
    if kind == 11:  # a DOCTYPE with entities
        return b'<!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;">]>' + data
    return data.replace(b"<robot", b"<robo", 1)


def mutate_toml(data: bytes, rng: random.Random) -> bytes:
    kind = rng.randrange(7)
    nums = list(NUMBER.finditer(data))
    if kind == 0 and nums:
        m = rng.choice(nums)
        new = rng.choice(["nan", "inf", "-inf", "1e400", "1" + "0" * 400, "true", '"x"', "[]", "9" * 5000])
        return data[: m.start()] + new.encode() + data[m.end() :]
    lines = data.split(b"\n")
    if kind in (0, 1):  # drop a line
        del lines[rng.randrange(len(lines))]
    elif kind == 2:  # duplicate a line (a key defined twice, a table twice)
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif kind == 3:
        i = rng.randrange(len(lines))
        lines[i] = lines[i] + b"\xff\xfe"
    elif kind == 4:
        return data[: rng.randrange(len(data))]
    elif kind == 5:
        lines.insert(3, b"deep = " + b"[" * 3000 + b"]" * 3000)
    else:
        lines.insert(
            3, rng.choice([b"3 = 1", b'"" = 1', b"a.b.c = 1", b"joints = 5", b"[base]\nxyz = [1e999, 0, 0]"])
        )
    return b"\n".join(lines)


def check_robot(robot: Robot) -> None:
    """Every number in the robot is finite; fk and J at its home are finite."""
    for ax in robot.axes:
        assert np.isfinite(ax.T_parent_joint).all() and np.isfinite(ax.T_joint_child).all()
        assert np.isfinite([ax.multiplier, ax.offset]).all()
    assert np.isfinite(robot.base).all() and np.isfinite(robot.tool).all()
    for j in robot.joints:
        assert j.qlim is None or np.isfinite(j.qlim).all()
    for c in robot.configurations:
        assert np.isfinite(c.q).all()
    assert np.isfinite(fk(robot, robot.home)).all() and np.isfinite(jacobian(robot, robot.home)).all()


class _Timeout(BaseException):
    pass


def run_bounded(fn, *args):
    """``fn(*args)`` within :data:`TIME_BOUND` of CPU time (and :data:`HANG_BOUND` of wall clock);
    returns the result or the JacobianLabError raised."""

    def expire(*_):
        raise _Timeout

    old = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, HANG_BOUND)
    start = time.thread_time()
    try:
        return fn(*args)
    except JacobianLabError as exc:
        return exc
    except _Timeout:
        pytest.fail(f"{fn.__name__} did not return within {HANG_BOUND} s")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
        seconds = time.thread_time() - start
        assert seconds < TIME_BOUND, f"{fn.__name__} took {seconds:.2f} CPU s"


def test_fuzzed_urdfs(tmp_path):
    rng = random.Random(8)
    outcomes = {"loaded": 0, "refused": 0}
    for i in range(300):
        data = rng.choice(SEEDS_URDF)
        for _ in range(rng.choice([1, 1, 2, 3])):
            data = mutate_urdf(data, rng)
        if i % 3 == 0:  # through a file: the reader, the chain list, and the string path
            path = tmp_path / f"case{i}.urdf"
            path.write_bytes(data)
            result = run_bounded(robot_from_urdf, path)
            run_bounded(chains, path)
        else:
            result = run_bounded(robot_from_urdf_string, data)
        if isinstance(result, Robot):
            check_robot(result)
            outcomes["loaded"] += 1
        else:
            assert str(result), "an error without a message"
            outcomes["refused"] += 1
    assert outcomes["loaded"] > 30 and outcomes["refused"] > 100  # the mutations reach both outcomes


def test_fuzzed_robot_files(tmp_path):
    rng = random.Random(7)
    outcomes = {"loaded": 0, "refused": 0}
    for i in range(150):
        data = rng.choice(SEEDS_TOML)
        for _ in range(rng.choice([1, 1, 2])):
            data = mutate_toml(data, rng)
        stem = re.search(rb'^name = "([^"]*)"', data, re.MULTILINE)
        folder = tmp_path / f"case{i}"
        folder.mkdir()
        path = folder / f"{stem.group(1).decode('utf-8', 'replace') if stem else 'robot'}.toml"
        path.write_bytes(data)
        result = run_bounded(robots.load, path)
        if isinstance(result, Robot):
            check_robot(result)
            outcomes["loaded"] += 1
        else:
            outcomes["refused"] += 1
    assert outcomes["loaded"] > 10 and outcomes["refused"] > 50
