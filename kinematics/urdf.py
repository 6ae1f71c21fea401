"""URDF in and out: a serial chain from a URDF file (via yourdfpy), and a URDF from any Robot.

Reading needs no mesh files: only the kinematic tree is parsed. The chain
runs from ``base_link`` (default: the root link) to ``tip_link`` (default: the
single leaf below ``base_link``). Fixed joints are folded into the
neighbouring transforms, mimic joints become extra axes driven by the joint
they follow, and every axis is rotated so that it moves about its local z.
"""

from __future__ import annotations

import io
import logging
import math
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

from .errors import UrdfError
from .model import Axis, Joint, Robot
from .transforms import matrix_to_rpy, rot_z, rotation_z_to, trans

__all__ = ["robot_from_urdf", "robot_from_urdf_string", "to_urdf"]

_MOVING = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
_MAX_BYTES = 20 * 1024 * 1024


def robot_from_urdf(path: str | Path, base_link: str | None = None, tip_link: str | None = None) -> Robot:
    """Build a :class:`Robot` from the URDF file at ``path``.

    Args:
        path: A ``.urdf`` file. Mesh files it references need not exist.
        base_link: Link whose frame is the robot's base frame (default: the root).
        tip_link: Link whose frame is the tool frame (default: the single leaf).

    Raises:
        UrdfError: The file is unreadable, not a tree, names an unknown link,
            has several leaves and no ``tip_link``, or uses floating/planar joints.
    """
    p = Path(path)
    try:
        size = p.stat().st_size
    except OSError as exc:
        raise UrdfError(f"cannot read URDF {str(path)!r}: {exc.strerror or exc}") from None
    if size > _MAX_BYTES:
        raise UrdfError(f"URDF {p.name!r} is {size} bytes; the limit is {_MAX_BYTES}")
    text = p.read_text(encoding="utf-8", errors="replace")
    robot = robot_from_urdf_string(text, base_link, tip_link, name=p.stem)
    return _replace(robot, urdf_path=str(p.resolve()))


def _replace(robot: Robot, **changes: object) -> Robot:
    import dataclasses

    return dataclasses.replace(robot, **changes)  # type: ignore[arg-type]


def _parse(text: str):
    import yourdfpy

    if "<!ENTITY" in text or "<!DOCTYPE" in text:
        raise UrdfError("URDF must not contain a DOCTYPE or ENTITY declarations")
    logging.getLogger("yourdfpy").setLevel(logging.ERROR)
    try:
        return yourdfpy.URDF.load(
            io.StringIO(text), build_scene_graph=False, load_meshes=False, load_collision_meshes=False
        )
    except Exception as exc:  # yourdfpy/lxml raise many types on malformed input
        raise UrdfError(f"cannot parse URDF: {type(exc).__name__}: {exc}") from None


def robot_from_urdf_string(
    text: str, base_link: str | None = None, tip_link: str | None = None, name: str = "urdf"
) -> Robot:
    """Like :func:`robot_from_urdf`, from the URDF's XML text."""
    model = _parse(text).robot
    links = [link.name for link in model.links]
    if not links:
        raise UrdfError("URDF has no <link>")
    by_child: dict[str, object] = {}
    children: dict[str, list[str]] = {name_: [] for name_ in links}
    for j in model.joints:
        for end in (j.parent, j.child):
            if end not in children:
                raise UrdfError(f"joint {j.name!r} refers to unknown link {end!r}")
        if j.child in by_child:
            raise UrdfError(
                f"URDF is not a tree: link {j.child!r} is the child of joints "
                f"{by_child[j.child].name!r} and {j.name!r}"  # type: ignore[attr-defined]
            )
        by_child[j.child] = j
        children[j.parent].append(j.child)
    roots = [n for n in links if n not in by_child]
    if len(roots) != 1:
        raise UrdfError(
            "URDF is not a tree: expected exactly one root link, found "
            f"{len(roots)}: {', '.join(roots) or 'none (the joints form a cycle)'}"
        )
    base = base_link or roots[0]
    if base not in children:
        raise UrdfError(f"unknown base_link {base!r}; links: {', '.join(links)}")
    if tip_link is None:
        leaves, stack = [], [base]
        while stack:
            link = stack.pop()
            if children[link]:
                stack.extend(children[link])
            else:
                leaves.append(link)
        if len(leaves) != 1:
            raise UrdfError(
                f"the tree below {base!r} has {len(leaves)} leaves ({', '.join(sorted(leaves))}); "
                "choose one as tip_link"
            )
        tip_link = leaves[0]
    if tip_link not in children:
        raise UrdfError(f"unknown tip_link {tip_link!r}; links: {', '.join(links)}")
    path = []
    link = tip_link
    while link != base:
        if link not in by_child:
            raise UrdfError(f"tip_link {tip_link!r} is not below base_link {base!r}")
        j = by_child[link]
        path.append(j)
        link = j.parent  # type: ignore[attr-defined]
    path.reverse()
    return _chain_from_joints(path, name)


def _chain_from_joints(path: list, name: str) -> Robot:
    for j in path:
        if j.type in ("floating", "planar"):
            raise UrdfError(
                f"joint {j.name!r} is {j.type}: only revolute, continuous, prismatic and fixed joints "
                "form a serial arm"
            )
        if j.type not in _MOVING and j.type != "fixed":
            raise UrdfError(f"joint {j.name!r} has unknown type {j.type!r}")
    actuated = [j for j in path if j.type in _MOVING and j.mimic is None]
    index = {j.name: i for i, j in enumerate(actuated)}
    joints = []
    for j in actuated:
        qlim = None
        if j.type != "continuous" and j.limit is not None and j.limit.lower is not None:
            lo, hi = float(j.limit.lower), float(j.limit.upper if j.limit.upper is not None else 0.0)
            qlim = (lo, hi) if math.isfinite(lo) and math.isfinite(hi) and lo < hi else None
        joints.append(Joint(j.name, _MOVING[j.type], qlim))
    axes = []
    pending = np.eye(4)
    for j in path:
        origin = np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=float)
        if not np.all(np.isfinite(origin)):
            raise UrdfError(f"joint {j.name!r}: origin has a non-finite number")
        if j.type == "fixed":
            pending = pending @ origin
            continue
        axis = np.array([1.0, 0, 0] if j.axis is None else j.axis, dtype=float)
        if not np.all(np.isfinite(axis)) or np.linalg.norm(axis) < 1e-9:
            raise UrdfError(f"joint {j.name!r}: axis {axis.tolist()} is not a finite non-zero vector")
        A = np.eye(4)
        A[:3, :3] = rotation_z_to(axis)
        if j.mimic is not None:
            if j.mimic.joint not in index:
                raise UrdfError(
                    f"joint {j.name!r} mimics {j.mimic.joint!r}, which is not an actuated joint of the chain"
                )
            k = index[j.mimic.joint]
            mult = 1.0 if j.mimic.multiplier is None else float(j.mimic.multiplier)
            off = 0.0 if j.mimic.offset is None else float(j.mimic.offset)
        else:
            k, mult, off = index[j.name], 1.0, 0.0
        axes.append(Axis(j.name, _MOVING[j.type], k, mult, off, pending @ origin @ A, A.T.copy()))
        pending = np.eye(4)
    if not axes:
        raise UrdfError("the chain between base_link and tip_link has no moving joint")
    return Robot(name=name, joints=tuple(joints), axes=tuple(axes), tool=pending)


def _attr(text: str) -> str:
    return escape(text, {'"': "&quot;"})


def _origin_xml(T: np.ndarray) -> str:
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
    c = robot._compiled  # type: ignore[attr-defined]
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
        origin = c.fixed[k]
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
        f"    {_origin_xml(c.fixed[-1])}",
        "  </joint>",
        "</robot>",
    ]
    return "\n".join(out) + "\n"
