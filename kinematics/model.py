"""The immutable robot model every input (DH table, URDF, robot file) compiles into.

A :class:`Robot` is a serial chain of *axes*. Each axis moves about (revolute)
or along (prismatic) the z axis of its own *joint frame*; fixed transforms sit
between them::

    T_base_tool = base · Π_k [ T_parent_joint[k] · M_k(q) · T_joint_child[k] ] · tool

where ``M_k`` is ``Rz(θ)`` or ``Tz(d)`` with ``θ`` (or ``d``) =
``multiplier[k] · q[joint_index[k]] + offset[k]``. An axis normally drives
one actuated joint with multiplier 1; a URDF *mimic* joint is an extra axis
that follows another joint's value. The frame after ``T_joint_child[k]`` is
the *link frame* k: for a DH robot it is exactly the DH frame k of the chosen
convention, for a URDF robot the child link's frame.

The model holds no state: the current configuration lives in the caller (the
app), and kinematics are free functions of ``(robot, q)`` in
:mod:`kinematics.numeric`.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from .errors import RobotDefinitionError
from .transforms import check_rigid_transform, rot_x, rot_z, trans

__all__ = ["Robot", "Joint", "Axis", "DHRow", "NamedConfiguration", "JointType"]

JointType = Literal["revolute", "prismatic"]
_JOINT_TYPES = ("revolute", "prismatic")
_DH_KEYS = ("joint", "a", "alpha", "d", "theta")


def _frozen_array(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a


@dataclass(frozen=True)
class Joint:
    """An actuated joint: one entry of ``q``.

    Attributes:
        name: Display name, unique within the robot.
        kind: ``"revolute"`` (q in [rad]) or ``"prismatic"`` (q in [m]).
        qlim: (lower, upper) limits, or ``None`` if unlimited (continuous).
            Limits bound sliders and sampling only, never the maths.
    """

    name: str
    kind: JointType
    qlim: tuple[float, float] | None = None


@dataclass(frozen=True, eq=False)
class Axis:
    """One moving axis of the chain, always about/along its joint frame's z.

    Attributes:
        name: Name of the joint this axis comes from (URDF joint name, DH row name).
        kind: ``"revolute"`` or ``"prismatic"``.
        joint_index: Index into ``q`` of the joint that drives this axis.
        multiplier: Axis value = multiplier · q[joint_index] + offset.
        offset: See ``multiplier`` ([rad] or [m]).
        T_parent_joint: 4×4 transform from the previous link frame to this joint frame.
        T_joint_child: 4×4 transform from the moved joint frame to this axis' link frame.
        corners: Points [m] in the moved joint frame through which the drawn link
            passes on its way to the link frame origin (the DH "d then a" corner).
    """

    name: str
    kind: JointType
    joint_index: int
    multiplier: float
    offset: float
    T_parent_joint: np.ndarray
    T_joint_child: np.ndarray
    corners: tuple[tuple[float, float, float], ...] = ()


@dataclass(frozen=True)
class DHRow:
    """One row of a DH table, in [m] and [rad], as given by the user."""

    joint: JointType
    a: float
    alpha: float
    d: float
    theta: float
    qlim: tuple[float, float] | None = None
    name: str = ""


@dataclass(frozen=True, eq=False)
class NamedConfiguration:
    """A configuration worth visiting (home, a singular pose, ...).

    Attributes:
        name: Short identifier (``"home"``, ``"wrist_singular"``).
        q: Joint values [rad] / [m], shape (n,).
        description: One sentence for the GUI.
        singular: Kind of singularity ("wrist", "elbow", "shoulder", "boundary", ...)
            or "" for a regular configuration.
    """

    name: str
    q: np.ndarray
    description: str = ""
    singular: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "q", _frozen_array(self.q))


@dataclass(frozen=True, eq=False)
class Robot:
    """An immutable serial manipulator. Build it with :meth:`from_dh` or :meth:`from_urdf`.

    Attributes:
        name: Identifier (library name or file stem).
        joints: The actuated joints, in chain order (``len == dof``).
        axes: The moving axes, in chain order (more than ``dof`` with mimic joints).
        base: 4×4 transform from the robot's base frame to the first link frame (frame 0).
        tool: 4×4 transform from the last link frame to the tool frame.
        dh: The DH table the robot was built from, or ``None``.
        convention: ``"standard"`` or ``"modified"`` for DH robots, else ``None``.
        planar: True when the task is planar motion in the base x-y plane
            (task rows vx, vy, ωz).
        task: Which rows of J form the robot's task: ``"auto"`` (planar rows for a
            planar robot, position rows below 6 joints, else all six), or one of
            ``"full"``, ``"linear"``, ``"angular"``, ``"planar"`` (a spherical wrist
            alone has the task ``"angular"``).
        title, description, source: Human-readable metadata (source = citation).
        configurations: Named configurations worth visiting.
    """

    name: str
    joints: tuple[Joint, ...]
    axes: tuple[Axis, ...]
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))
    dh: tuple[DHRow, ...] | None = None
    convention: Literal["standard", "modified"] | None = None
    planar: bool = False
    task: Literal["auto", "full", "linear", "angular", "planar"] = "auto"
    title: str = ""
    description: str = ""
    source: str = ""
    configurations: tuple[NamedConfiguration, ...] = ()
    urdf_path: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "base", _frozen_array(check_rigid_transform(self.base, "base")))
        object.__setattr__(self, "tool", _frozen_array(check_rigid_transform(self.tool, "tool")))
        if self.task not in ("auto", "full", "linear", "angular", "planar"):
            raise RobotDefinitionError(
                f"robot {self.name!r}: task must be auto, full, linear, angular or planar, got {self.task!r}"
            )
        if not self.joints:
            raise RobotDefinitionError(f"robot {self.name!r}: the chain has no moving joint")
        names = [j.name for j in self.joints]
        if len(set(names)) != len(names):
            raise RobotDefinitionError(f"robot {self.name!r}: joint names are not unique: {names}")
        for k, ax in enumerate(self.axes):
            if not 0 <= ax.joint_index < len(self.joints):
                raise RobotDefinitionError(f"axis {k} ({ax.name}): joint_index out of range")
        for c in self.configurations:
            if c.q.shape != (len(self.joints),):
                raise RobotDefinitionError(
                    f"robot {self.name!r}: configuration {c.name!r} has {c.q.size} values, "
                    f"expected {len(self.joints)} (one per joint)"
                )
        object.__setattr__(self, "_compiled", _Compiled.build(self))

    # ------------------------------------------------------------------ queries
    @property
    def dof(self) -> int:
        """Number of actuated joints (the length of ``q``)."""
        return len(self.joints)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Names of the actuated joints, in chain order."""
        return tuple(j.name for j in self.joints)

    @property
    def joint_types(self) -> tuple[JointType, ...]:
        """``"revolute"`` or ``"prismatic"`` for each actuated joint."""
        return tuple(j.kind for j in self.joints)

    @property
    def qlim(self) -> np.ndarray:
        """(2, n) array of lower and upper limits; ±∞ where a joint has none."""
        lim = np.empty((2, self.dof))
        for i, j in enumerate(self.joints):
            lim[:, i] = j.qlim if j.qlim is not None else (-np.inf, np.inf)
        return lim

    def configuration(self, name: str) -> np.ndarray:
        """The named configuration ``name``; raises listing the available names."""
        for c in self.configurations:
            if c.name == name:
                return c.q
        available = ", ".join(c.name for c in self.configurations) or "none"
        raise RobotDefinitionError(
            f"robot {self.name!r} has no configuration {name!r}; available: {available}"
        )

    @property
    def home(self) -> np.ndarray:
        """The ``home`` configuration if named, else the middle of the limits (0 if unlimited)."""
        for c in self.configurations:
            if c.name == "home":
                return c.q
        lim = self.qlim
        mid = np.where(np.isfinite(lim).all(axis=0), lim.mean(axis=0), 0.0)
        return _frozen_array(mid)

    def fingerprint(self) -> str:
        """A hex digest of the kinematic content (used as a cache key).

        Two robots with the same chain, base, tool and DH table have the same
        fingerprint, whatever their names and descriptions.
        """
        h = hashlib.sha256()
        for ax in self.axes:
            h.update(f"{ax.kind}|{ax.joint_index}|{ax.multiplier!r}|{ax.offset!r}".encode())
            h.update(np.ascontiguousarray(ax.T_parent_joint).tobytes())
            h.update(np.ascontiguousarray(ax.T_joint_child).tobytes())
        h.update(self.base.tobytes())
        h.update(self.tool.tobytes())
        h.update(repr((self.convention, self.dh, [j.kind for j in self.joints])).encode())
        return h.hexdigest()

    def __repr__(self) -> str:
        kinds = "".join("R" if j.kind == "revolute" else "P" for j in self.joints)
        origin = f"DH {self.convention}" if self.dh is not None else "URDF" if self.urdf_path else "chain"
        return f"Robot({self.name!r}, {self.dof} joints {kinds}, {origin})"

    # ------------------------------------------------------------ constructors
    @classmethod
    def from_dh(
        cls,
        rows: Sequence[Mapping[str, object]],
        convention: str = "standard",
        base: np.ndarray | None = None,
        tool: np.ndarray | None = None,
        name: str = "",
        *,
        title: str = "",
        description: str = "",
        source: str = "",
        planar: bool = False,
        task: str = "auto",
        configurations: Sequence[NamedConfiguration] = (),
    ) -> Robot:
        """Build a robot from a Denavit–Hartenberg table.

        Args:
            rows: One mapping per joint with keys ``joint`` (``"revolute"`` or
                ``"prismatic"``), ``a`` [m], ``alpha`` [rad], ``d`` [m], ``theta`` [rad],
                optional ``qlim`` (lower, upper) and ``name``. For a revolute joint
                θ = q + ``theta`` and ``d`` is constant; for a prismatic joint
                d = q + ``d`` and ``theta`` is constant.
            convention: ``"standard"``: A = Rz(θ) Tz(d) Tx(a) Rx(α);
                ``"modified"`` (Craig): A = Rx(α) Tx(a) Rz(θ) Tz(d).
            base, tool: 4×4 rigid transforms; T_base_tool = base · A1 ⋯ An · tool.
            name: Robot identifier.

        Example:
            >>> r = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0, d=0, theta=0)] * 2)
            >>> r.dof
            2
        """
        if convention not in ("standard", "modified"):
            raise RobotDefinitionError(f"DH convention must be 'standard' or 'modified', got {convention!r}")
        if isinstance(rows, (str, bytes, Mapping)) or not isinstance(rows, Sequence):
            raise RobotDefinitionError("DH rows: expected a sequence of mappings, one per joint")
        if len(rows) == 0:
            raise RobotDefinitionError("DH table is empty: expected at least one row")
        dh = tuple(_parse_dh_row(i, row) for i, row in enumerate(rows))
        joints, axes = [], []
        for i, r in enumerate(dh):
            name_i = r.name or f"q{i + 1}"
            joints.append(Joint(name_i, r.joint, r.qlim))
            revolute = r.joint == "revolute"
            if convention == "standard":
                T_pj = np.eye(4) if revolute else rot_z(r.theta)
                if revolute:
                    T_jc = trans(z=r.d) @ trans(x=r.a) @ rot_x(r.alpha)
                    corners = ((0.0, 0.0, r.d),) if r.d != 0 and r.a != 0 else ()
                else:
                    T_jc = trans(x=r.a) @ rot_x(r.alpha)
                    # The slide ends at the moved joint origin; the link then runs along x by a.
                    corners = ((0.0, 0.0, 0.0),) if r.a != 0 else ()
            else:
                T_pj = rot_x(r.alpha) @ trans(x=r.a)
                if revolute:
                    T_jc = trans(z=r.d)
                else:
                    T_pj = T_pj @ rot_z(r.theta)
                    T_jc = np.eye(4)
                corners = ()
            offset = r.theta if revolute else r.d
            axes.append(
                Axis(name_i, r.joint, i, 1.0, offset, _frozen_array(T_pj), _frozen_array(T_jc), corners)
            )
        return cls(
            name=name,
            joints=tuple(joints),
            axes=tuple(axes),
            base=np.eye(4) if base is None else base,
            tool=np.eye(4) if tool is None else tool,
            dh=dh,
            convention=convention,  # type: ignore[arg-type]
            planar=planar,
            task=task,  # type: ignore[arg-type]
            title=title,
            description=description,
            source=source,
            configurations=tuple(configurations),
        )

    @classmethod
    def from_urdf(cls, path: str, base_link: str | None = None, tip_link: str | None = None) -> Robot:
        """Build the chain from ``base_link`` to ``tip_link`` of a URDF file (see :mod:`kinematics.urdf`)."""
        from .urdf import robot_from_urdf

        return robot_from_urdf(path, base_link=base_link, tip_link=tip_link)


def _parse_dh_row(i: int, row: Mapping[str, object]) -> DHRow:
    where = f"DH row {i + 1}"
    if not isinstance(row, Mapping):
        raise RobotDefinitionError(f"{where}: expected a mapping with keys {', '.join(_DH_KEYS)}")
    missing = [k for k in _DH_KEYS if k not in row]
    if missing:
        raise RobotDefinitionError(f"{where}: missing key(s) {', '.join(map(repr, missing))}")
    unknown = sorted(set(row) - set(_DH_KEYS) - {"qlim", "name"})
    if unknown:
        raise RobotDefinitionError(
            f"{where}: unknown key(s) {', '.join(map(repr, unknown))}; "
            f"allowed: {', '.join(_DH_KEYS)}, qlim, name"
        )
    kind = row["joint"]
    if kind not in _JOINT_TYPES:
        raise RobotDefinitionError(f"{where}: 'joint' must be 'revolute' or 'prismatic', got {kind!r}")
    vals = {k: _finite(row[k], f"{where}, key {k!r}") for k in ("a", "alpha", "d", "theta")}
    qlim = row.get("qlim")
    if qlim is not None:
        qlim = _parse_qlim(qlim, f"{where}, key 'qlim'")
    name = row.get("name", "")
    if not isinstance(name, str):
        raise RobotDefinitionError(f"{where}, key 'name': expected a string, got {name!r}")
    return DHRow(kind, vals["a"], vals["alpha"], vals["d"], vals["theta"], qlim, name)  # type: ignore[arg-type]


def _finite(x: object, where: str) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise RobotDefinitionError(f"{where}: expected a number, got {x!r}")
    v = float(x)
    if not math.isfinite(v):
        raise RobotDefinitionError(f"{where}: expected a finite number, got {v}")
    return v


def _parse_qlim(qlim: object, where: str) -> tuple[float, float]:
    if isinstance(qlim, (str, bytes)) or not isinstance(qlim, (Sequence, np.ndarray)) or len(qlim) != 2:
        raise RobotDefinitionError(f"{where}: expected (lower, upper), got {qlim!r}")
    lo, hi = (_finite(v, where) for v in qlim)
    if not lo < hi:
        raise RobotDefinitionError(f"{where}: lower limit {lo} must be below upper limit {hi}")
    return (lo, hi)


@dataclass(frozen=True, eq=False)
class _Compiled:
    """Arrays precomputed once per robot for the numeric kernels.

    ``fixed[k]`` is the constant transform between the moved frame of axis k-1
    and the joint frame of axis k (``fixed[0]`` includes ``base``, ``fixed[m]``
    ends with ``tool``), so T_base_tool = fixed[0] · M_1 · fixed[1] ⋯ M_m · fixed[m].
    """

    fixed: np.ndarray  # (m+1, 4, 4)
    index: np.ndarray  # (m,) int
    multiplier: np.ndarray  # (m,)
    offset: np.ndarray  # (m,)
    revolute: np.ndarray  # (m,) float 1.0/0.0
    prismatic: np.ndarray  # (m,) float
    simple: bool  # one axis per joint, in order, multiplier 1
    selection: np.ndarray  # (m, n): column k of J = Σ_axes selection[axis, k] · contribution
    all_revolute: bool
    prismatic_index: np.ndarray  # (p,) indices of prismatic axes
    rz_cos: np.ndarray  # (m, 4, 4): Rz(θ) F_k = cos θ · rz_cos + sin θ · rz_sin + rz_const
    rz_sin: np.ndarray
    rz_const: np.ndarray
    tz_lin: np.ndarray  # (m, 4, 4): Tz(d) F_k = F_k + d · tz_lin

    @staticmethod
    def build(robot: Robot) -> _Compiled:
        m, n = len(robot.axes), robot.dof
        fixed = np.empty((m + 1, 4, 4))
        prev = robot.base
        for k, ax in enumerate(robot.axes):
            fixed[k] = prev @ ax.T_parent_joint
            prev = ax.T_joint_child
        fixed[m] = prev @ robot.tool
        index = np.array([ax.joint_index for ax in robot.axes], dtype=int)
        mult = np.array([ax.multiplier for ax in robot.axes])
        rev = np.array([1.0 if ax.kind == "revolute" else 0.0 for ax in robot.axes])
        sel = np.zeros((m, n))
        sel[np.arange(m), index] = mult
        simple = m == n and bool(np.all(index == np.arange(n))) and bool(np.all(mult == 1.0))
        offset = np.array([ax.offset for ax in robot.axes])
        pri_idx = np.flatnonzero(rev == 0.0)
        F = fixed[1:]
        Dc, Ds, E, Dz = np.diag([1.0, 1, 0, 0]), np.zeros((4, 4)), np.diag([0.0, 0, 1, 1]), np.zeros((4, 4))
        Ds[0, 1], Ds[1, 0], Dz[2, 3] = -1.0, 1.0, 1.0
        parts = [Dc @ F, Ds @ F, E @ F, Dz @ F]
        for a in (fixed, index, mult, offset, rev, sel, pri_idx, *parts):
            a.flags.writeable = False
        return _Compiled(
            fixed, index, mult, offset, rev, 1.0 - rev, simple, sel, len(pri_idx) == 0, pri_idx, *parts
        )
