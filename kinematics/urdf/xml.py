"""The kinematic content of a URDF document, parsed strictly from its bytes with lxml.

Only what the kinematics uses is read: the robot name, link names (and their
visual mesh file names, for :mod:`kinematics.urdf.mesh`), and each joint's
type, parent, child, ``<origin>``, ``<axis>``, ``<limit>`` and ``<mimic>``.
Geometry (``<capsule>``, ``<plane>``, unknown tags), inertia, transmissions and
simulator extensions are never looked at, so they cannot make a file unloadable.

The parser resolves no external entity, never touches the network and keeps
libxml2's depth and size limits; a document with a DOCTYPE is refused before
parsing. Every number is checked: the right count, space-separated, finite.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..conventions import FloatArray
from ..errors import UrdfError
from ..transforms import rpy_to_matrix

__all__ = ["UrdfDoc", "UrdfJoint", "parse_urdf", "MAX_LINKS", "JOINT_TYPES"]

Element = Any
"""An lxml element (lxml is installed without type information)."""

MAX_LINKS = 1000
"""Most links (and joints) a URDF may have: real robots have at most a few hundred."""

MAX_MAGNITUDE = 1e6
"""Largest magnitude of a length [m], angle [rad], axis component or mimic factor in a URDF."""

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")

_DECLARATION = re.compile(rb"\A\s*(<\?xml[^>]*\?>)?", re.DOTALL)


@dataclass(frozen=True, eq=False)
class UrdfJoint:
    """One ``<joint>`` as written in the file (numbers in [m] and [rad]).

    Attributes:
        name, type, parent, child: As in the file.
        origin: 4×4 transform from the parent link frame to the joint (child link) frame.
        axis: Unit axis in the joint frame (default x, as the URDF specification says).
        lower, upper: ``<limit>`` bounds, or ``None`` when absent.
        mimic: (leader joint name, multiplier, offset) or ``None``.
        line: Line of the ``<joint>`` element in the file.
    """

    name: str
    type: str
    parent: str
    child: str
    origin: FloatArray
    axis: FloatArray
    lower: float | None = None
    upper: float | None = None
    mimic: tuple[str, float, float] | None = None
    line: int = 0

    @property
    def moving(self) -> bool:
        """True for revolute, continuous and prismatic joints."""
        return self.type in ("revolute", "continuous", "prismatic")


@dataclass(frozen=True, eq=False)
class UrdfDoc:
    """The parsed document: robot name, links in file order, joints in file order, visual meshes."""

    name: str
    links: tuple[str, ...]
    joints: tuple[UrdfJoint, ...]
    meshes: tuple[tuple[str, str], ...] = field(default=())  # (link name, filename) of visual meshes


def _prepare(data: bytes) -> bytes:
    """Drop what makes a valid document unparsable by libxml2 without changing line numbers.

    The XML declaration goes (the text is checked to be UTF-8 beforehand, so its
    encoding is known, and libxml2 refuses versions such as "0.0"), as does
    whitespace before it and NUL bytes or whitespace after the document.
    """
    m = _DECLARATION.match(data)
    head = m.group(0) if m else b""
    return b"\n" * head.count(b"\n") + data[len(head) :].rstrip(b"\x00 \t\r\n")


def _element_tree(data: bytes) -> Element:
    from lxml import etree

    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise UrdfError("URDF must not contain a DOCTYPE or ENTITY declarations")
    parser = etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        huge_tree=False,
        load_dtd=False,
        dtd_validation=False,
        remove_comments=True,
        remove_pis=True,
    )
    try:
        return etree.fromstring(_prepare(data), parser)
    except etree.XMLSyntaxError as exc:
        line, column = exc.position if exc.position else (exc.lineno, 0)
        raise UrdfError(f"cannot parse URDF: line {line}, column {column}: {exc.msg}") from None


def _local(tag: object) -> str:
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


MAX_NUMBER_CHARACTERS = 64
"""The longest text read as one number (a 60 kB digit string is refused, not read as ∞)."""


def _clip(text: str, limit: int = 40) -> str:
    """``text`` itself, or its start and its length when it is longer than ``limit`` characters."""
    return text if len(text) <= limit else f"{text[:limit]}… ({len(text)} characters)"


def _check_length(tok: str, what: str) -> None:
    if len(tok) > MAX_NUMBER_CHARACTERS:
        raise UrdfError(
            f"{what}: a number of {len(tok)} characters; a number has at most {MAX_NUMBER_CHARACTERS}"
        )


def _numbers(el: Element, attr: str, count: int, where: str, default: tuple[float, ...]) -> FloatArray:
    text = el.get(attr) if el is not None else None
    if text is None:
        return np.array(default, dtype=float)
    what = f'{where}: <{_local(el.tag)} {attr}="{_clip(text)}">'
    if "," in text:
        raise UrdfError(f"{what}: numbers must be separated by spaces, not commas")
    tokens = text.split()
    if len(tokens) != count:
        raise UrdfError(f"{what}: expected {count} numbers, found {len(tokens)}")
    values = []
    for tok in tokens:
        _check_length(tok, what)
        try:
            v = float(tok)
        except ValueError:
            raise UrdfError(f"{what}: {_clip(tok)!r} is not a number") from None
        if not math.isfinite(v):
            raise UrdfError(f"{what}: {tok!r} is not a finite number")
        if abs(v) > MAX_MAGNITUDE:
            raise UrdfError(f"{what}: {tok!r} is beyond ±{MAX_MAGNITUDE:g}")
        values.append(v)
    return np.array(values)


def _number(el: Element, attr: str, where: str, default: float | None, limit: bool = False) -> float | None:
    """A single number; ``limit``: a joint limit, where any magnitude (even ±inf) means what it says."""
    text = el.get(attr)
    if text is None:
        return default
    what = f'{where}: <{_local(el.tag)} {attr}="{_clip(text)}">'
    _check_length(text.strip(), what)
    try:
        v = float(text.strip())
    except ValueError:
        raise UrdfError(f"{what}: not a number") from None
    if math.isnan(v) or (math.isinf(v) and not limit):
        raise UrdfError(f"{what}: expected a finite number")
    if abs(v) > MAX_MAGNITUDE and not limit:
        raise UrdfError(f"{what}: expected a number within ±{MAX_MAGNITUDE:g}")
    return v


def _name(el: Element, where: str) -> str:
    name: str | None = el.get("name")
    if name is None or not name.strip():
        raise UrdfError(f"{where}: missing or empty name attribute")
    return name


def _link_ref(el: Element, tag: str, where: str) -> str:
    ref = [c for c in el if _local(c.tag) == tag]
    if len(ref) != 1:
        raise UrdfError(f"{where}: expected one <{tag} link=...>, found {len(ref)}")
    link: str | None = ref[0].get("link")
    if link is None or not link.strip():
        raise UrdfError(f"{where}: <{tag}> has no link attribute")
    return link


def _child(el: Element, tag: str) -> Element | None:
    for c in el:
        if _local(c.tag) == tag:
            return c
    return None


def _joint(el: Element) -> UrdfJoint:
    line = el.sourceline or 0
    name = _name(el, f"<joint> at line {line}")
    where = f"joint {name!r} (line {line})"
    kind = el.get("type")
    if kind not in JOINT_TYPES:
        raise UrdfError(f"{where}: type {kind!r} is not one of {', '.join(JOINT_TYPES)}")
    parent, child = _link_ref(el, "parent", where), _link_ref(el, "child", where)
    o = _child(el, "origin")
    T = np.eye(4)
    T[:3, 3] = _numbers(o, "xyz", 3, where, (0.0, 0.0, 0.0))
    T[:3, :3] = rpy_to_matrix(*_numbers(o, "rpy", 3, where, (0.0, 0.0, 0.0)))
    axis = _numbers(_child(el, "axis"), "xyz", 3, where, (1.0, 0.0, 0.0))
    norm = float(np.linalg.norm(axis))
    if kind in ("revolute", "continuous", "prismatic") and not norm > 1e-9:
        raise UrdfError(f"{where}: <axis xyz>: the axis {axis.tolist()} has zero length")
    lower = upper = None
    lim = _child(el, "limit")
    if lim is not None:
        lower = _number(lim, "lower", where, 0.0, limit=True)
        upper = _number(lim, "upper", where, 0.0, limit=True)
    mimic = None
    m = _child(el, "mimic")
    if m is not None:
        leader = m.get("joint")
        if leader is None or not leader.strip():
            raise UrdfError(f"{where}: <mimic> has no joint attribute")
        mult = _number(m, "multiplier", where, 1.0)
        off = _number(m, "offset", where, 0.0)
        mimic = (leader, float(mult), float(off))  # type: ignore[arg-type]
    unit = axis / norm if norm > 1e-9 else axis
    return UrdfJoint(name, kind, parent, child, T, unit, lower, upper, mimic, line)


def parse_urdf(data: bytes) -> UrdfDoc:
    """Parse a URDF document from its (UTF-8) bytes.

    Raises:
        UrdfError: not well-formed XML (with line and column), a DOCTYPE, a root other than
            ``<robot>``, no link, more than :data:`MAX_LINKS` links or joints, duplicate names,
            a malformed number (naming the joint, element and attribute).
    """
    root = _element_tree(data)
    if _local(root.tag) != "robot":
        raise UrdfError(f"URDF: the root element is <{_local(root.tag)}>, expected <robot>")
    links_el = [c for c in root if _local(c.tag) == "link"]
    joints_el = [c for c in root if _local(c.tag) == "joint"]
    for what, items in (("links", links_el), ("joints", joints_el)):
        if len(items) > MAX_LINKS:
            raise UrdfError(f"URDF has {len(items)} {what}; Jacobian Lab reads at most {MAX_LINKS}")
    if not links_el:
        raise UrdfError("URDF has no <link>: expected at least one link")
    links: list[str] = []
    meshes: list[tuple[str, str]] = []
    for el in links_el:
        name = _name(el, f"<link> at line {el.sourceline}")
        links.append(name)
        for visual in (c for c in el if _local(c.tag) == "visual"):
            for mesh in visual.iter("{*}mesh", "mesh"):
                if mesh.get("filename"):
                    meshes.append((name, mesh.get("filename")))
    joints = [_joint(el) for el in joints_el]
    for what, names in (("link", links), ("joint", [j.name for j in joints])):
        seen: set[str] = set()
        for n in names:
            if n in seen:
                raise UrdfError(f"URDF has two {what}s named {n!r}: {what} names must be unique")
            seen.add(n)
    name = (root.get("name") or "").strip()
    return UrdfDoc(name, tuple(links), tuple(joints), tuple(meshes))
