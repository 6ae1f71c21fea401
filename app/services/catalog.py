"""The robots a client can choose: the library (``robots.names()``) plus files named on the command line.

Robots are immutable, so one loaded robot is shared by every client.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import robots
from kinematics import Robot
from kinematics.errors import UnknownRobotError
from kinematics.urdf import ChainInfo, mesh_report
from kinematics.urdf import chains as urdf_chains

__all__ = ["RobotCatalog", "DEFAULT_ROBOT"]

DEFAULT_ROBOT = "puma560"
"""The first robot a student sees: the textbook 6R arm, whose DH frames, spherical wrist and three
named singularities (wrist, elbow, shoulder) are the course's running example."""


class RobotCatalog:
    """Names shown in the robot dropdown and the robots behind them.

    Args:
        files: Extra robot files (``.urdf`` or ``.toml``); each is listed under its file stem
            (with a suffix if that name is taken).
        base_link, tip_link: The chain taken from each URDF in ``files`` (default: the URDF
            reader's choice, see :mod:`kinematics.urdf`).
        xacro_args: The arguments of the ``.xacro`` files in ``files``.
        package_dirs, package_path: The ROS packages of the URDF and xacro files (``--package NAME=DIR``,
            ``--package-path DIR``; see :func:`robots.load`).
    """

    def __init__(
        self,
        files: Sequence[str | Path] = (),
        base_link: str | None = None,
        tip_link: str | None = None,
        xacro_args: Mapping[str, str] | None = None,
        package_dirs: Mapping[str, str | Path] | None = None,
        package_path: Sequence[str | Path] = (),
    ) -> None:
        self._xacro_args = dict(xacro_args) if xacro_args else None
        self._packages: dict[str, Any] = {"package_dirs": package_dirs, "package_path": tuple(package_path)}
        self._files: dict[str, Path] = {}
        self._chains: dict[str, tuple[str | None, str | None]] = {}
        self._cache: dict[str, Robot] = {}
        self._chain_lists: dict[str, list[ChainInfo]] = {}
        self._lock = threading.Lock()
        for f in files:
            self.add_file(f, base_link, tip_link)

    def add_file(self, path: str | Path, base_link: str | None = None, tip_link: str | None = None) -> str:
        """List the robot file ``path`` (an upload, a DH table saved by an editor); returns its name.

        ``base_link``/``tip_link`` choose the chain of a URDF (ignored for a ``.toml`` robot file).
        """
        path = Path(path)
        urdf = _is_urdf(path)
        # A URDF is listed under its <robot name> (read now, so a broken file fails at once).
        stem = robots.load_file(path, base_link, tip_link, **self._xacro(path)).name if urdf else path.stem
        with self._lock:
            name = stem or path.stem
            while name in robots.names() or name in self._files:
                name += " (file)"
            self._files[name] = path
            self._chains[name] = (base_link, tip_link) if urdf else (None, None)
        return name

    def _xacro(self, path: Path) -> dict[str, Any]:
        """The keyword arguments of a URDF's or xacro file's loading: its xacro arguments, its packages."""
        return {"xacro_args": self._xacro_args if path.suffix.lower() == ".xacro" else None, **self._packages}

    def names(self) -> list[str]:
        """Dropdown entries: the files given first, then the library robots."""
        return [*self._files, *robots.names()]

    def default(self) -> str:
        """The first file given, else :data:`DEFAULT_ROBOT` (or the first library robot)."""
        if self._files:
            return next(iter(self._files))
        names = robots.names()
        return DEFAULT_ROBOT if DEFAULT_ROBOT in names else names[0]

    def chains(self, name: str) -> list[ChainInfo]:
        """The serial chains of the URDF listed as ``name`` (default first); ``[]`` for other robots."""
        path = self._files.get(name)
        if path is None or not _is_urdf(path):
            return []
        with self._lock:
            if name in self._chain_lists:
                return self._chain_lists[name]
        found = urdf_chains(path, self._chains[name][0], **self._xacro(path))
        with self._lock:
            self._chain_lists[name] = found
        return found

    def load_chain(self, name: str, tip_link: str) -> Robot:
        """The robot of the URDF listed as ``name`` ending at ``tip_link`` (loaded once per chain).

        Raises:
            UnknownRobotError: ``name`` is not a listed URDF file.
            UrdfError: ``tip_link`` does not end a chain of it.
        """
        if name not in self._files or not _is_urdf(self._files[name]):
            raise UnknownRobotError(f"{name!r} is not a URDF file of this lab: it has no chains to choose")
        key = f"{name}\x00{tip_link}"
        with self._lock:
            if key in self._cache:
                return self._cache[key]
        path = self._files[name]
        robot = robots.load_file(path, self._chains[name][0], tip_link, **self._xacro(path))
        with self._lock:
            self._cache[key] = robot
        return robot

    def meshes(self, name: str) -> tuple[int, list[str]]:
        """(found, not found) mesh files of the URDF listed as ``name``; (0, []) for other robots."""
        path = self._files.get(name)
        if path is None or not _is_urdf(path):
            return 0, []
        resolved, unresolved = mesh_report(path)
        return len(resolved), unresolved

    def presets(self, name: str) -> tuple[robots.MotionPreset, ...]:
        """The resolved-rate presets of the robot listed as ``name`` (none for a URDF)."""
        if name in self._files:
            return robots.motions(self._files[name])
        return robots.motions(name) if name in robots.names() else ()

    def load(self, name: str) -> Robot:
        """The robot listed as ``name`` (loaded once).

        Raises:
            UnknownRobotError: ``name`` is not listed (the message lists what is).
            RobotDefinitionError: the robot file is invalid.
        """
        with self._lock:
            if name in self._cache:
                return self._cache[name]
        if name in self._files:
            base_link, tip_link = self._chains[name]
            path = self._files[name]
            robot = robots.load_file(path, base_link, tip_link, **self._xacro(path))
        elif name in robots.names():
            robot = robots.load(name)
        else:
            raise UnknownRobotError(f"unknown robot {name!r}; available: {', '.join(self.names())}")
        with self._lock:
            self._cache[name] = robot
        return robot


def _is_urdf(path: Path) -> bool:
    """A URDF, or a xacro file that expands to one."""
    return path.suffix.lower() in (".urdf", ".xacro")
