"""``--package NAME=DIR`` and ``--package-path DIR``: where a URDF's or xacro file's ROS packages are,
without a ROS workspace (no ``ROS_PACKAGE_PATH``, no ament index). One function adds them to every
command that opens a robot (``serve``, ``export``, ``handout``, ``record``); :func:`package_options`
gives them to :func:`robots.load` (and to the worker processes of ``serve``) as plain strings."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["add_package_arguments", "package_options"]


def _package(text: str) -> tuple[str, str]:
    name, sep, folder = text.partition("=")
    name = name.strip()
    if not sep or not name or not folder.strip():
        raise argparse.ArgumentTypeError(
            f"expected NAME=DIR (e.g. kuka_kr6_support=rtbdata/xacro/kuka_kr6), got {text!r}"
        )
    if name in (".", "..") or any(c in name for c in "/\\\x00"):
        raise argparse.ArgumentTypeError(f"{name!r} is not a package name (a name has no slash)")
    return name, _folder(folder.strip())


def _folder(text: str) -> str:
    path = Path(text).expanduser()
    if not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is not a folder")
    return str(path.resolve())


def add_package_arguments(parser: argparse.ArgumentParser) -> None:
    """``--package NAME=DIR`` and ``--package-path DIR``, both repeatable."""
    parser.add_argument(
        "--package",
        metavar="NAME=DIR",
        type=_package,
        action="append",
        default=[],
        help="URDF/xacro: the ROS package NAME is the folder DIR, for $(find NAME) and package://NAME "
        "meshes (repeatable); no ROS workspace needed",
    )
    parser.add_argument(
        "--package-path",
        metavar="DIR",
        type=_folder,
        action="append",
        default=[],
        help="URDF/xacro: a folder that is a ROS package or holds packages (folders named after them, or "
        "with a package.xml naming them), searched like ROS_PACKAGE_PATH (repeatable)",
    )


def package_options(args: argparse.Namespace) -> dict[str, Any]:
    """The keyword arguments ``package_dirs`` ({NAME: DIR}) and ``package_path`` ([DIR, …]) of
    :func:`robots.load` that the command line gives (none when the parser has no such options)."""
    named = dict(getattr(args, "package", None) or [])
    return {"package_dirs": named or None, "package_path": list(getattr(args, "package_path", None) or [])}
