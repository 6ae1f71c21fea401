"""A :class:`~kinematics.model.Robot` from a chosen URDF chain, and a regular start configuration.

Fixed joints fold into the neighbouring transforms; each moving joint becomes
an axis about its local z (its frame rotated so that z is the URDF axis).
Mimic joints are axes driven by the joint they follow (transitively), with
the combined multiplier and offset; a leader on a sibling branch (the other
finger of a two-finger gripper) becomes an actuated joint of the chain that
drives only its followers.

A URDF names no configuration, so the robot gets a ``home``: zeros (clipped
into the limits), nudged by small deterministic offsets until the task rows
of J are well away from singular (κ ≤ 50, σmin/σmax ≥ :data:`HOME_GOOD_RATIO`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..analysis import singular_values, task_rows
from ..conventions import FloatArray
from ..errors import UrdfError
from ..model import Axis, Joint, NamedConfiguration, Robot
from ..numeric import jacobian
from ..transforms import rotation_z_to
from .tree import ChainChoice, Tree
from .xml import UrdfDoc, UrdfJoint

__all__ = [
    "build_robot",
    "hold_fixed_ranges",
    "limit_notes",
    "regular_home",
    "HOME_GOOD_RATIO",
    "HOME_MIN_RATIO",
    "UNLIMITED",
]

_KIND = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
HOME_MIN_RATIO = 1e-3
HOME_GOOD_RATIO = 0.02
"""σmin/σmax a start pose aims for (κ ≤ 50: the app's banner calls it regular); ``HOME_MIN_RATIO`` is
the least accepted when no such pose is near the file's zero."""
"""A start configuration is accepted when σmin/σmax of the task rows exceeds this."""
UNLIMITED = 1e15
"""A URDF limit of this magnitude or more (±1e16 is a common sentinel) means "unlimited"."""
_NUDGES = (0.05, 0.1, 0.2, 0.35, 0.5, 0.8)  # [rad] or [m]: sizes of the offsets tried, in order
_DIRECTIONS = 12
_SPREAD = 256


def _qlim(j: UrdfJoint) -> tuple[float, float] | None:
    """Limits for sliders and sampling; ``None`` for continuous joints and sentinel or empty ranges."""
    if j.type == "continuous" or j.lower is None or j.upper is None:
        return None
    lo, hi = j.lower, j.upper
    if not (abs(lo) < UNLIMITED and abs(hi) < UNLIMITED):
        return None
    return (lo, hi) if lo < hi else None  # lower > upper: Bullet's "no limit" (see limit_notes)


def _finite_range(j: UrdfJoint) -> tuple[float, float] | None:
    if j.type not in ("revolute", "prismatic") or j.lower is None or j.upper is None:
        return None
    if not (abs(j.lower) < UNLIMITED and abs(j.upper) < UNLIMITED):
        return None
    return j.lower, j.upper


def _no_range(j: UrdfJoint) -> bool:
    """True for a revolute or prismatic ``<limit>`` with lower = upper = 0: written so (the SolidWorks
    exporter writes ``lower="0" upper="0" effort="0" velocity="0"`` on every joint it exports, as the
    double pendulum of example-robot-data) or with lower and upper left out (``<limit effort velocity>``,
    both default to 0). It gives no range: the joint moves, unlimited."""
    return _finite_range(j) == (0.0, 0.0)


def hold_fixed_ranges(doc: UrdfDoc) -> UrdfDoc:
    """``doc`` with every revolute or prismatic joint whose ``<limit>`` has lower = upper ≠ 0 (a joint that
    may not move) turned into a fixed joint at that value, unless a mimic joint follows or it follows one.
    lower = upper = 0 is no range at all (see :func:`_no_range`): that joint stays a moving joint."""
    led = {j.mimic[0] for j in doc.joints if j.mimic is not None}
    out = []
    for j in doc.joints:
        r = _finite_range(j)
        if r is None or r[0] != r[1] or _no_range(j) or j.mimic is not None or j.name in led:
            out.append(j)
            continue
        motion = np.eye(4)
        if j.type == "revolute":
            k = np.asarray(j.axis, float)
            K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            motion[:3, :3] = np.eye(3) + math.sin(r[0]) * K + (1 - math.cos(r[0])) * K @ K
        else:
            motion[:3, 3] = np.asarray(j.axis, float) * r[0]
        out.append(dataclasses.replace(j, type="fixed", origin=j.origin @ motion, lower=r[0], upper=r[1]))
    return dataclasses.replace(doc, joints=tuple(out))


def limit_notes(path: tuple[UrdfJoint, ...]) -> tuple[str, ...]:
    """What the chain's limits were read as, when the file does not say it plainly: lower > upper
    (Bullet's way of writing "no limit") is unlimited; lower = upper = 0 (no range given) is unlimited;
    lower = upper ≠ 0 holds the joint fixed."""
    notes = []
    for j in path:
        if _no_range(j):
            notes.append(
                f"Joint {j.name!r}: <limit> gives no range (lower = upper = 0, or both left out): read as "
                "unlimited."
            )
        if j.type == "fixed" and j.lower is not None and j.lower == j.upper:
            notes.append(
                f"Joint {j.name!r}: <limit> lower = upper = {j.lower:g}, a joint that may not move: "
                "held there, as a fixed joint."
            )
        r = _finite_range(j)
        if r is not None and r[0] > r[1]:
            notes.append(
                f"Joint {j.name!r}: <limit> lower={r[0]:g} is above upper={r[1]:g} (Bullet's way of "
                "writing no limit): read as unlimited."
            )
    return tuple(notes)


def build_robot(tree: Tree, choice: ChainChoice, name: str, **meta: object) -> Robot:
    """The robot of the chain ``choice`` in ``tree`` (no configurations yet).

    Raises:
        UrdfError: a floating or planar joint on the chain, no moving joint, a bad mimic.
    """
    for j in choice.path:
        if j.type in ("floating", "planar"):
            raise UrdfError(
                f"joint {j.name!r} is {j.type}: only revolute, continuous, prismatic and fixed joints "
                "form a serial arm"
            )
    drivers = tree.actuated(choice.path)
    if not drivers:
        raise UrdfError(
            f"the chain from {choice.base_link!r} to {choice.tip_link!r} has no moving joint "
            "(choose another tip_link)"
        )
    index = {d.name: i for i, d in enumerate(drivers)}
    joints = tuple(Joint(d.name, _KIND[d.type], _qlim(d)) for d in drivers)  # type: ignore[arg-type]
    axes = []
    pending = np.eye(4)
    for j in choice.path:
        if not j.moving:
            pending = pending @ j.origin
            continue
        d, mult, off = tree.driver(j)
        if not (math.isfinite(mult) and math.isfinite(off)):
            raise UrdfError(f"joint {j.name!r}: its mimic multiplier and offset overflow ({mult}, {off})")
        A = np.eye(4)
        A[:3, :3] = rotation_z_to(j.axis)
        axes.append(
            Axis(j.name, _KIND[j.type], index[d.name], mult, off, pending @ j.origin @ A, A.T.copy())  # type: ignore[arg-type]
        )
        pending = np.eye(4)
    return Robot(name=name, joints=joints, axes=tuple(axes), tool=pending, **meta)  # type: ignore[arg-type]


def _ratio(robot: Robot, Q: FloatArray) -> FloatArray:
    """σmin/σmax of the task rows of J at each row of ``Q`` (0 where J vanishes)."""
    s = singular_values(jacobian(robot, Q), task_rows(robot))
    top = s[..., 0]
    return np.divide(s[..., -1], top, out=np.zeros_like(top), where=top > 0)


def regular_home(robot: Robot) -> tuple[FloatArray, float]:
    """A start configuration well off the singular set, and its σmin/σmax.

    Zeros clipped into the limits when σmin/σmax ≥ :data:`HOME_GOOD_RATIO` (κ ≤ 50); else the first
    of a fixed sequence of nudges (growing sizes along fixed pseudo-random directions, clipped into the
    limits) that reaches it; else the first of fixed pseudo-random configurations spread over the
    limits that does; failing that, the first of all these above :data:`HOME_MIN_RATIO`, else the best.
    """
    lim = robot.qlim
    lo, hi = lim
    q0 = np.clip(np.zeros(robot.dof), lo, hi)
    r0 = float(_ratio(robot, q0[None])[0])
    if r0 >= HOME_GOOD_RATIO:
        return q0, r0
    rng = np.random.default_rng(20261201)
    directions = rng.normal(size=(_DIRECTIONS, robot.dof))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    Q = np.clip(np.concatenate([q0 + s * directions for s in _NUDGES]), lo, hi)
    r = _ratio(robot, Q)
    if not np.any(r >= HOME_GOOD_RATIO):  # spread over the limits (±π or ±0.5 m where unlimited)
        wide = np.where(np.array(robot.joint_types) == "revolute", np.pi, 0.5)
        spread = rng.uniform(np.maximum(lo, -wide), np.minimum(hi, wide), size=(_SPREAD, robot.dof))
        Q, r = np.concatenate([Q, spread]), np.concatenate([r, _ratio(robot, spread)])
    for target in (HOME_GOOD_RATIO, HOME_MIN_RATIO):
        good = np.flatnonzero(r >= target)
        if good.size and r0 < target:
            k = int(good[0])
            return Q[k], float(r[k])
    if r0 >= HOME_MIN_RATIO or float(r.max()) <= r0:
        return q0, r0
    k = int(np.argmax(r))
    return Q[k], float(r[k])


def with_home(robot: Robot) -> Robot:
    """``robot`` with a ``home`` configuration chosen by :func:`regular_home`, its description saying
    what it is (κ of the task rows, and how far it is from the file's zero pose)."""
    q, ratio = regular_home(robot)
    zero = np.clip(np.zeros(robot.dof), *robot.qlim)
    kappa = f"κ = {1 / ratio:.3g}" if ratio > 0 else "κ = ∞"
    if np.any(q != zero):
        r_zero = float(_ratio(robot, zero[None])[0])
        moved = ", ".join(
            f"{name} {math.degrees(v) if kind == 'revolute' else v:+.3g}{'°' if kind == 'revolute' else ' m'}"
            for name, v, kind, v0 in zip(robot.joint_names, q, robot.joint_types, zero, strict=True)
            if v != v0
        )
        zero_kappa = f"κ = {1 / r_zero:.3g}" if r_zero > 1e-10 else "singular"
        text = f"Start pose: the file's zero pose ({zero_kappa}) moved to {kappa}: {moved}"
    else:
        text = f"Start pose: the file's zero joint values ({kappa})"
    home = NamedConfiguration("home", q, text)
    return dataclasses.replace(robot, configurations=(home, *robot.configurations))
