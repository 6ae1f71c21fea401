"""URDF in and out: a serial chain from a URDF file, and a URDF from any Robot.

Reading needs no mesh files: only the kinematic tree is parsed
(:mod:`kinematics.urdf.xml`, lxml on the file's bytes, no entities, no network).
The chain runs from ``base_link`` to ``tip_link``; either may be left out and a
sensible one is chosen (:mod:`kinematics.urdf.tree`: a link named ``tool0``,
``*_tcp``, ``flange``, ``ee_link`` or ``*hand*``, else the leaf with the most
moving joints, never a gripper jaw). Fixed joints are folded into the
neighbouring transforms, mimic joints become extra axes driven by the joint
they follow (a leader on a sibling branch becomes an actuated joint of the
chain), and every axis is rotated so that it moves about its local z
(:mod:`kinematics.urdf.build`). The robot is named after ``<robot name>``, its
``description`` says which chain was taken, and it starts at a ``home`` off
the singular set. Mesh files are found by :func:`resolve_mesh` and
:func:`mesh_report` (:mod:`kinematics.urdf.mesh`), never outside the URDF's
folder tree and its packages.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from xml.sax.saxutils import escape

from ..conventions import FloatArray
from ..errors import UrdfError
from ..files import decode_utf8
from ..model import Robot
from ..transforms import matrix_to_rpy, rot_z, trans
from .build import build_robot, hold_fixed_ranges, limit_notes, with_home
from .expand import expand_xacro, is_xacro, parse_xacro_args, read_description, xacro_leftover
from .mesh import mesh_filename_handler, mesh_report, resolve_mesh
from .tree import ChainInfo, Tree
from .xml import MAX_LINKS, parse_urdf

__all__ = [
    "ChainInfo",
    "MAX_LINKS",
    "chains",
    "expand_xacro",
    "is_xacro",
    "parse_xacro_args",
    "read_description",
    "mesh_filename_handler",
    "mesh_report",
    "resolve_mesh",
    "robot_from_urdf",
    "robot_from_urdf_string",
    "to_urdf",
]


def _read(
    path: str | Path,
    xacro_args: Mapping[str, str] | None = None,
    package_dirs: Mapping[str, str | Path] | None = None,
    package_path: Sequence[str | Path] = (),
) -> bytes:
    return read_description(path, xacro_args, package_path, package_dirs)


def _leftover(exc: UrdfError, data: bytes, file: str) -> UrdfError:
    """``exc``, or, when the URDF's text still holds xacro, a message that says so and what to do."""
    left = xacro_leftover(data)
    if left is None:
        return exc
    stem = file.split(".")[0] or "robot"
    where = f"{file} is" if file else "this URDF is"
    return UrdfError(
        f"{where} not expanded xacro: it still holds {left!r}, which only xacro replaces, hence: {exc}. "
        f"Open the .xacro file it was made from (jacobian-lab serve --urdf {stem}.urdf.xacro, with "
        f"--xacro-arg NAME:=VALUE and --package NAME=DIR as it needs), or expand it first "
        f"(xacro {stem}.urdf.xacro > {stem}.urdf)"
    )


def _as_bytes(text: str | bytes) -> bytes:
    if isinstance(text, bytes):
        return decode_utf8(text, "URDF", UrdfError).encode("utf-8")
    if isinstance(text, str):
        return text.encode("utf-8", errors="replace")
    raise UrdfError(f"URDF text: expected str or bytes, got {type(text).__name__}")


def robot_from_urdf(
    path: str | Path,
    base_link: str | None = None,
    tip_link: str | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_dirs: Mapping[str, str | Path] | None = None,
    package_path: Sequence[str | Path] = (),
) -> Robot:
    """Build a :class:`Robot` from the URDF file at ``path``.

    Args:
        path: A URDF file (UTF-8, at most 20 MB), or a ``.xacro`` file expanded with ``xacro_args``
            (:mod:`kinematics.urdf.expand`). Mesh files it references need not exist.
        base_link: Link whose frame is the robot's base frame (default: the root, or the link
            below the last floating/planar joint above the tip).
        tip_link: Link whose frame is the tool frame (default: see :mod:`kinematics.urdf.tree`).
        xacro_args: A xacro file's arguments (``NAME -> VALUE``; one it does not declare is refused).
        package_dirs: ROS packages by name, ``{NAME: DIR}`` (``--package NAME=DIR``), for ``$(find NAME)``
            and ``package://NAME`` meshes; looked at before anything else.
        package_path: Folders that are packages or hold packages (``--package-path``), searched like
            ``ROS_PACKAGE_PATH``.

    Raises:
        UrdfError: the file is unreadable (missing, not a regular file, too large, not UTF-8),
            not well-formed XML (line and column given), not a tree, names an unknown link,
            has a malformed number (joint and attribute named) or a floating/planar joint
            on the chain, or has no serial chain with a moving joint.
    """
    p = Path(path)
    stem = p.name.split(".")[0] or p.stem
    data = _read(p, xacro_args, package_dirs, package_path)
    try:
        return _robot(data, base_link, tip_link, stem, str(p.resolve()), p.name)
    except UrdfError as exc:
        if is_xacro(p):
            raise
        raise _leftover(exc, data, p.name) from None


def robot_from_urdf_string(
    text: str | bytes, base_link: str | None = None, tip_link: str | None = None, name: str = "urdf"
) -> Robot:
    """Like :func:`robot_from_urdf`, from the URDF's XML text (``name``: used when ``<robot>`` has none)."""
    data = _as_bytes(text)
    try:
        return _robot(data, base_link, tip_link, name, None, "")
    except UrdfError as exc:
        raise _leftover(exc, data, "") from None


def chains(
    path: str | Path,
    base_link: str | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
    package_dirs: Mapping[str, str | Path] | None = None,
    package_path: Sequence[str | Path] = (),
) -> list[ChainInfo]:
    """The serial chains of the URDF at ``path``, for a chain picker.

    The default chain (the one :func:`robot_from_urdf` opens without a tip) comes
    first with ``is_default=True``, then one chain per leaf link (and, for a leaf
    below a gripper jaw, the chain cut above the jaw), each with a moving joint.
    """
    data = _read(path, xacro_args, package_dirs, package_path)
    try:
        return Tree(hold_fixed_ranges(parse_urdf(data))).chains(base_link)
    except UrdfError as exc:
        if is_xacro(path):
            raise
        raise _leftover(exc, data, Path(path).name) from None


def _robot(
    data: bytes, base_link: str | None, tip_link: str | None, stem: str, urdf_path: str | None, file: str
) -> Robot:
    doc = hold_fixed_ranges(parse_urdf(data))
    tree = Tree(doc)
    choice = tree.choose(base_link, tip_link)
    name = doc.name or stem
    where = f" of {file}" if file else ""
    description = " ".join(
        (
            f"Chain from link {choice.base_link!r} to link {choice.tip_link!r}{where} ({choice.reason}).",
            *limit_notes(choice.path),
        )
    )
    robot = build_robot(
        tree,
        choice,
        name,
        title=name,
        description=description,
        source=f"URDF file {file}" if file else "URDF",
        urdf_path=urdf_path,
    )
    return with_home(robot)


def _attr(text: str) -> str:
    return escape(text, {'"': "&quot;"})


def _origin_xml(T: FloatArray) -> str:
    xyz = " ".join(repr(float(v)) for v in T[:3, 3])
    rpy = " ".join(repr(float(v)) for v in matrix_to_rpy(T[:3, :3]))
    return f'<origin xyz="{xyz}" rpy="{rpy}"/>'


def to_urdf(robot: Robot) -> str:
    """A URDF document with the same kinematics as ``robot`` (links ``base``, ``link1``…, ``tool``).

    Each axis becomes a joint moving about z; fixed transforms go into the
    joint origins; the base transform into the first joint and the tool
    transform into a fixed joint ``tool_joint``. Mimic axes are written as
    ``<mimic>``. Joint names are those of the robot.
    """
    fixed = robot.fixed_transforms()
    out = ['<?xml version="1.0"?>', f'<robot name="{_attr(robot.name or "robot")}">', '  <link name="base"/>']
    seen: set[int] = set()
    for k in range(len(robot.axes)):
        out.append(f'  <link name="link{k + 1}"/>')
    out.append('  <link name="tool"/>')
    for k, ax in enumerate(robot.axes):
        parent = "base" if k == 0 else f"link{k}"
        kind = "revolute" if ax.kind == "revolute" else "prismatic"
        joint = robot.joints[ax.joint_index]
        mimic = ax.joint_index in seen
        if not mimic and ax.multiplier != 1.0:
            raise UrdfError(
                f"axis {ax.name!r} is the first axis of joint {joint.name!r} but has multiplier "
                f"{ax.multiplier}: URDF cannot express that"
            )
        origin = fixed[k]
        if not mimic and ax.offset != 0.0:
            # URDF has no joint offset: M(q + o) = M(o) M(q) about the same axis, so fold it in.
            origin = origin @ (rot_z(ax.offset) if kind == "revolute" else trans(z=ax.offset))
        jname = joint.name if not mimic else f"{ax.name}_axis{k + 1}"
        lim = joint.qlim or ((-1e3, 1e3) if kind == "prismatic" else (-4 * math.pi, 4 * math.pi))
        out += [
            f'  <joint name="{_attr(jname)}" type="{kind}">',
            f'    <parent link="{parent}"/>',
            f'    <child link="link{k + 1}"/>',
            f"    {_origin_xml(origin)}",
            '    <axis xyz="0 0 1"/>',
            f'    <limit lower="{lim[0]!r}" upper="{lim[1]!r}" effort="0" velocity="0"/>',
        ]
        if mimic:
            factors = f'multiplier="{ax.multiplier!r}" offset="{ax.offset!r}"'
            out.append(f'    <mimic joint="{_attr(joint.name)}" {factors}/>')
        seen.add(ax.joint_index)
        out.append("  </joint>")
    out += [
        '  <joint name="tool_joint" type="fixed">',
        f'    <parent link="link{len(robot.axes)}"/>',
        '    <child link="tool"/>',
        f"    {_origin_xml(fixed[-1])}",
        "  </joint>",
        "</robot>",
    ]
    return "\n".join(out) + "\n"
