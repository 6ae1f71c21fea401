"""Where a URDF's mesh files are, without ever leaving the folders the user pointed at.

``package://PKG/rest`` is looked up in a folder named PKG: the URDF's own
folder or one of its ancestors when it is named PKG, a PKG folder next to the
URDF or next to one of its ancestors (``package:///PKG/rest``, with an empty
name, as ``package://PKG/rest``), then the ``package_dirs`` given, the
``ROS_PACKAGE_PATH`` entries (a package, or a folder of packages) and
``AMENT_PREFIX_PATH`` entries (``PREFIX/share/PKG``). Any other file name is
relative to the URDF's folder (``file://`` URIs and absolute paths too, but
only when they point inside it, or inside a package folder that a xacro file's
``$(find PKG)`` resolved to), or, when it is not there and its first part is
the name of that folder or of an ancestor (a path from the package's top, as
pybullet writes them), relative to that folder's parent, inside that folder.

The result is always a mesh file (``.stl``, ``.dae``, ``.obj``, ...) inside the
URDF's own folder tree or inside the package folder found: the candidate is
resolved (symbolic links followed, ``..`` removed) and then checked for
containment, so ``/etc/passwd``,
``file:///etc/passwd``, ``../../x.stl``, ``package://../../etc/x`` and links
that point outside resolve to ``None``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from urllib.parse import unquote, urlsplit

from .expand import read_description
from .packages import ANCESTOR_LEVELS, found_packages, package_name, package_roots
from .xml import parse_urdf

__all__ = [
    "resolve_mesh",
    "mesh_report",
    "mesh_filename_handler",
    "package_name",
    "package_roots",
    "MESH_SUFFIXES",
]

_PACKAGE = "package://"
MESH_SUFFIXES = frozenset({".stl", ".dae", ".obj", ".ply", ".glb", ".gltf", ".off", ".3mf"})
"""File types a mesh may have (case-insensitive): nothing else is ever returned."""


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
        if not package:  # package:///PKG/rest (Talos's files): the first part names the package
            package, _, rest = rest.partition("/")
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
    found = _contained_file(here, uri)
    if found is None and Path(uri).is_absolute():
        # $(find PKG)/meshes/x.stl of a xacro file: absolute once expanded, inside the package folder found
        for root in found_packages(urdf_path):
            if _inside(Path(uri), root):
                return _contained_file(root, str(Path(uri).relative_to(root)))
    if found is None and not Path(uri).is_absolute():
        # A path from the package's top (pybullet_data's differential/diff_ring.stl, written in
        # differential/x.urdf): its first part names the URDF's folder or an ancestor, inside which it
        # must then lie.
        first, _, rest = uri.replace("\\", "/").partition("/")
        for folder in [here, *here.parents][: ANCESTOR_LEVELS + 1]:
            if rest and folder.name == first:
                return _contained_file(folder, rest)
    return found


def mesh_report(
    path: str | Path, package_dirs: Sequence[str | Path] | None = None
) -> tuple[dict[str, Path], list[str]]:
    """The visual meshes of the URDF (or xacro file, as last expanded) at ``path``:
    ``({uri: file}, [unresolved uris])``, in file order.

    Raises:
        UrdfError: the URDF cannot be read or parsed.
    """
    doc = parse_urdf(read_description(path))
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
