"""Where a URDF's mesh files are, without ever leaving the folders the user pointed at.

``package://PKG/rest`` is looked up in a folder named PKG: the URDF's own
folder or one of its ancestors when it is named PKG, a PKG folder next to the
URDF or next to one of its ancestors, then the ``package_dirs`` given, the
``ROS_PACKAGE_PATH`` entries (a package, or a folder of packages) and
``AMENT_PREFIX_PATH`` entries (``PREFIX/share/PKG``). Any other file name is
relative to the URDF's folder (``file://`` URIs and absolute paths too, but
only when they point inside it).

The result is always a mesh file (``.stl``, ``.dae``, ``.obj``, ...) inside the
URDF's own folder tree or inside the package folder found: the candidate is
resolved (symbolic links followed, ``..`` removed) and then checked for
containment, so ``/etc/passwd``,
``file:///etc/passwd``, ``../../x.stl``, ``package://../../etc/x`` and links
that point outside resolve to ``None``.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from pathlib import Path
from urllib.parse import unquote, urlsplit

from ..files import MAX_FILE_BYTES, decode_utf8, read_user_file
from .xml import parse_urdf

__all__ = ["resolve_mesh", "mesh_report", "mesh_filename_handler", "package_roots", "MESH_SUFFIXES"]

_PACKAGE = "package://"
MESH_SUFFIXES = frozenset({".stl", ".dae", ".obj", ".ply", ".glb", ".gltf", ".off", ".3mf"})
"""File types a mesh may have (case-insensitive): nothing else is ever returned."""
ANCESTOR_LEVELS = 6
"""How far above the URDF's folder an enclosing folder named like the package is looked for."""
SIBLING_LEVELS = 3
"""How far above the URDF's folder a package folder is looked for beside it."""


def _inside(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


def _contained_file(folder: Path, relative: str) -> Path | None:
    """``folder / relative`` when it resolves to an existing regular file inside ``folder``."""
    if "\x00" in relative:
        return None
    try:
        root = folder.resolve()
        candidate = (root / relative).resolve()
    except (OSError, RuntimeError, ValueError):  # RuntimeError: a symlink loop
        return None
    if not _inside(candidate, root) or candidate == root or candidate.suffix.lower() not in MESH_SUFFIXES:
        return None
    try:
        return candidate if candidate.is_file() else None
    except OSError:
        return None


def _env_dirs(name: str) -> list[Path]:
    return [Path(p) for p in os.environ.get(name, "").split(os.pathsep) if p.strip()]


def package_roots(
    urdf_path: str | Path, package: str, package_dirs: Sequence[str | Path] = ()
) -> Iterator[Path]:
    """Folders named ``package`` where ``package://package/...`` may live, in search order.

    The URDF's folder and its ancestors up to :data:`ANCESTOR_LEVELS` above it when named
    ``package``; a ``package`` folder inside the URDF's folder or inside one of the
    :data:`SIBLING_LEVELS` folders above it (never inside the filesystem root or the home
    folder); then ``package_dirs``, ``ROS_PACKAGE_PATH`` and ``AMENT_PREFIX_PATH``.
    """
    if not package or package in (".", "..") or any(c in package for c in "/\\\x00"):
        return
    here = Path(urdf_path).resolve().parent
    ancestors = [here, *here.parents][: ANCESTOR_LEVELS + 1]
    stop = {Path(here.anchor), Path.home().resolve()}
    for level, folder in enumerate(ancestors):
        if folder.name == package and folder not in stop:
            yield folder
        if level <= SIBLING_LEVELS and folder not in stop and (folder / package).is_dir():
            yield folder / package
    spots: Iterable[Path] = [*map(Path, package_dirs), *_env_dirs("ROS_PACKAGE_PATH")]
    for spot in spots:
        if spot.name == package and spot.is_dir():
            yield spot
        elif (spot / package).is_dir():
            yield spot / package
    for prefix in _env_dirs("AMENT_PREFIX_PATH"):
        if (prefix / "share" / package).is_dir():
            yield prefix / "share" / package


def resolve_mesh(
    urdf_path: str | Path, uri: str, package_dirs: Sequence[str | Path] | None = None
) -> Path | None:
    """The mesh file that ``uri`` (a URDF ``<mesh filename>``) names, or ``None``.

    Args:
        urdf_path: The URDF file the name comes from.
        uri: ``package://PKG/...``, ``file://...``, or a path (relative to the URDF's folder).
        package_dirs: Extra folders that are packages or hold packages.

    Returns:
        An existing regular file inside the URDF's folder tree or inside the package folder
        found, resolved; ``None`` when there is none (missing, or pointing elsewhere).
    """
    if not isinstance(uri, str) or not uri.strip():
        return None
    uri = uri.strip()
    here = Path(urdf_path).resolve().parent
    if uri.startswith(_PACKAGE):
        package, _, rest = uri[len(_PACKAGE) :].partition("/")
        for root in package_roots(urdf_path, package, package_dirs or ()):
            found = _contained_file(root, rest)
            if found is not None:
                return found
        return None
    if uri.startswith("file://"):
        parts = urlsplit(uri)
        if parts.netloc not in ("", "localhost"):
            return None
        uri = unquote(parts.path)
    elif "://" in uri:
        return None  # http:// and other schemes are never fetched
    return _contained_file(here, uri)


def mesh_report(
    path: str | Path, package_dirs: Sequence[str | Path] | None = None
) -> tuple[dict[str, Path], list[str]]:
    """The visual meshes of the URDF at ``path``: ``({uri: file}, [unresolved uris])``, in file order.

    Raises:
        UrdfError: the URDF cannot be read or parsed.
    """
    from ..errors import UrdfError

    data = read_user_file(path, "URDF", UrdfError, MAX_FILE_BYTES)
    doc = parse_urdf(decode_utf8(data, "URDF", UrdfError).encode("utf-8"))
    resolved: dict[str, Path] = {}
    unresolved: list[str] = []
    for _, uri in doc.meshes:
        if uri in resolved or uri in unresolved:
            continue
        found = resolve_mesh(path, uri, package_dirs)
        if found is None:
            unresolved.append(uri)
        else:
            resolved[uri] = found
    return resolved, unresolved


def mesh_filename_handler(
    urdf_path: str | Path, package_dirs: Sequence[str | Path] | None = None
) -> Callable[[str], str]:
    """A ``filename_handler`` for ``yourdfpy.URDF.load``: :func:`resolve_mesh`, or ``""`` when unresolved.

    yourdfpy skips a mesh whose handled name is not a file, so an unresolved or hostile name
    loads nothing (and the app can list it from :func:`mesh_report`).
    """

    def handler(fname: str) -> str:
        found = resolve_mesh(urdf_path, fname, package_dirs)
        return "" if found is None else str(found)

    return handler
