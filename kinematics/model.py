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
:mod:`kinematics.numeric`. Its parts (:class:`Joint`, :class:`Axis`, :class:`DHRow`,
:class:`NamedConfiguration`) live in :mod:`kinematics.parts`, DH tables are read by
:mod:`kinematics.dh`.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np

from .conventions import FloatArray
from .errors import RobotDefinitionError
from .parts import (
    CONVENTIONS,
    TASKS,
    Axis,
    Convention,
    DHRow,
    Joint,
    JointType,
    NamedConfiguration,
    Task,
    check_choice,
    param_names,
    translations,
    value_bound,
)
from .transforms import check_rigid_transform
from .validation import MAX_AXES, frozen_array, show

__all__ = ["Robot", "Joint", "Axis", "DHRow", "NamedConfiguration", "JointType", "Convention", "Task"]


@dataclass(frozen=True, eq=False)
class Robot:
    """An immutable serial manipulator. Build it with :meth:`from_dh`, or from a URDF file
    with :func:`kinematics.robot_from_urdf` (:mod:`kinematics.urdf`).

    Attributes:
        name: Identifier (library name or file stem).
        joints: The actuated joints, in chain order (``len == dof``).
        axes: The moving axes, in chain order (more than ``dof`` with mimic joints; at most
            :data:`~kinematics.validation.MAX_AXES`).
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
        title, description, source: Human-readable metadata (source = citation), in English.
        translations: The title and description in other languages, language code →
            {"title": …, "description": …} (read-only, empty by default; either key may be missing:
            whoever shows them falls back to English). See :func:`kinematics.parts.translations`.
        configurations: Named configurations worth visiting (names unique).
        urdf_path: The URDF file the robot was read from, or ``None``.
        param_names: Course names of the symbolic DH parameters, default name → course name
            (``{"a1": "l1"}``; read-only, empty by default). Keys are the default names of
            :mod:`kinematics.symbolic` (``a{k}``, ``alpha{k}``, ``d{i}``, ``theta{i}``, ``d{i}0``,
            ``theta{i}0``, ``xt``, ``yt``, ``zt``, ``xb``, ``yb``, ``zb``); values are a letter then
            up to 15 letters or digits, distinct, and neither a joint symbol ``q1…`` nor another
            default name.

    Every attribute is checked on construction (RobotDefinitionError naming it); arrays are
    stored read-only.
    """

    name: str
    joints: tuple[Joint, ...]
    axes: tuple[Axis, ...]
    base: FloatArray = field(default_factory=lambda: np.eye(4))
    tool: FloatArray = field(default_factory=lambda: np.eye(4))
    dh: tuple[DHRow, ...] | None = None
    convention: Convention | None = None
    planar: bool = False
    task: Task = "auto"
    title: str = ""
    description: str = ""
    source: str = ""
    configurations: tuple[NamedConfiguration, ...] = ()
    urdf_path: str | None = None
    param_names: Mapping[str, str] = field(default_factory=dict)
    translations: Mapping[str, Mapping[str, str]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise RobotDefinitionError(f"robot name: expected a string, got {show(self.name)}")
        who = f"robot {self.name!r}"
        for key in ("title", "description", "source"):
            if not isinstance(getattr(self, key), str):
                raise RobotDefinitionError(f"{who}, {key}: expected a string, got {show(getattr(self, key))}")
        if self.urdf_path is not None and not isinstance(self.urdf_path, str):
            raise RobotDefinitionError(f"{who}, urdf_path: expected a string or None")
        set_ = object.__setattr__
        set_(self, "base", frozen_array(check_rigid_transform(self.base, "base")))
        set_(self, "tool", frozen_array(check_rigid_transform(self.tool, "tool")))
        check_choice(self.task, TASKS, f"{who}, task")
        if self.convention is not None:
            check_choice(self.convention, CONVENTIONS, f"{who}, convention")
        if not isinstance(self.planar, (bool, np.bool_)):
            raise RobotDefinitionError(f"{who}, planar: expected true or false, got {show(self.planar)}")
        set_(self, "planar", bool(self.planar))
        set_(self, "joints", _parts(self.joints, Joint, f"{who}, joints"))
        set_(self, "axes", _parts(self.axes, Axis, f"{who}, axes"))
        set_(
            self, "configurations", _parts(self.configurations, NamedConfiguration, f"{who}, configurations")
        )
        if self.dh is not None:
            set_(self, "dh", _parts(self.dh, DHRow, f"{who}, dh"))
        set_(self, "param_names", param_names(self.param_names, self.name))
        set_(
            self,
            "translations",
            translations(self.translations, ("title", "description"), f"{who}, translations"),
        )
        self._check_chain(who)

    def _check_chain(self, who: str) -> None:
        if not self.joints:
            raise RobotDefinitionError(f"{who}: the chain has no moving joint")
        if len(self.axes) > MAX_AXES:
            raise RobotDefinitionError(
                f"{who}: the chain has {len(self.axes)} moving axes; at most {MAX_AXES} are supported"
            )
        names = [j.name for j in self.joints]
        if len(set(names)) != len(names):
            raise RobotDefinitionError(f"{who}: joint names are not unique: {names}")
        driven: set[int] = set()
        for k, ax in enumerate(self.axes):
            if not 0 <= ax.joint_index < len(self.joints):
                raise RobotDefinitionError(f"axis {k} ({ax.name}): joint_index out of range")
            driven.add(ax.joint_index)
        idle = [self.joints[i].name for i in range(len(self.joints)) if i not in driven]
        if idle:
            raise RobotDefinitionError(f"{who}: joint(s) {', '.join(map(repr, idle))} drive no axis")
        seen: set[str] = set()
        for c in self.configurations:
            where = f"{who}: configuration {c.name!r}"
            if c.name in seen:
                raise RobotDefinitionError(f"{where} is named twice")
            seen.add(c.name)
            if c.q.shape != (len(self.joints),):
                raise RobotDefinitionError(
                    f"{where} has {c.q.size} values, expected {len(self.joints)} (one per joint)"
                )
            for j, v in zip(self.joints, c.q, strict=True):
                bound, unit = value_bound(j.kind)
                if abs(v) > bound:
                    raise RobotDefinitionError(
                        f"{where}, joint {j.name!r}: {v:g} {unit} is out of range; "
                        f"expected |q| ≤ {bound:g} {unit}"
                    )

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
    def qlim(self) -> FloatArray:
        """(2, n) array of lower and upper limits; ±∞ where a joint has none."""
        lim = np.empty((2, self.dof))
        for i, j in enumerate(self.joints):
            lim[:, i] = j.qlim if j.qlim is not None else (-np.inf, np.inf)
        return lim

    def configuration(self, name: str) -> FloatArray:
        """The named configuration ``name``; raises listing the available names."""
        for c in self.configurations:
            if c.name == name:
                return c.q
        available = ", ".join(c.name for c in self.configurations) or "none"
        raise RobotDefinitionError(
            f"robot {self.name!r} has no configuration {show(name)}; available: {available}"
        )

    @property
    def home(self) -> FloatArray:
        """The ``home`` configuration if named, else the middle of the limits (0 if unlimited)."""
        for c in self.configurations:
            if c.name == "home":
                return c.q
        lim = self.qlim
        limited = np.isfinite(lim).all(axis=0)
        mid = np.zeros(self.dof)
        mid[limited] = lim[:, limited].mean(axis=0)
        return frozen_array(mid)

    def fixed_transforms(self) -> FloatArray:
        """The constant transforms between the moving axes, shape (m + 1, 4, 4), m = ``len(axes)``.

        ``F[0] = base · T_parent_joint[0]``, ``F[k] = T_joint_child[k-1] · T_parent_joint[k]``
        and ``F[m] = T_joint_child[m-1] · tool``, so that
        ``T_base_tool = F[0] · M_1(q) · F[1] ⋯ M_m(q) · F[m]``.
        """
        m = len(self.axes)
        F = np.empty((m + 1, 4, 4))
        prev = self.base
        for k, ax in enumerate(self.axes):
            F[k] = prev @ ax.T_parent_joint
            prev = ax.T_joint_child
        F[m] = prev @ self.tool
        return F

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
        base: FloatArray | None = None,
        tool: FloatArray | None = None,
        name: str = "",
        *,
        title: str = "",
        description: str = "",
        source: str = "",
        planar: bool = False,
        task: str = "auto",
        configurations: Sequence[NamedConfiguration] = (),
        param_names: Mapping[str, str] | None = None,
        translations: Mapping[str, Mapping[str, str]] | None = None,
    ) -> Robot:
        """Build a robot from a Denavit–Hartenberg table.

        Args:
            rows: One mapping per joint with keys ``joint`` (``"revolute"`` or
                ``"prismatic"``), ``a`` [m], ``alpha`` [rad], ``d`` [m], ``theta`` [rad],
                optional ``qlim`` (lower, upper) and ``name``. For a revolute joint
                θ = q + ``theta`` and ``d`` is constant; for a prismatic joint
                d = q + ``d`` and ``theta`` is constant. See :func:`kinematics.dh.parse_dh_table`
                for what is checked.
            convention: ``"standard"``: A = Rz(θ) Tz(d) Tx(a) Rx(α);
                ``"modified"`` (Craig): A = Rx(α) Tx(a) Rz(θ) Tz(d).
            base, tool: 4×4 rigid transforms; T_base_tool = base · A1 ⋯ An · tool.
            name: Robot identifier.
            title, description, source, planar, task, configurations, param_names, translations: See
                the attributes of :class:`Robot`.

        Raises:
            RobotDefinitionError: The message names the row and key (``DH row 2, key 'a'``),
                or the attribute, and what was expected.

        Example:
            >>> r = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0, d=0, theta=0)] * 2)
            >>> r.dof
            2
        """
        from .dh import dh_chain, parse_dh_table

        conv = check_choice(convention, CONVENTIONS, "DH convention")
        dh = parse_dh_table(rows)
        joints, axes = dh_chain(dh, conv)
        return cls(
            name=name,
            joints=joints,
            axes=axes,
            base=np.eye(4) if base is None else base,
            tool=np.eye(4) if tool is None else tool,
            dh=dh,
            convention=conv,
            planar=planar,
            task=check_choice(task, TASKS, f"robot {name!r}, task"),
            title=title,
            description=description,
            source=source,
            configurations=tuple(configurations),
            param_names={} if param_names is None else param_names,
            translations={} if translations is None else translations,
        )


_P = TypeVar("_P")


def _parts(items: object, kind: type[_P], where: str) -> tuple[_P, ...]:
    """``items`` as a tuple whose elements are all ``kind`` instances."""
    if isinstance(items, (str, bytes, Mapping)) or not isinstance(items, (Sequence, np.ndarray)):
        raise RobotDefinitionError(f"{where}: expected a sequence of {kind.__name__}, got {show(items)}")
    for i, item in enumerate(items):
        if not isinstance(item, kind):
            raise RobotDefinitionError(f"{where}[{i}]: expected a {kind.__name__}, got {show(item)}")
    return tuple(items)
