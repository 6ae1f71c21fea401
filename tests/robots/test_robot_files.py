"""Robot files (.toml) that are not what they claim: clear RobotDefinitionErrors, never a hang or a raw error."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import numpy as np
import pytest

import robots
from kinematics import fk
from kinematics.errors import RobotDefinitionError

PLANAR2 = (robots.DATA_DIR / "planar2.toml").read_text(encoding="utf-8")


def write(tmp_path: Path, text: str | bytes) -> Path:
    path = tmp_path / "planar2.toml"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


def test_a_copy_of_a_library_file_loads(tmp_path):
    robot = robots.load(write(tmp_path, PLANAR2))
    np.testing.assert_allclose(fk(robot, [0.0, np.pi / 2])[:3, 3], [1.0, 1.0, 0.0], atol=1e-12)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "a = 1.0",
            "a = " + "1" * 401,
            r"joints row 1, key 'a': expected a finite number within float range, "
            r"got an integer of about 40\d digits",
        ),
        (
            "a = 1.0",
            "a = 1e400",
            r"joints row 1, key 'a': expected a finite number within float range, got inf",
        ),
        ("a = 1.0", "a = -1e400", r"got -inf"),
        (
            "qlim = [-180.0, 180.0]",
            "qlim = [-1" + "0" * 400 + ", 180.0]",
            r"joints row 1, key 'qlim'.*float range",
        ),
        (
            "q = [30, 60]",
            "q = [30, 1" + "0" * 330 + "]",
            r"configurations entry 1 \('home'\), key 'q'.*float range",
        ),
        (
            "a = 1.0",
            "a = " + "9" * 5000,
            r"planar2.toml: an integer of 5000 digits; write a number within float range",
        ),
        ('name = "planar2"', 'name = "planar2"\n"1" = 2', r"planar2.toml: unknown key\(s\) '1'"),
        ('name = "planar2"', 'name = "planar2"\n3 = 2\n"x y" = 1', r"unknown key\(s\) '3', 'x y'"),
        ("planar = true", "planar = [" * 2000 + "]" * 2000, r"planar2.toml: not valid TOML"),
        ('name = "q1"', "name = 1", r"joints row 1, key 'name': expected a str, got 1"),
    ],
    ids=[
        "int-400-digits",
        "1e400",
        "-1e400",
        "qlim-huge",
        "q-huge",
        "int-5000-digits",
        "quoted-digit-key",
        "bare-digit-key",
        "deep-nesting",
        "name-not-string",
    ],
)
def test_bad_values_name_the_key(tmp_path, old, new, message):
    assert old in PLANAR2
    with pytest.raises(RobotDefinitionError, match=message):
        robots.load(write(tmp_path, PLANAR2.replace(old, new, 1)))


def test_non_utf8_robot_file(tmp_path):
    data = PLANAR2.replace('title = "Planar 2R arm"', 'title = "Planar 2R arm caf\udce9"').encode(
        "utf-8", errors="surrogateescape"
    )
    with pytest.raises(
        RobotDefinitionError, match=r"planar2.toml is not UTF-8 text: byte 0xe9 at line 2, column 27"
    ):
        robots.load(write(tmp_path, data))


def test_directory_fifo_and_device_are_refused_at_once(tmp_path):
    folder = tmp_path / "folder.toml"
    folder.mkdir()
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)

    def hung(*_):
        raise TimeoutError("a robot file read blocked")

    old = signal.signal(signal.SIGALRM, hung)
    signal.setitimer(signal.ITIMER_REAL, 5.0)
    try:
        with pytest.raises(
            RobotDefinitionError, match=r"cannot read robot file '.*folder.toml': it is a directory"
        ):
            robots.load(folder)
        with pytest.raises(RobotDefinitionError, match=r"'.*pipe.toml': it is a FIFO \(named pipe\)"):
            robots.load(fifo)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def test_a_device_behind_a_toml_name_is_refused(tmp_path):
    link = tmp_path / "urandom.toml"
    link.symlink_to("/dev/urandom")
    with pytest.raises(
        RobotDefinitionError, match=r"'.*urandom.toml': it is a character device, not a regular file"
    ):
        robots.load(link)


def test_a_robot_file_over_the_cap(tmp_path):
    path = tmp_path / "planar2.toml"
    with open(path, "wb") as f:
        f.truncate(robots.MAX_ROBOT_FILE_BYTES + 1)
    with pytest.raises(
        RobotDefinitionError, match=rf"is {robots.MAX_ROBOT_FILE_BYTES + 1} bytes; the limit is"
    ):
        robots.load(path)


def test_links_are_for_urdf_only(tmp_path):
    with pytest.raises(
        RobotDefinitionError, match=r"planar2.toml: base_link/tip_link choose a chain in a URDF"
    ):
        robots.load("planar2", tip_link="tool0")
    with pytest.raises(RobotDefinitionError, match=r"base_link/tip_link choose a chain in a URDF"):
        robots.load(write(tmp_path, PLANAR2), base_link="base")
