"""``.xacro`` robot descriptions expanded to URDF with the ``xacro`` package, without ROS and without
the network.

Most robot descriptions ship as ``robot.urdf.xacro``. :func:`expand_xacro` runs xacro (pure Python) on
the file and returns the URDF's XML. ``$(find PKG)`` resolves the way ``package://PKG`` meshes do
(:func:`kinematics.urdf.mesh.package_roots`): a folder named after the package, or whose ``package.xml``
names it, enclosing the file or beside it or one of its ancestors; then ``ROS_PACKAGE_PATH`` and
``AMENT_PREFIX_PATH``. ``args`` are xacro's ``NAME:=VALUE`` arguments. An undefined argument, macro or
property, a package that is not found or a malformed file raises :class:`~kinematics.errors.UrdfError`
naming the file and what is missing.

A xacro file is a program of its author's: its ``${…}`` expressions are evaluated by xacro (without
Python's builtins) and it may include other files and read YAML. Expand only files the user chose on
their own machine (the command line, the library); an upload from a browser is never expanded here.
"""

from __future__ import annotations

import importlib
import threading
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import UrdfError
from ..files import MAX_FILE_BYTES, decode_utf8, read_user_file
from .packages import package_roots

__all__ = ["XACRO_SUFFIX", "expand_xacro", "is_xacro", "parse_xacro_args", "read_description", "remember"]

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


def expand_xacro(
    path: str | Path, args: Mapping[str, str] | None = None, package_dirs: Sequence[str | Path] = ()
) -> str:
    """The URDF that the xacro file at ``path`` expands to.

    Args:
        path: The ``.xacro`` file (UTF-8, at most 20 MB).
        args: xacro arguments (``<xacro:arg name=…>`` values).
        package_dirs: Extra folders that are packages or hold packages, for ``$(find PKG)``.

    Raises:
        UrdfError: unreadable file, undefined argument, macro or property, unknown package, malformed
            XML or xacro; the message names the file and the cause.
    """
    p = Path(path)
    read_user_file(p, "xacro file", UrdfError, MAX_FILE_BYTES)  # regular, bounded, readable: fail early
    xacro = _xacro()
    substitution: Any = importlib.import_module("xacro.substitution_args")

    def find(package: str) -> str:
        for root in package_roots(p, package, package_dirs):
            return str(root)
        raise UrdfError(
            f"{p.name}: $(find {package}): no package {package!r} near the file, in ROS_PACKAGE_PATH "
            "or in AMENT_PREFIX_PATH (a folder named after the package, or with a package.xml naming it)"
        )

    with _LOCK:
        saved = substitution._eval_find
        substitution._eval_find = find
        try:
            xacro.init_stacks(None)
            doc = xacro.process_file(str(p), mappings={str(k): str(v) for k, v in (args or {}).items()})
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
            substitution._eval_find = saved
    return text


_EXPANDED: dict[str, bytes] = {}  # resolved xacro path -> its URDF as last expanded in this process


def remember(path: str | Path, urdf: bytes) -> None:
    """Keep ``urdf`` as the expansion of the xacro file ``path`` (what :func:`read_description` returns)."""
    _EXPANDED[str(Path(path).resolve())] = urdf


def read_description(path: str | Path, xacro_args: Mapping[str, str] | None = None) -> bytes:
    """The URDF XML of the file at ``path`` (UTF-8 bytes).

    A ``.xacro`` file is expanded (:func:`kinematics.urdf.expand.expand_xacro`) with ``xacro_args``;
    without them, its last expansion in this process is reused (the meshes and chain picker of a robot
    loaded with arguments see the same URDF), else it is expanded with none.
    """
    p = Path(path)
    if p.suffix.lower() == ".xacro":
        key = str(p.resolve())
        if xacro_args is None and key in _EXPANDED:
            return _EXPANDED[key]
        data = expand_xacro(p, xacro_args).encode("utf-8")
        remember(p, data)
        return data
    data = read_user_file(p, "URDF", UrdfError, MAX_FILE_BYTES)
    return decode_utf8(data, f"URDF {p.name!r}", UrdfError).encode("utf-8")


def _clean(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= 400 else text[:399] + "…"
