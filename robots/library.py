"""The robot library (one robot file per robot in ``robots/data/``) and loading any robot file.

A name is looked up in the library; anything with a slash or a ``.toml`` / ``.urdf`` / ``.xacro`` suffix is
a path. Robot files are read by :mod:`robots.files`; URDF and xacro files by :mod:`kinematics.urdf`.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from kinematics import Robot
from kinematics.errors import RobotDefinitionError, UnknownRobotError
from kinematics.urdf import robot_from_urdf

from . import files
from .files import MotionPreset

__all__ = ["DATA_DIR", "SUFFIXES", "names", "load", "load_file", "info", "motions"]

DATA_DIR = Path(__file__).resolve().parent / "data"
SUFFIXES = (".toml", ".urdf", ".xacro")


def names() -> list[str]:
    """Names of the robots in the library (the stems of ``robots/data/*.toml``), sorted.

    The folder is listed again only when its modification time changed (a file added, removed or
    renamed), and its time is read at most every :data:`NAMES_CHECK_EVERY` seconds: every redraw of
    every tab asks for the robot menu's entries (a room of 300 followers, 300 system calls a move)."""
    global _checked
    now = time.monotonic()
    checked_at, stamp = _checked
    if now - checked_at >= NAMES_CHECK_EVERY:
        try:
            stamp = DATA_DIR.stat().st_mtime_ns
        except OSError:
            stamp = -1
        _checked = (now, stamp)
    return list(_names(DATA_DIR, stamp))


NAMES_CHECK_EVERY = 1.0
"""[s] How stale the library's list of names may be."""
_checked: tuple[float, int] = (-NAMES_CHECK_EVERY, -1)


@functools.lru_cache(maxsize=1)
def _names(folder: Path, stamp: int) -> tuple[str, ...]:
    return tuple(sorted(p.stem for p in folder.glob("*.toml")))


def load(
    name_or_path: str | Path,
    base_link: str | None = None,
    tip_link: str | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_dirs: Mapping[str, str | Path] | None = None,
    package_path: Sequence[str | Path] = (),
) -> Robot:
    """A robot by library name (``"puma560"``), or from a ``.toml`` robot file, a ``.urdf`` file or a
    ``.xacro`` file (expanded to a URDF with ``xacro_args``, :mod:`kinematics.urdf.expand`).

    Args:
        name_or_path: Library name or file path.
        base_link, tip_link: For a URDF, the ends of the chain (default: see
            :mod:`kinematics.urdf`); a robot file or library robot has no links to choose.
        xacro_args: ``NAME -> VALUE`` arguments of a xacro file (one it does not declare is refused).
        package_dirs: ROS packages of a URDF or xacro file by name, ``{"kuka_kr6_support": DIR}``
            (``--package NAME=DIR``), for ``$(find NAME)`` and ``package://NAME`` meshes.
        package_path: Folders that are packages or hold packages (``--package-path``), searched like
            ``ROS_PACKAGE_PATH``.

    Raises:
        UnknownRobotError: not a library name (nor a file path); the message lists the names.
        RobotDefinitionError: the file is invalid; the message names the file and the key or row.
    """
    path = _resolve(name_or_path)
    if path.parent == DATA_DIR and path.suffix == ".toml":
        _no_links(path, base_link, tip_link)
        return _load_library(path.stem)
    return load_file(
        path, base_link, tip_link, xacro_args=xacro_args, package_dirs=package_dirs, package_path=package_path
    )


def _no_links(path: Path, base_link: str | None, tip_link: str | None) -> None:
    if base_link is not None or tip_link is not None:
        raise RobotDefinitionError(
            f"{path.name}: base_link/tip_link choose a chain in a URDF; a robot file (.toml) is one chain"
        )


def info(name_or_path: str | Path) -> dict[str, Any]:
    """Metadata of a robot file, without building the robot: name, title, description, source,
    convention, planar and task (``"auto"`` unless the file sets it)."""
    path = _resolve(name_or_path)
    doc = files.parse(files.read_text(path), path.name)
    return {"name": doc["name"], "convention": doc["convention"]} | files.meta(doc)


def motions(name_or_path: str | Path) -> tuple[MotionPreset, ...]:
    """The resolved-rate presets of a robot file (``[[motions]]``; none for a URDF)."""
    path = _resolve(name_or_path)
    if path.suffix.lower() != ".toml":
        return ()
    return files.read(path).motions


def load_file(
    path: str | Path,
    base_link: str | None = None,
    tip_link: str | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_dirs: Mapping[str, str | Path] | None = None,
    package_path: Sequence[str | Path] = (),
) -> Robot:
    """Build a robot from a ``.toml`` robot file, a ``.urdf`` file or a ``.xacro`` file (base and tip
    links and packages: URDF and xacro only; ``xacro_args``: xacro only; see :func:`load`)."""
    path = Path(path)
    if path.suffix.lower() in (".urdf", ".xacro"):
        return robot_from_urdf(
            str(path),
            base_link=base_link,
            tip_link=tip_link,
            xacro_args=xacro_args,
            package_dirs=package_dirs,
            package_path=package_path,
        )
    if path.suffix.lower() != ".toml":
        raise RobotDefinitionError(
            f"{path.name}: expected a .toml robot file, a .urdf file or a .xacro file (e.g. arm.urdf.xacro)"
        )
    _no_links(path, base_link, tip_link)
    return files.read(path).robot


def _resolve(name_or_path: str | Path) -> Path:
    text = str(name_or_path)
    if isinstance(name_or_path, Path) or any(ch in text for ch in "/\\") or text.lower().endswith(SUFFIXES):
        return Path(name_or_path)
    if text not in names():
        raise UnknownRobotError(f"unknown robot {text!r}; available robots: {', '.join(names())}")
    return DATA_DIR / f"{text}.toml"


@functools.cache
def _load_library(name: str) -> Robot:
    return load_file(DATA_DIR / f"{name}.toml")
