"""``.xacro`` robot descriptions expanded to URDF with the ``xacro`` package, without ROS and without
the network.

Most robot descriptions ship as ``robot.urdf.xacro``. :func:`expand_xacro` runs xacro (pure Python) on
the file and returns the URDF's XML. ``$(find PKG)`` resolves the way ``package://PKG`` meshes do
(:func:`kinematics.urdf.packages.package_roots`): the folder the user mapped it to (``named``,
``--package NAME=DIR``); a folder named after the package, or whose ``package.xml`` names it, enclosing
the file or beside it or one of its ancestors; then ``package_dirs`` (``--package-path``),
``ROS_PACKAGE_PATH`` and ``AMENT_PREFIX_PATH``. ``args`` are xacro's ``NAME:=VALUE`` arguments; one the
file does not declare is refused, naming those it does. An undefined argument, macro or property, a
package that is not found (the message says where it was looked for and how to map it), a file of
macros only or a malformed file raises :class:`~kinematics.errors.UrdfError` naming the file and what
is missing.

A xacro file is a program of its author's: its ``${…}`` expressions are evaluated by xacro (without
Python's builtins) and it may include other files and read YAML. Expand only files the user chose on
their own machine (the command line, the library); an upload from a browser is never expanded here.
"""

from __future__ import annotations

import importlib
import os
import re
import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import UrdfError
from ..files import MAX_FILE_BYTES, decode_utf8, read_user_file
from .packages import found_package, looked_in, package_roots, use_packages

__all__ = [
    "XACRO_SUFFIX",
    "expand_xacro",
    "is_xacro",
    "parse_xacro_args",
    "read_description",
    "remember",
    "xacro_leftover",
]

XACRO_SUFFIX = ".xacro"

_LOCK = threading.Lock()  # xacro keeps its state in module globals: one expansion at a time


def is_xacro(path: str | Path) -> bool:
    """Whether ``path`` names a xacro file (``arm.xacro``, ``arm.urdf.xacro``)."""
    return Path(path).suffix.lower() == XACRO_SUFFIX


def parse_xacro_args(items: Sequence[str]) -> dict[str, str]:
    """``["NAME:=VALUE", …]`` (``--xacro-arg``) as a mapping.

    Raises:
        UrdfError: an item without ``:=`` or with an empty name.
    """
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = str(item).partition(":=")
        if not sep or not name.strip() or not name.strip().replace("_", "a").isalnum():
            raise UrdfError(f"xacro argument {item!r}: expected NAME:=VALUE (e.g. prefix:=left_)")
        out[name.strip()] = value
    return out


def _xacro() -> Any:
    try:
        return importlib.import_module("xacro")
    except ImportError as exc:  # a dependency of the project: only a broken install lacks it
        raise UrdfError("reading .xacro files needs the 'xacro' package (pip install xacro)") from exc


class _Declared(dict[str, str]):
    """xacro's argument table that notes the names the file declares (``<xacro:arg name=…>`` asks
    ``name in table`` once per declaration)."""

    def __init__(self, given: Mapping[str, str]) -> None:
        super().__init__(given)
        self.declared: set[str] = set()

    def __contains__(self, name: object) -> bool:
        if isinstance(name, str):
            self.declared.add(name)
        return super().__contains__(name)


def expand_xacro(
    path: str | Path,
    args: Mapping[str, str] | None = None,
    package_dirs: Sequence[str | Path] = (),
    named: Mapping[str, str | Path] | None = None,
) -> str:
    """The URDF that the xacro file at ``path`` expands to.

    Args:
        path: The ``.xacro`` file (UTF-8, at most 20 MB).
        args: xacro arguments (``<xacro:arg name=…>`` values).
        package_dirs: Extra folders that are packages or hold packages, for ``$(find PKG)``.
        named: Package name -> its folder (``--package NAME=DIR``), looked at first.

    Raises:
        UrdfError: unreadable file, an argument the file does not declare, undefined argument, macro
            or property, unknown package, a file of macros only, malformed XML or xacro; the message
            names the file and the cause.
    """
    p = Path(path)
    read_user_file(p, "xacro file", UrdfError, MAX_FILE_BYTES)  # regular, bounded, readable: fail early
    xacro = _xacro()
    substitution: Any = importlib.import_module("xacro.substitution_args")

    def find(package: str) -> str:  # near the file, or near the included file that asks
        stack = [f for f in getattr(xacro, "filestack", None) or [] if f]
        near = [p] + ([Path(stack[-1])] if stack and Path(stack[-1]) != p else [])  # and the includer
        for base in near:
            for root in package_roots(base, package, package_dirs, named):
                found_package(p, root)
                return str(root)
        raise UrdfError(missing_package(p, package, package_dirs, named))

    with _LOCK:
        saved, saved_parse = substitution._eval_find, xacro.parse
        substitution._eval_find = find
        xacro.parse = _legacy_tags(saved_parse)
        try:
            found_package(p, None)
            xacro.init_stacks(None)
            table = _Declared({str(k): str(v) for k, v in (args or {}).items()})
            doc = xacro.process_file(str(p), mappings=table)
            _check_args(p, table)
            if not doc.getElementsByTagName("link"):
                raise UrdfError(_macros_only(p))
            text: str = doc.toxml()
        except UrdfError:
            raise
        except xacro.XacroException as exc:
            cause = getattr(exc, "exc", None)
            if isinstance(cause, UrdfError):
                raise cause from None
            if isinstance(cause, substitution.ArgException):
                raise UrdfError(
                    f"{p.name}: xacro argument {cause} is not defined: give it as --xacro-arg {cause}:=VALUE"
                ) from None
            raise UrdfError(f"{p.name}: xacro: {_clean(exc)}") from None
        except Exception as exc:  # expat errors, a bad include, a YAML error: xacro's own words
            raise UrdfError(
                f"{p.name}: xacro could not expand it: {type(exc).__name__}: {_clean(exc)}"
            ) from None
        finally:
            substitution._eval_find, xacro.parse = saved, saved_parse
    return text


_LEGACY = ("property", "macro")
"""Tags that xacro 1 read without the ``xacro:`` prefix (KUKA's kr210l150_macro.xacro writes
``<property name="deg" …/>``) and xacro 2 no longer does: read as ``xacro:property`` and ``xacro:macro``."""


def _legacy_tags(parse: Any) -> Any:
    """xacro's ``parse`` that also renames the unprefixed :data:`_LEGACY` tags of a xacro document (one
    whose root declares the ``xacro`` namespace; URDF has no element of those names)."""

    def legacy_parse(inp: Any, filename: Any = None) -> Any:
        doc = parse(inp, filename)
        root = getattr(doc, "documentElement", doc)
        if root is not None and root.getAttribute("xmlns:xacro"):
            for tag in _LEGACY:
                for node in list(root.getElementsByTagName(tag)):
                    node.tagName = node.nodeName = f"xacro:{tag}"
        return doc

    return legacy_parse


def missing_package(
    path: Path, package: str, package_dirs: Sequence[str | Path], named: Mapping[str, str | Path] | None
) -> str:
    """The message for ``$(find package)`` not found: the package, every place looked, how to map it."""
    places = "; ".join(looked_in(path, package_dirs, named))
    return (
        f"{path.name}: $(find {package}): no package {package!r} found (a folder named {package!r}, or with "
        f"a package.xml naming it). Looked in: {places}. Map it to its folder with --package {package}=DIR "
        f"(package_dirs={{{package!r}: DIR}} in robots.load), or give the folder that holds it with "
        "--package-path DIR"
    )


def _check_args(path: Path, table: _Declared) -> None:
    unknown = sorted(set(table) - table.declared)
    if unknown:
        declared = ", ".join(sorted(table.declared)) or "none"
        raise UrdfError(
            f"{path.name}: xacro argument {', '.join(unknown)} is not an argument of the file; "
            f"it declares: {declared}"
        )


_MACRO = re.compile(rb"<xacro:macro\s[^>]*?name\s*=\s*[\"']([^\"']+)")


def _macros_only(path: Path) -> str:
    """The message for a xacro file that expands to no link: its macros, and the files that call them."""
    try:
        source = path.read_bytes()[:MAX_FILE_BYTES]
    except OSError:
        source = b""
    macros = [m.decode("utf-8", "replace") for m in _MACRO.findall(source)][:5]
    callers = _includers(path)
    what = f"defines the macro(s) {', '.join(macros)} but no robot" if macros else "expands to no <link>"
    open_ = (
        f"open the xacro file that uses them, e.g. {', '.join(callers)}"
        if callers
        else "open the xacro file that includes it and calls its macros (often NAME.urdf.xacro in the "
        "package's urdf/ or robots/ folder)"
    )
    return f"{path.name}: a xacro file of macros only: it {what} (it is meant to be included); {open_}"


def _includers(path: Path, limit: int = 3) -> list[str]:
    """Up to ``limit`` .xacro files in the package (the file's folder, its parent and their sub-folders:
    200 folders and 400 files at most, hidden folders left out) that name ``path``'s file: the robot
    files that include it."""
    here = path.resolve().parent
    found: list[str] = []
    seen = folders = 0
    for top in (here, here.parent):
        for folder, subs, names in os.walk(top):
            subs[:] = sorted(d for d in subs if not d.startswith("."))
            folders += 1
            if folders > 200:
                return found
            for n in sorted(names):
                if not n.endswith(XACRO_SUFFIX) or n == path.name:
                    continue
                seen += 1
                f = Path(folder) / n
                try:
                    if f.stat().st_size < 1024 * 1024 and path.name.encode() in f.read_bytes():
                        shown = os.path.relpath(f, Path.cwd())
                        if shown not in found:
                            found.append(shown)
                except (OSError, ValueError):  # ValueError: relpath across Windows drives
                    continue
                if len(found) >= limit or seen >= 400:
                    return found
    return found


_LEFTOVER = re.compile(r"\$\((?:find|optenv|env|arg|eval|dirname|anon)\b[^)]*\)|\$\{[^}]*\}|<xacro:[\w]+")


def xacro_leftover(text: str | bytes) -> str | None:
    """The first piece of xacro left in a URDF's text (``$(optenv …)``, ``$(find …)``, ``${…}``,
    ``<xacro:…``), or ``None``."""
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    match = _LEFTOVER.search(text)
    return match.group(0)[:80] if match else None


_EXPANDED: dict[str, bytes] = {}  # resolved xacro path -> its URDF as last expanded in this process
_EXPANDED_WITH: dict[str, object] = {}  # resolved xacro path -> the packages of that expansion


def remember(path: str | Path, urdf: bytes) -> None:
    """Keep ``urdf`` as the expansion of the xacro file ``path`` (what :func:`read_description` returns)."""
    _EXPANDED[str(Path(path).resolve())] = urdf


def read_description(
    path: str | Path,
    xacro_args: Mapping[str, str] | None = None,
    package_dirs: Sequence[str | Path] = (),
    named: Mapping[str, str | Path] | None = None,
) -> bytes:
    """The URDF XML of the file at ``path`` (UTF-8 bytes).

    A ``.xacro`` file is expanded (:func:`kinematics.urdf.expand.expand_xacro`) with ``xacro_args`` and
    the packages given; without arguments (and without packages, or with those of that expansion), its
    last expansion in this process is reused (the meshes and chain picker of a robot loaded with
    arguments see the same URDF), else it is expanded with none. The packages given are remembered for
    the file's meshes (:func:`kinematics.urdf.packages.use_packages`).
    """
    p = Path(path)
    if package_dirs or named:
        use_packages(p, package_dirs, named)
    if p.suffix.lower() == ".xacro":
        key = str(p.resolve())
        given = (tuple(map(str, package_dirs)), tuple(sorted((k, str(v)) for k, v in (named or {}).items())))
        same = given == ((), ()) or _EXPANDED_WITH.get(key) == given
        if xacro_args is None and same and key in _EXPANDED:
            return _EXPANDED[key]
        data = expand_xacro(p, xacro_args, package_dirs, named).encode("utf-8")
        remember(p, data)
        _EXPANDED_WITH[key] = given
        return data
    data = read_user_file(p, "URDF", UrdfError, MAX_FILE_BYTES)
    return decode_utf8(data, f"URDF {p.name!r}", UrdfError).encode("utf-8")


def _clean(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= 400 else text[:399] + "…"
