"""Tests of the robot library (robots/): the loader, the data files, published values, singularities."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import robots
from kinematics import Robot, fk, jacobian
from kinematics.analysis import rank, singular_values, task_rows
from kinematics.errors import JacobianLabError, RobotDefinitionError, UnknownRobotError
from kinematics.singularity import assess

NAMES = [
    "elbow3r",
    "iiwa14",
    "panda",
    "planar2",
    "planar3",
    "puma560",
    "puma560_mdh",
    "scara",
    "stanford",
    "trr",
    "ur5",
    "wrist",
]
DOF = {
    "elbow3r": 3,
    "iiwa14": 7,
    "panda": 7,
    "planar2": 2,
    "planar3": 3,
    "puma560": 6,
    "puma560_mdh": 6,
    "scara": 4,
    "stanford": 6,
    "trr": 3,
    "ur5": 6,
    "wrist": 3,
}
KINDS = {"", "wrist", "elbow", "shoulder", "boundary", "aligned axes"}
deg = math.radians


def all_configurations():
    for name in NAMES:
        for c in robots.load(name).configurations:
            yield pytest.param(name, c.name, id=f"{name}-{c.name}")


def configuration(name: str, conf: str):
    r = robots.load(name)
    return r, next(c for c in r.configurations if c.name == conf)


# ------------------------------------------------------------------- library
def test_names_lists_the_library():
    assert robots.names() == NAMES


def test_names_follow_files_added_and_removed(tmp_path, monkeypatch):
    """The listing is kept between calls, and listed again when the folder changes (its time read at
    most every NAMES_CHECK_EVERY seconds: here a fake clock passes that much between calls)."""
    import os

    from robots import library

    clock = [1000.0]

    def monotonic() -> float:
        clock[0] += library.NAMES_CHECK_EVERY
        return clock[0]

    monkeypatch.setattr(library, "DATA_DIR", tmp_path)
    monkeypatch.setattr(library.time, "monotonic", monotonic)
    monkeypatch.setattr(library, "_checked", (-library.NAMES_CHECK_EVERY, -1))  # as at import
    (tmp_path / "b.toml").write_text("")
    (tmp_path / "notes.txt").write_text("")
    os.utime(tmp_path, ns=(1_000_000_000, 1_000_000_000))
    first = robots.names()
    assert first == ["b"]
    first.append("changed by the caller")  # a copy: the next caller gets the folder's names
    assert robots.names() == ["b"]
    (tmp_path / "a.toml").write_text("")
    os.utime(tmp_path, ns=(2_000_000_000, 2_000_000_000))  # as a later change would (coarse clocks)
    assert robots.names() == ["a", "b"]
    (tmp_path / "b.toml").unlink()
    os.utime(tmp_path, ns=(3_000_000_000, 3_000_000_000))
    assert robots.names() == ["a"]


def test_names_read_the_folder_time_at_most_once_a_second(tmp_path, monkeypatch):
    """A room's redraws ask for the names hundreds of times a second: one system call per second."""
    import os

    from robots import library

    clock = [5000.0]
    stats = []
    real_stat = Path.stat

    def stat(self, *args, **kwargs):
        if self == tmp_path:
            stats.append(clock[0])
        return real_stat(self, *args, **kwargs)

    monkeypatch.setattr(library, "DATA_DIR", tmp_path)
    monkeypatch.setattr(library.time, "monotonic", lambda: clock[0])
    monkeypatch.setattr(library, "_checked", (-library.NAMES_CHECK_EVERY, -1))  # as at import
    monkeypatch.setattr(Path, "stat", stat)
    (tmp_path / "b.toml").write_text("")
    os.utime(tmp_path, ns=(1_000_000_000, 1_000_000_000))
    assert robots.names() == ["b"] and stats
    read = len(stats)
    (tmp_path / "a.toml").write_text("")
    os.utime(tmp_path, ns=(2_000_000_000, 2_000_000_000))
    for _ in range(100):
        clock[0] += 0.005
        assert robots.names() == ["b"]  # within the second: the list as it was, the folder not read
    assert len(stats) == read
    clock[0] += library.NAMES_CHECK_EVERY
    assert robots.names() == ["a", "b"] and len(stats) > read


@pytest.mark.parametrize("name", NAMES)
def test_every_file_loads_with_metadata_limits_and_home(name):
    r = robots.load(name)
    assert isinstance(r, Robot) and r.name == name and r.dof == DOF[name]
    meta = robots.info(name)
    for key in ("title", "description", "source"):
        assert meta[key] and "\n" not in meta[key], key
        assert getattr(r, key) == meta[key]
    assert all(j.qlim is not None for j in r.joints), "every joint needs limits"
    assert np.all(np.isfinite(r.qlim)) and np.all(r.qlim[0] < r.qlim[1])
    assert [c.name for c in r.configurations][0] == "home"
    for c in r.configurations:
        assert c.description and c.singular in KINDS, c.name
    assert robots.load(name) is r  # library robots are cached (they are immutable)


def test_units_are_converted_from_degrees():
    p = robots.load("puma560")
    assert p.qlim[:, 1] == pytest.approx([deg(-45), deg(225)])
    assert p.joint_types == ("revolute",) * 6
    assert [row.alpha for row in p.dh] == pytest.approx([deg(a) for a in (90, 0, -90, 90, -90, 0)])
    assert [row.a for row in p.dh] == [0, 0.4318, 0.0203, 0, 0, 0]
    assert [row.d for row in p.dh] == [0, 0, 0.15005, 0.4318, 0, 0]
    m = robots.load("puma560_mdh")
    assert m.convention == "modified"
    assert [row.alpha for row in m.dh] == pytest.approx([deg(a) for a in (0, -90, 0, -90, 90, -90)])
    assert [row.a for row in m.dh] == [0, 0, 0.4318, 0.0203, 0, 0]
    assert [row.d for row in m.dh] == [0, 0, 0.15005, 0.4318, 0, 0]
    s = robots.load("stanford")
    assert s.joint_types[2] == "prismatic" and s.qlim[:, 2] == pytest.approx([0.3048, 1.27])
    assert s.configuration("home")[2] == 0.6  # prismatic entries stay in metres
    assert robots.load("trr").joint_types == ("prismatic", "revolute", "revolute")
    assert robots.load("scara").joint_types == ("revolute", "revolute", "prismatic", "revolute")


def test_published_joint_tables_and_limits():
    ur5 = robots.load("ur5")
    assert [r.d for r in ur5.dh] == [0.089159, 0, 0, 0.10915, 0.09465, 0.0823]
    assert [r.a for r in ur5.dh] == [0, -0.425, -0.39225, 0, 0, 0]
    assert [r.alpha for r in ur5.dh] == pytest.approx([deg(a) for a in (90, 0, 0, 90, -90, 0)])
    assert np.allclose(ur5.qlim, [[-2 * np.pi] * 6, [2 * np.pi] * 6])
    panda = robots.load("panda")
    lim = [
        (-2.8973, 2.8973),
        (-1.7628, 1.7628),
        (-2.8973, 2.8973),
        (-3.0718, -0.0698),
        (-2.8973, 2.8973),
        (-0.0175, 3.7525),
        (-2.8973, 2.8973),
    ]
    assert np.allclose(panda.qlim.T, lim, atol=1e-12, rtol=0)
    assert panda.tool[:3, 3] == pytest.approx([0, 0, 0.107]) and np.allclose(panda.tool[:3, :3], np.eye(3))
    iiwa = robots.load("iiwa14")
    assert [r.d for r in iiwa.dh] == [0.36, 0, 0.42, 0, 0.4, 0, 0.126]
    assert [r.alpha for r in iiwa.dh] == pytest.approx([deg(a) for a in (-90, 90, 90, -90, -90, 90, 0)])
    assert np.allclose(iiwa.qlim[1], [deg(v) for v in (170, 120, 170, 120, 170, 120, 175)])
    assert np.allclose(iiwa.qlim[0], -iiwa.qlim[1])


def test_unknown_name_lists_the_available_robots():
    with pytest.raises(UnknownRobotError) as err:
        robots.load("puma650")
    assert "puma650" in str(err.value)
    assert all(n in str(err.value) for n in NAMES)
    assert isinstance(err.value, (JacobianLabError, ValueError))
    with pytest.raises(UnknownRobotError):
        robots.info("nope")


# ------------------------------------------------------------- file errors
GOOD = """\
name = "{stem}"
title = "Two links"
description = "A test arm."
source = "tests"
convention = "standard"
planar = true

[tool]
xyz = [0.1, 0, 0]

[[joints]]
joint = "revolute"
a = 1.0
alpha = 0.0
d = 0.0
theta = 0.0
qlim = [-90, 90]

[[joints]]
name = "slide"
joint = "prismatic"
a = 0.0
alpha = 0.0
d = 0.5
theta = 90.0
qlim = [0, 1]

[[configurations]]
name = "home"
q = [30, 0.25]
description = "Somewhere."
"""


def write(tmp_path: Path, text: str, stem: str = "arm") -> Path:
    path = tmp_path / f"{stem}.toml"
    path.write_text(text.format(stem=stem) if "{stem}" in text else text)
    return path


def test_a_valid_file_loads_by_path(tmp_path):
    path = write(tmp_path, GOOD)
    for arg in (path, str(path)):
        r = robots.load(arg)
        assert r.name == "arm" and r.dof == 2 and r.planar
        assert r.qlim[:, 0] == pytest.approx([deg(-90), deg(90)])
        assert r.qlim[:, 1] == pytest.approx([0, 1])
        assert r.configuration("home") == pytest.approx([deg(30), 0.25])
    # q = (0 rad, 0.25 m): the slide adds d = 0.75 along z after theta = 90 deg; tool 0.1 along x.
    T = fk(r, [0.0, 0.25])
    assert T[:3, 3] == pytest.approx([1.0, 0.1, 0.75])
    assert robots.info(path)["task"] == "auto" and r.task == "auto"


BAD = [
    # (what, old, new, words the message must contain)
    (
        "missing key",
        "alpha = 0.0\nd = 0.0\ntheta = 0.0\nqlim = [-90",
        "d = 0.0\ntheta = 0.0\nqlim = [-90",
        ["arm.toml", "joints row 1", "'alpha'"],
    ),
    ("missing top key", 'source = "tests"\n', "", ["arm.toml", "'source'"]),
    ("wrong type", 'title = "Two links"', "title = 3", ["arm.toml", "'title'", "str"]),
    ("non-numeric", "a = 1.0", 'a = "one"', ["arm.toml", "joints row 1", "'a'", "number"]),
    ("boolean is not a number", "a = 1.0", "a = true", ["joints row 1", "'a'", "number"]),
    ("non-finite", "a = 1.0", "a = nan", ["arm.toml", "joints row 1", "'a'", "finite"]),
    ("infinite q", "q = [30, 0.25]", "q = [30, inf]", ["arm.toml", "'home'", "finite"]),
    ("qlim length", "qlim = [0, 1]", "qlim = [0, 1, 2]", ["arm.toml", "joints row 2", "qlim", "2 numbers"]),
    ("qlim order", "qlim = [0, 1]", "qlim = [1, 0]", ["arm.toml", "row 2", "qlim", "below"]),
    ("configuration length", "q = [30, 0.25]", "q = [30]", ["arm.toml", "'home'", "'q'", "2 numbers"]),
    ("unknown key", "a = 1.0", "a = 1.0\nalpah = 0.0", ["arm.toml", "joints row 1", "'alpah'", "allowed"]),
    ("joint kind", 'joint = "revolute"', 'joint = "helical"', ["joints row 1", "'joint'", "helical"]),
    ("convention", 'convention = "standard"', 'convention = "craig"', ["arm.toml", "'convention'", "craig"]),
    ("name vs stem", 'name = "{stem}"', 'name = "other"', ["arm.toml", "'name'", "'other'", "'arm'"]),
    ("tool xyz", "xyz = [0.1, 0, 0]", "xyz = [0.1, 0]", ["arm.toml", "[tool]", "'xyz'", "3 numbers"]),
    ("task", "planar = true", 'planar = true\ntask = "position"', ["arm.toml", "'task'", "position"]),
    ("not TOML", "a = 1.0", "a = = 1.0", ["arm.toml", "TOML"]),
    (
        "duplicate configuration",
        'description = "Somewhere."\n',
        'description = "Somewhere."\n\n[[configurations]]\nname = "home"\nq = [0, 0]\n',
        ["arm.toml", "configurations entry 2", "duplicate", "'home'"],
    ),
]


@pytest.mark.parametrize("what, old, new, words", BAD, ids=[b[0] for b in BAD])
def test_bad_files_raise_naming_the_problem(tmp_path, what, old, new, words):
    assert old in GOOD
    path = write(tmp_path, GOOD.replace(old, new, 1))
    with pytest.raises(RobotDefinitionError) as err:
        robots.load(path)
    message = str(err.value)
    for word in words:
        assert word in message, f"{what}: {word!r} not in {message!r}"


def test_missing_file_and_wrong_suffix(tmp_path):
    with pytest.raises(RobotDefinitionError, match="no such robot file"):
        robots.load(tmp_path / "ghost.toml")
    other = tmp_path / "arm.yaml"
    other.write_text("name: arm")
    with pytest.raises(RobotDefinitionError, match=r"\.toml"):
        robots.load_file(other)


def test_urdf_files_go_to_the_urdf_loader(tmp_path):
    pytest.importorskip("kinematics.urdf")
    path = tmp_path / "one.urdf"
    path.write_text(
        '<robot name="one"><link name="base"/><link name="arm"/>'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>'
        '<origin xyz="0 0 0.5" rpy="0 0 0"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    r = robots.load(path)
    assert r.dof == 1 and fk(r, [0.0])[:3, 3] == pytest.approx([0, 0, 0.5])


# ------------------------------------------------------------- published values
def test_puma560_published_poses():
    p = robots.load("puma560")
    # Corke's qz: tool (wrist centre) at (a2 + a3, -d3, d4), identity base (d1 = 0 as in mdl_puma560.m).
    assert fk(p, np.zeros(6))[:3, 3] == pytest.approx([0.4521, -0.15005, 0.4318], abs=1e-12)
    # Corke's qn = (0, 45, 180, 0, 45, 0) deg (home writes q3 = -180 deg): t = (0.5963, -0.1501, -0.0144).
    for q3 in (180, -180):
        T = fk(p, [deg(v) for v in (0, 45, q3, 0, 45, 0)])
        assert np.all(np.abs(T[:3, 3] - [0.5963, -0.1501, -0.0144]) <= 0.5e-4 + 1e-12)  # as printed
        assert np.allclose(T[:3, :3], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-12)


def test_ur5_zero_pose():
    T = fk(robots.load("ur5"), np.zeros(6))
    # (a2 + a3, -(d4 + d6), d1 - d5) from UR's table.
    assert T[:3, 3] == pytest.approx([-0.81725, -0.19145, -0.005491], abs=1e-12)
    assert np.allclose(T[:3, :3], [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-12)


def test_panda_flange_at_the_ready_pose():
    panda = robots.load("panda")
    T = fk(panda, panda.home)
    assert panda.home == pytest.approx([0, -np.pi / 4, 0, -3 * np.pi / 4, 0, np.pi / 2, np.pi / 4])
    # Flange pointing straight down at (0.307, 0, 0.590) m; Franka's hand TCP, 0.1034 m below it,
    # is at the familiar (0.307, 0, 0.487) m.
    assert T[:3, 3] == pytest.approx([0.3069, 0.0, 0.5903], abs=1e-4)
    assert (T[:3, 3] + 0.1034 * T[:3, 2]) == pytest.approx([0.307, 0.0, 0.487], abs=1e-3)
    s = math.sqrt(0.5)
    assert np.allclose(T[:3, :3], [[s, -s, 0], [-s, -s, 0], [0, 0, -1]], atol=1e-12)


def test_trr_course_example():
    trr = robots.load("trr")
    q = [5.0, deg(60), deg(-15)]
    qd = np.array([0.5, deg(90), deg(45)])
    v = jacobian(trr, q)[:3] @ qd
    # Printed in the course as (17.256, -20.13, 0.500) m/s.
    assert np.all(np.abs(v - [17.256, -20.13, 0.500]) <= [0.5e-3, 0.5e-2, 0.5e-3])
    assert trr.home == pytest.approx(q)


def test_trr_position_formula_at_random_q():
    trr = robots.load("trr")
    rng = np.random.default_rng(1)
    q = rng.uniform(trr.qlim[0], trr.qlim[1], size=(200, 3))
    p = fk(trr, q)[:, :3, 3]
    l1, l2, l3 = 10.0, 5.0, 8.0
    expected = np.column_stack(
        [
            l2 * np.sin(q[:, 1]) + l3 * np.sin(q[:, 1] + q[:, 2]),
            l1 + l2 * np.cos(q[:, 1]) + l3 * np.cos(q[:, 1] + q[:, 2]),
            q[:, 0],
        ]
    )
    assert np.allclose(p, expected, atol=1e-12)


def test_elbow3r_position_formula_at_random_q():
    arm = robots.load("elbow3r")
    rng = np.random.default_rng(2)
    q = rng.uniform(-np.pi, np.pi, size=(200, 3))
    p = fk(arm, q)[:, :3, 3]
    L1, L2, L3 = 0.2, 0.5, 0.4
    c2, s2 = np.cos(q[:, 1]), np.sin(q[:, 1])
    c23, s23 = np.cos(q[:, 1] + q[:, 2]), np.sin(q[:, 1] + q[:, 2])
    r = L1 + L2 * c2 + L3 * c23
    expected = np.column_stack([np.cos(q[:, 0]) * r, np.sin(q[:, 0]) * r, L2 * s2 + L3 * s23])
    assert np.allclose(p, expected, atol=1e-12)


def test_puma560_standard_and_modified_agree_at_random_q():
    std, mdh = robots.load("puma560"), robots.load("puma560_mdh")
    rng = np.random.default_rng(3)
    q = rng.uniform(-2 * np.pi, 2 * np.pi, size=(200, 6))
    assert np.allclose(fk(std, q), fk(mdh, q), atol=1e-12)  # position and orientation
    assert np.allclose(jacobian(std, q), jacobian(mdh, q), atol=1e-12)
    # The constants that make them agree: base yaw 180 deg and a 180 deg offset on joint 2.
    assert np.allclose(mdh.base[:3, :3], np.diag([-1, -1, 1]), atol=1e-15)
    assert mdh.dh[1].theta == pytest.approx(np.pi)


# ------------------------------------------------------------- singularities
@pytest.mark.parametrize("name, conf", list(all_configurations()))
def test_named_configuration_is_within_limits(name, conf):
    r, c = configuration(name, conf)
    assert np.all(c.q >= r.qlim[0] - 1e-12) and np.all(c.q <= r.qlim[1] + 1e-12)


@pytest.mark.parametrize("name, conf", list(all_configurations()))
def test_task_jacobian_rank_drops_exactly_where_tagged(name, conf):
    r, c = configuration(name, conf)
    rows = task_rows(r)
    J = jacobian(r, c.q)
    full = min(len(rows), r.dof)
    if c.singular:
        assert rank(J, rows) < full, f"tagged {c.singular!r} but the task Jacobian has full rank"
    else:
        assert rank(J, rows) == full
        s = singular_values(J, rows)
        assert s[full - 1] / s[0] > 1e-2, "regular, but close to a singularity"


@pytest.mark.parametrize("name, conf", list(all_configurations()))
def test_kinematics_assess_agrees_with_the_tags(name, conf):
    r, c = configuration(name, conf)
    assert assess(r, c.q).status == ("singular" if c.singular else "regular")


def test_the_wrist_task_is_orientation():
    wrist = robots.load("wrist")
    assert wrist.task == "angular" and task_rows(wrist) == (3, 4, 5)
    assert robots.info("wrist")["task"] == "angular" and robots.info("puma560")["task"] == "auto"
    assert all(robots.load(n).task == "auto" for n in NAMES if n != "wrist")


def test_finite_difference_jacobian_agrees_at_the_named_configurations():
    """An independent check of the rank claims: J from finite differences of fk."""
    h = 1e-7
    for name in NAMES:
        r = robots.load(name)
        for c in r.configurations:
            J = jacobian(r, c.q)
            T0 = fk(r, c.q)
            for i in range(r.dof):
                dq = np.zeros(r.dof)
                dq[i] = h
                T1 = fk(r, c.q + dq)
                v = (T1[:3, 3] - T0[:3, 3]) / h
                W = (T1[:3, :3] - T0[:3, :3]) / h @ T0[:3, :3].T
                w = np.array([W[2, 1], W[0, 2], W[1, 0]])
                assert np.allclose(J[:, i], np.r_[v, w], atol=1e-5), (name, c.name, i)
