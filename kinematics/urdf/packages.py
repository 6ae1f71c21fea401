"""Where ROS packages are, for ``package://PKG`` meshes and xacro's ``$(find PKG)``.

Search order (:func:`package_roots`): first the folder the user mapped the package to (``named``:
``--package NAME=DIR``, ``package_dirs={NAME: DIR}`` in :func:`robots.load`); then the file's folder and
its ancestors up to :data:`ANCESTOR_LEVELS` above it when named PKG (or when their ``package.xml`` names
it); a PKG folder (or a folder whose ``package.xml`` names PKG) inside the file's folder or inside one of
the :data:`SIBLING_LEVELS` folders above it (never the filesystem root or the home folder); then the
``package_dirs`` given (``--package-path``), ``ROS_PACKAGE_PATH`` entries (a package, or a folder of
packages) and ``AMENT_PREFIX_PATH`` entries (``PREFIX/share/PKG``). The packages a robot file was opened
with are remembered for its meshes (:func:`use_packages`).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path

__all__ = [
    "ANCESTOR_LEVELS",
    "PATH_DEPTH",
    "SIBLING_LEVELS",
    "found_package",
    "found_packages",
    "looked_in",
    "package_name",
    "package_roots",
    "packages_of",
    "use_packages",
]

ANCESTOR_LEVELS = 6
"""How far above the file's folder an enclosing folder named like the package is looked for."""
SIBLING_LEVELS = 3
"""How far above the file's folder a package folder is looked for beside it."""
PATH_DEPTH = 3
"""How deep below a ``--package-path`` or ``ROS_PACKAGE_PATH`` entry a package.xml is looked for
(``ws/src/group/pkg``)."""


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


def _valid(package: str) -> bool:
    return bool(package) and package not in (".", "..") and not any(c in package for c in "/\\\x00")


def _nested(folder: Path, depth: int = PATH_DEPTH) -> Iterator[Path]:
    """The packages (folders with a package.xml) in ``folder`` and its sub-folders down to ``depth``
    levels, a package's own sub-folders left out (as ROS does), 200 per folder at most."""
    yield from _children(folder)
    if depth > 1:
        try:
            entries = sorted(os.scandir(folder), key=lambda e: e.name)[:2000]
        except OSError:
            return
        for entry in entries:
            try:
                inner = entry.is_dir() and not entry.name.startswith(".")
                inner = inner and not os.path.isfile(os.path.join(entry.path, "package.xml"))
            except OSError:
                continue
            if inner:
                yield from _nested(Path(entry.path), depth - 1)


def package_roots(
    urdf_path: str | Path,
    package: str,
    package_dirs: Sequence[str | Path] = (),
    named: Mapping[str, str | Path] | None = None,
) -> Iterator[Path]:
    """Folders named ``package`` where ``package://package/...`` may live, in search order.

    The URDF's folder and its ancestors up to :data:`ANCESTOR_LEVELS` above it when named
    ``package`` (or when their ``package.xml`` names it); a ``package`` folder (or a folder whose
    ``package.xml`` names it) inside the URDF's folder or inside one of the :data:`SIBLING_LEVELS`
    folders above it (never the filesystem root or the home folder); then ``package_dirs`` and
    ``ROS_PACKAGE_PATH`` (each entry: the package itself, a ``package`` folder in it, or a package.xml
    naming it down to :data:`PATH_DEPTH` levels below) and ``AMENT_PREFIX_PATH``. A folder ``named``
    maps the package to comes first (package name -> its folder, whatever the folder is called).
    Without ``package_dirs`` and ``named``, those remembered for the file (:func:`use_packages`) are used.
    """
    if not _valid(package):
        return
    if not package_dirs and named is None:
        package_dirs, named = packages_of(urdf_path)
    if named and package in named and Path(named[package]).is_dir():
        yield Path(named[package])
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
        if (spot.name == package or package_name(spot) == package) and spot.is_dir():
            yield spot
        elif (spot / package).is_dir():
            yield spot / package
        else:  # as ROS crawls ROS_PACKAGE_PATH: a package.xml naming it, in nested folders
            yield from (f for f in _nested(spot) if package_name(f) == package)
    for prefix in _env_dirs("AMENT_PREFIX_PATH"):
        if (prefix / "share" / package).is_dir():
            yield prefix / "share" / package


_USED: dict[str, tuple[tuple[Path, ...], dict[str, Path]]] = {}  # resolved robot file -> its packages


def use_packages(
    path: str | Path, package_dirs: Sequence[str | Path] = (), named: Mapping[str, str | Path] | None = None
) -> None:
    """Remember the packages a robot file was opened with, for its meshes (:func:`packages_of`)."""
    key = str(Path(path).resolve())
    if package_dirs or named:
        _USED[key] = (tuple(map(Path, package_dirs)), {k: Path(v) for k, v in (named or {}).items()})
    else:
        _USED.pop(key, None)


_FOUND: dict[str, set[Path]] = {}  # resolved xacro file -> the package folders its $(find …) gave


def found_package(path: str | Path, root: Path | None) -> None:
    """Note ``root`` as a package folder the xacro file ``path``'s ``$(find …)`` resolved to (``None``:
    forget them all, before an expansion), so that its meshes named ``$(find PKG)/meshes/x.stl``, absolute
    once expanded, are found inside that folder and only there (:func:`found_packages`)."""
    key = str(Path(path).resolve())
    if root is None:
        _FOUND.pop(key, None)
    else:
        _FOUND.setdefault(key, set()).add(root.resolve())


def found_packages(path: str | Path) -> list[Path]:
    """The package folders the last expansion of the xacro file ``path`` found (:func:`found_package`)."""
    return sorted(_FOUND.get(str(Path(path).resolve()), ()))


def packages_of(path: str | Path) -> tuple[tuple[Path, ...], dict[str, Path]]:
    """The ``(package_dirs, named)`` the robot file ``path`` was last opened with (none by default)."""
    return _USED.get(str(Path(path).resolve()), ((), {}))


def looked_in(
    urdf_path: str | Path,
    package_dirs: Sequence[str | Path] = (),
    named: Mapping[str, str | Path] | None = None,
) -> list[str]:
    """Where :func:`package_roots` looks, in words (for a message naming a package not found)."""
    here = Path(urdf_path).resolve().parent
    ancestors = [here, *here.parents][: ANCESTOR_LEVELS + 1]
    stop = {Path(here.anchor), Path.home().resolve()}
    top = [f for f in ancestors if f not in stop]
    out = []
    if named:
        out.append("--package: " + ", ".join(f"{k}={v}" for k, v in named.items()))
    if top:
        beside = [f for f in ancestors[: SIBLING_LEVELS + 1] if f not in stop]
        out.append(f"the folders enclosing the file up to {top[-1]}")
        if beside:
            out.append(
                f"the folders inside {beside[0]}" + (f" up to {beside[-1]}" if len(beside) > 1 else "")
            )
    out.append("--package-path: " + (", ".join(map(str, package_dirs)) or "(none given)"))
    for var in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"):
        entries = _env_dirs(var)
        shown = ", ".join(f"{p}/share" if var == "AMENT_PREFIX_PATH" else str(p) for p in entries)
        out.append(f"{var}: {shown or '(not set)'}")
    return out
