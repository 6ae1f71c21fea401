"""The robot library: one TOML file per robot in ``robots/data/`` (``puma560.toml`` is the
commented example of the format), and its loader.

* :mod:`robots.files`: the robot-file format in one place: read, validate and write (lossless);
* :mod:`robots.texts`: a robot file's texts in other languages (``translations``);
* :mod:`robots.library`: the library's names, and loading a robot by name or from a file.

Files are in metres and DEGREES (alpha, theta, revolute limits and configuration entries,
base/tool rpy); the reader converts to radians and builds a :class:`kinematics.Robot`. It only
parses data (tomllib); nothing is ever evaluated.
"""

from __future__ import annotations

from kinematics.conventions import TASKS

from .files import MAX_ROBOT_FILE_BYTES, TEXT_LANGUAGES, MotionPreset, RobotFile, dumps, loads, read
from .library import DATA_DIR, info, load, load_file, motions, names

__all__ = [
    "DATA_DIR",
    "MAX_ROBOT_FILE_BYTES",
    "TEXT_LANGUAGES",
    "TASKS",
    "MotionPreset",
    "RobotFile",
    "names",
    "load",
    "load_file",
    "info",
    "motions",
    "read",
    "loads",
    "dumps",
]
