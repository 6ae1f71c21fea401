"""Where ROS packages are, for ``package://PKG`` meshes and xacro's ``$(find PKG)``.

Search order (:func:`package_roots`): the file's folder and its ancestors up to
:data:`ANCESTOR_LEVELS` above it when named PKG (or when their ``package.xml`` names it); a PKG folder
(or a folder whose ``package.xml`` names PKG) inside the file's folder or inside one of the
:data:`SIBLING_LEVELS` folders above it (never the filesystem root or the home folder); then the
``package_dirs`` given, ``ROS_PACKAGE_PATH`` entries (a package, or a folder of packages) and
``AMENT_PREFIX_PATH`` entries (``PREFIX/share/PKG``).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path

__all__ = ["ANCESTOR_LEVELS", "SIBLING_LEVELS", "package_name", "package_roots"]

ANCESTOR_LEVELS = 6
"""How far above the file's folder an enclosing folder named like the package is looked for."""
SIBLING_LEVELS = 3
"""How far above the file's folder a package folder is looked for beside it."""


def _env_dirs(name: str) -> list[Path]:
    return [Path(p) for p in os.environ.get(name, "").split(os.pathsep) if p.strip()]


def package_name(folder: Path) -> str | None:
    """The ``<name>`` in ``folder/package.xml`` (a ROS package's manifest), or ``None``."""
    manifest = folder / "package.xml"
    try:
        if not manifest.is_file() or manifest.stat().st_size > 256 * 1024:
            return None
        text = manifest.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    match = re.search(r"<name>\s*([^<\s]+)\s*</name>", text)
    return match.group(1) if match else None


def _children(folder: Path, limit: int = 200) -> list[Path]:
    """Up to ``limit`` sub-folders of ``folder`` that hold a package.xml."""
    try:
        entries = sorted(os.scandir(folder), key=lambda e: e.name)[:2000]
    except OSError:
        return []
    out = []
    for entry in entries:
        try:
            if entry.is_dir() and os.path.isfile(os.path.join(entry.path, "package.xml")):
                out.append(Path(entry.path))
        except OSError:
            continue
        if len(out) >= limit:
            break
    return out


def package_roots(
    urdf_path: str | Path, package: str, package_dirs: Sequence[str | Path] = ()
) -> Iterator[Path]:
    """Folders named ``package`` where ``package://package/...`` may live, in search order.

    The URDF's folder and its ancestors up to :data:`ANCESTOR_LEVELS` above it when named
    ``package`` (or when their ``package.xml`` names it); a ``package`` folder (or a folder whose
    ``package.xml`` names it) inside the URDF's folder or inside one of the :data:`SIBLING_LEVELS`
    folders above it (never the filesystem root or the home folder); then ``package_dirs``,
    ``ROS_PACKAGE_PATH`` and ``AMENT_PREFIX_PATH``.
    """
    if not package or package in (".", "..") or any(c in package for c in "/\\\x00"):
        return
    here = Path(urdf_path).resolve().parent
    ancestors = [here, *here.parents][: ANCESTOR_LEVELS + 1]
    stop = {Path(here.anchor), Path.home().resolve()}
    for level, folder in enumerate(ancestors):
        if folder in stop:
            continue
        if folder.name == package or package_name(folder) == package:
            yield folder
        if level <= SIBLING_LEVELS:
            if (folder / package).is_dir():
                yield folder / package
            for child in _children(folder):  # a package whose folder has another name (package.xml)
                if child.name != package and package_name(child) == package:
                    yield child
    spots: Iterable[Path] = [*map(Path, package_dirs), *_env_dirs("ROS_PACKAGE_PATH")]
    for spot in spots:
        if spot.name == package and spot.is_dir():
            yield spot
        elif (spot / package).is_dir():
            yield spot / package
    for prefix in _env_dirs("AMENT_PREFIX_PATH"):
        if (prefix / "share" / package).is_dir():
            yield prefix / "share" / package
