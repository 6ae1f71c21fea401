"""The link tree of a parsed URDF and the choice of a serial chain in it.

Without a ``tip_link`` the chain ends at a link named like an arm's end (in
this order of preference: ``tool0``, ``*_tcp``, ``flange``, ``ee_link``, a tool
frame (``*_tool_frame`` as PR2's ``r_gripper_tool_frame``, ``*tool_link`` as
TIAGo's ``arm_tool_link``, ``ee_gripper_link`` as the Interbotix arms',
``*_grasptarget`` as pybullet's Panda), ``*hand*``, case-insensitive, a
``prefix/`` allowed; the uppermost such link of a branch) with moving joints
above it; else at the leaf with the most moving joints above it.
Gripper jaws never extend an arm by default: a moving joint whose name or
child link says finger, jaw, knuckle, claw, thumb or gripper (but not a wrist
yaw, roll or pitch), or a mimic pair whose two joints sit on sibling branches,
ends a default chain just above it (and above any fixed link named like a
finger it hangs from, as a ``*_thumb_base`` that carries a hand's fingers).
A joint named only index, middle, ring, pinky or little is a finger when
nothing below it branches (a humanoid's ``middle_*`` spine carries the arms
and the head: it is no finger). Without a
``base_link`` the chain starts at the root, or just below the last floating or
planar joint above the tip.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..errors import UrdfError
from .xml import UrdfDoc, UrdfJoint

__all__ = ["ChainInfo", "Tree", "ChainChoice"]

_PREFIX = r"(.*[_/])?"  # "r_gripper_", "wx250s/"
_PREFERRED = (
    ("a link named tool0", re.compile(r"tool0")),
    ("a link named *_tcp", re.compile(rf"{_PREFIX}tcp")),
    ("a link named flange", re.compile(rf"{_PREFIX}flange")),
    ("a link named ee_link", re.compile(rf"{_PREFIX}ee_link")),
    (
        "a tool frame (*_tool_frame, *tool_link, ee_gripper_link, *_grasptarget)",
        re.compile(rf"{_PREFIX}(tool_frame|tool_link|ee_gripper_link|grasptarget)"),
    ),
    ("a link named *hand*", re.compile(r".*hand.*")),
)
_JAW = re.compile(r"finger|jaw|knuckle|claw|thumb", re.IGNORECASE)
_FINGER_WORD = re.compile(r"(^|[_/])(index|middle|ring|pinky|little)(_|\d|$)", re.IGNORECASE)
"""Words that name a finger in a hand, and a spine ("middle_*") or a link elsewhere: see _jaw_joints."""
_GRIPPER = re.compile(r"gripper", re.IGNORECASE)  # a moving "gripper" joint is the jaw drive...
_WRIST = re.compile(r"yaw|roll|pitch|wrist", re.IGNORECASE)  # ...unless it is a wrist axis


@dataclass(frozen=True)
class ChainInfo:
    """One serial chain of a URDF, for a chain picker.

    Attributes:
        base_link, tip_link: Its ends.
        joints: Names of its actuated joints, in chain order (the robot's ``joint_names``).
        dof: ``len(joints)``.
        is_default: True for the chain opened when no tip is given.
    """

    base_link: str
    tip_link: str
    joints: tuple[str, ...]
    dof: int
    is_default: bool = False


@dataclass(frozen=True)
class ChainChoice:
    """A chosen chain: its ends, the joints from base to tip, and why it was chosen."""

    base_link: str
    tip_link: str
    path: tuple[UrdfJoint, ...]
    reason: str


class Tree:
    """The links of a URDF as a tree (checked: one root, every link reachable, no cycle)."""

    def __init__(self, doc: UrdfDoc) -> None:
        self.doc = doc
        self.by_name = {j.name: j for j in doc.joints}
        self.parent_joint: dict[str, UrdfJoint] = {}
        self.children: dict[str, list[UrdfJoint]] = {link: [] for link in doc.links}
        for j in doc.joints:
            for end in (j.parent, j.child):
                if end not in self.children:
                    raise UrdfError(f"joint {j.name!r} (line {j.line}) refers to unknown link {end!r}")
            if j.parent == j.child:
                raise UrdfError(f"joint {j.name!r} (line {j.line}) connects link {j.parent!r} to itself")
            if j.child in self.parent_joint:
                raise UrdfError(
                    f"URDF is not a tree: link {j.child!r} is the child of joints "
                    f"{self.parent_joint[j.child].name!r} and {j.name!r}"
                )
            self.parent_joint[j.child] = j
            self.children[j.parent].append(j)
        roots = [link for link in doc.links if link not in self.parent_joint]
        if len(roots) != 1:
            raise UrdfError(
                "URDF is not a tree: expected exactly one root link, found "
                f"{len(roots)}: {', '.join(roots[:10]) or 'none (the joints form a cycle)'}"
            )
        self.root = roots[0]
        self.order = self._depth_first(self.root)
        if len(self.order) != len(doc.links):
            reached = set(self.order)
            lost = [link for link in doc.links if link not in reached]
            raise UrdfError(
                f"URDF is not a tree: links {', '.join(map(repr, lost[:10]))} are not connected to the "
                f"root {self.root!r} (their joints form a cycle)"
            )
        self._jaws = self._jaw_joints()
        self._drivable: set[str] = set()  # mimic joints whose driver resolves

    def _depth_first(self, start: str) -> list[str]:
        out, stack = [], [start]
        while stack:
            link = stack.pop()
            out.append(link)
            stack.extend(j.child for j in reversed(self.children[link]))
        return out

    def _jaw_joints(self) -> set[str]:
        jaws = {j.name for j in self.doc.joints if j.moving and _jaw_like(j)}
        worded = [j for j in self.doc.joints if j.moving and _FINGER_WORD.search(f"{j.name}/{j.child}")]
        jaws |= {j.name for j in worded if self._unbranched(j.child)}
        for j in self.doc.joints:
            leader = self.by_name.get(j.mimic[0]) if j.mimic else None
            if leader is not None and j.moving and leader.moving:
                if not (self._above(leader, j.child) or self._above(j, leader.child)):
                    jaws |= {j.name, leader.name}
        return jaws

    def _unbranched(self, link: str) -> bool:
        """True when no link at or below ``link`` has two child branches with moving joints (a finger's
        phalanges; not a spine that carries arms and a head)."""
        moving_below: dict[str, bool] = {}
        for name in reversed(self._depth_first(link)):  # children before parents
            moving_below[name] = any(j.moving or moving_below[j.child] for j in self.children[name])
        return all(
            sum(1 for j in self.children[name] if j.moving or moving_below[j.child]) < 2
            for name in moving_below
        )

    def _above(self, joint: UrdfJoint, link: str) -> bool:
        """True when ``joint`` lies on the path from the root to ``link``."""
        return any(j is joint for j in self.path_to(link))

    def path_to(self, link: str, base: str | None = None) -> list[UrdfJoint]:
        """Joints from ``base`` (default: the root) down to ``link``, in chain order."""
        base = self.root if base is None else base
        path = []
        while link != base:
            j = self.parent_joint.get(link)
            if j is None:
                return []
            path.append(j)
            link = j.parent
        path.reverse()
        return path

    def _check_link(self, link: str, role: str) -> None:
        if link not in self.children:
            shown = ", ".join(self.doc.links[:40]) + (", ..." if len(self.doc.links) > 40 else "")
            raise UrdfError(f"unknown {role} {link!r}; links: {shown}")

    def _serial(self, path: list[UrdfJoint], base: str | None) -> tuple[str, list[UrdfJoint]]:
        """Cut ``path`` below its last floating/planar joint when the base was not given."""
        start = base if base is not None else self.root
        if base is None:
            for i in range(len(path) - 1, -1, -1):
                if path[i].type in ("floating", "planar"):
                    return path[i].child, path[i + 1 :]
        return start, path

    def _candidates(self, base: str | None) -> list[tuple[str, str, list[UrdfJoint]]]:
        """(base, tip, path) for every link below ``base`` that ends a chain with a moving joint."""
        start = self.root if base is None else base
        out = []
        for link in self._depth_first(start):
            b, path = self._serial(self.path_to(link, start), base)
            if any(j.moving for j in path) and all(j.type not in ("floating", "planar") for j in path):
                if self._buildable(path):
                    out.append((b, link, path))
        return out

    def _buildable(self, path: list[UrdfJoint]) -> bool:
        """False when a mimic joint on ``path`` follows a missing joint or a cycle."""
        for j in path:
            if j.mimic is not None and j.name not in self._drivable:
                try:
                    self.driver(j)
                except UrdfError:
                    return False
                self._drivable.add(j.name)
        return True

    def choose(self, base_link: str | None = None, tip_link: str | None = None) -> ChainChoice:
        """The chain from ``base_link`` to ``tip_link``; either may be ``None`` (see the module text)."""
        if base_link is not None:
            self._check_link(base_link, "base_link")
        if tip_link is not None:
            self._check_link(tip_link, "tip_link")
            start = self.root if base_link is None else base_link
            path = self.path_to(tip_link, start)
            if not path and tip_link != start:
                raise UrdfError(f"tip_link {tip_link!r} is not below base_link {start!r}")
            b, path = self._serial(path, base_link)
            return ChainChoice(b, tip_link, tuple(path), "the tip given")
        candidates = self._candidates(base_link)
        if not candidates:
            below = base_link if base_link is not None else self.root
            for link in self._depth_first(below):
                path = self.path_to(link, below)
                if any(j.moving for j in path):
                    self.actuated(path)  # raises the mimic error that rules the chain out
            free = [j for j in self.doc.joints if j.type in ("floating", "planar")][:3]
            why = "".join(
                f"; joint {j.name!r} is {j.type}: only revolute, continuous, prismatic and fixed joints "
                "form a serial arm"
                for j in free
            )
            raise UrdfError(f"no moving joint in any serial chain below link {below!r}{why}")
        clean = [c for c in candidates if not any(j.name in self._jaws for j in c[2])]
        for reason, pattern in _PREFERRED:
            matches = {c[1] for c in clean if pattern.fullmatch(c[1].lower())}
            # The uppermost match of a branch: below "hand" come the fingers, not a better tool frame.
            named = [c for c in clean if c[1] in matches and not any(j.parent in matches for j in c[2])]
            if named:
                b, tip, path = min(named, key=lambda c: (-_moving(c[2]), len(c[2]), c[1]))
                return ChainChoice(b, tip, tuple(path), reason)
        leaves = {link for link, js in self.children.items() if not js}
        ends = []
        for b, tip, path in candidates:
            if tip not in leaves:
                continue
            cut = self._cut_above_jaw(path)
            if cut is not None:
                tip, path = cut
            if any(j.moving for j in path):
                ends.append((b, tip, path))
        if not ends:  # every chain is a gripper (or no leaf ends a chain): take the longest as it is
            ends = [c for c in candidates if c[1] in leaves] or candidates
        rank = {link: i for i, link in enumerate(self.order)}
        b, tip, path = min(ends, key=lambda c: (-_moving(c[2]), rank[c[1]]))
        return ChainChoice(b, tip, tuple(path), "the leaf with the most moving joints above it")

    def _cut_above_jaw(self, path: list[UrdfJoint]) -> tuple[str, list[UrdfJoint]] | None:
        """``path`` cut just above its first gripper jaw: (tip, path), or ``None`` when it has no jaw.

        The tip then climbs fixed joints while its own name is a finger's: the Alex humanoid's fingers
        hang from a fixed ``Left_thumb_base`` below the hand's ``LeftPsyonicAbilityBaseLink``, which is
        the hand's frame, not a thumb."""
        cut = next((i for i, j in enumerate(path) if j.name in self._jaws), None)
        if cut is None:
            return None
        tip, path = path[cut].parent, path[:cut]
        while path and path[-1].type == "fixed" and (_JAW.search(tip) or _FINGER_WORD.search(tip)):
            tip, path = path[-1].parent, path[:-1]
        return tip, path

    def driver(self, joint: UrdfJoint) -> tuple[UrdfJoint, float, float]:
        """The joint whose value moves ``joint`` and the (multiplier, offset) relating them.

        Follows ``<mimic>`` transitively: q_joint = multiplier · q_driver + offset.
        """
        mult, off, seen, j = 1.0, 0.0, [joint.name], joint
        while j.mimic is not None:
            leader_name, m, o = j.mimic
            leader = self.by_name.get(leader_name)
            if leader is None or not leader.moving:
                raise UrdfError(
                    f"joint {j.name!r} mimics {leader_name!r}, which is not an actuated joint of the URDF"
                )
            if leader_name in seen:
                raise UrdfError(f"mimic joints form a cycle: {' -> '.join([*seen, leader_name])}")
            seen.append(leader_name)
            mult, off = mult * m, mult * o + off
            j = leader
        return j, mult, off

    def actuated(self, path: tuple[UrdfJoint, ...] | list[UrdfJoint]) -> list[UrdfJoint]:
        """The joints that become entries of ``q`` for a chain: each moving joint's driver, in order."""
        out: list[UrdfJoint] = []
        seen: set[str] = set()
        for j in path:
            if j.moving:
                d = self.driver(j)[0] if j.mimic is not None else j
                if d.name not in seen:
                    seen.add(d.name)
                    out.append(d)
        return out

    def chains(self, base_link: str | None = None) -> list[ChainInfo]:
        """The default chain first, then one per leaf (and per leaf cut above a gripper jaw)."""
        default = self.choose(base_link)
        seen = {(default.base_link, default.tip_link)}
        out = [self._info(default.base_link, default.tip_link, default.path, True)]
        leaves = {link for link, js in self.children.items() if not js}
        for b, tip, path in self._candidates(base_link):
            cut = self._cut_above_jaw(path)
            ends = [(tip, path)] if tip in leaves else []
            if tip in leaves and cut is not None and any(j.moving for j in cut[1]):
                ends.insert(0, cut)
            for t, p in ends:
                if (b, t) not in seen:
                    seen.add((b, t))
                    out.append(self._info(b, t, tuple(p), False))
        return out

    def _info(
        self, base: str, tip: str, path: tuple[UrdfJoint, ...] | list[UrdfJoint], default: bool
    ) -> ChainInfo:
        names = tuple(j.name for j in self.actuated(path))
        return ChainInfo(base, tip, names, len(names), default)


def _jaw_like(j: UrdfJoint) -> bool:
    """A joint named like a gripper jaw or finger (its own name or its child link's)."""
    texts = (j.name, j.child)
    if any(_JAW.search(t) for t in texts):
        return True
    return any(_GRIPPER.search(t) for t in texts) and not any(_WRIST.search(t) for t in texts)


def _moving(path: list[UrdfJoint]) -> int:
    return sum(1 for j in path if j.moving)
