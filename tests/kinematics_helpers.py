"""Helpers shared by the kinematics tests."""

from __future__ import annotations

import contextlib
import importlib.util
import subprocess
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from fakes import random_q  # its home is tests/fakes.py; here for tests written before

import robots
from kinematics import Robot
from kinematics.kernel import kernel
from kinematics.transforms import rot_x, rot_z, trans
from kinematics.urdf import robot_from_urdf, robot_from_urdf_string

__all__ = ["import_source", "random_q", "MIMIC_URDF", "chains_under_test"]


def import_source(path, text, name):
    """Write ``text`` (an exported Python module) to ``path`` and import it as ``name``."""
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


DATA = Path(__file__).parent / "data"

MIMIC_URDF = """<robot name="m">
  <link name="a"/><link name="b"/><link name="c"/><link name="d"/><link name="e"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.3 -0.2 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="b"/><child link="c"/>
    <origin xyz="1 0 0" rpy="1.0 0 0.5"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="j1" multiplier="-2.5" offset="0.1"/></joint>
  <joint name="slide" type="prismatic"><parent link="c"/><child link="d"/>
    <origin xyz="0 0.4 0" rpy="0 0.7 0"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="follow" type="prismatic"><parent link="d"/><child link="e"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="slide" multiplier="0.5" offset="0.05"/></joint>
</robot>"""
"""Two joints driving four axes: a revolute and a prismatic mimic (multipliers -2.5 and 0.5, offsets)."""


def chains_under_test() -> dict[str, Robot]:
    """Every library robot, every URDF of tests/data that loads (the hostile ones are refused on
    purpose), the gripper arm up to its mimic finger (a prismatic mimic joint of a real file),
    MIMIC_URDF, and a DH arm with a rotated base and tool and a prismatic joint."""
    found: dict[str, Robot] = {name: robots.load(name) for name in robots.names()}
    for path in sorted([*DATA.glob("*.urdf"), *DATA.glob("urdf/*.urdf"), *DATA.glob("urdf/*/urdf/*.urdf")]):
        try:
            found[path.name] = robot_from_urdf(path)
        except Exception:  # noqa: BLE001 - the hostile test files are refused on purpose
            continue
    found["gripper_arm.urdf to its mimic finger"] = robot_from_urdf(
        DATA / "urdf" / "gripper_arm.urdf", tip_link="right_finger"
    )
    found["mimic+prismatic"] = robot_from_urdf_string(MIMIC_URDF, tip_link="e")
    found["dh with base and tool"] = Robot.from_dh(
        [
            dict(joint="revolute", a=0.3, alpha=np.pi / 2, d=0.1, theta=0.2),
            dict(joint="prismatic", a=0.0, alpha=-np.pi / 2, d=0.2, theta=0.4),
            dict(joint="revolute", a=0.2, alpha=0.7, d=0.0, theta=0.0),
        ],
        convention="modified",
        base=trans(0.1, -0.2, 0.5) @ rot_x(0.4),
        tool=trans(0.0, 0.0, 0.12) @ rot_z(-np.pi / 4),
        name="based",
    )
    return found


@contextlib.contextmanager
def generated_code_set_aside(robot: Robot) -> Iterator[None]:
    """Every kernel function of ``robot`` takes its NumPy scan (as for chains over MAX_AXES, and as every
    robot did before the generated code): the reference the tests and the bench compare against."""
    c = kernel(robot)
    saved = c.compiled
    object.__setattr__(c, "compiled", None)
    try:
        yield
    finally:
        object.__setattr__(c, "compiled", saved)


def octave_lines(octave: str, folder: Path, script: list[str]) -> list[str]:
    """Run ``script`` (lines of an Octave script) in ``folder`` with ``octave``; its non-empty output lines."""
    (folder / "run_all.m").write_text("\n".join(script) + "\n", encoding="utf-8")
    done = subprocess.run(
        [octave, "--no-gui", "--quiet", "--no-window-system", "run_all.m"],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return [line for line in done.stdout.splitlines() if line.strip()]
