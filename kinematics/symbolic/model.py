"""The symbolic twin of a :class:`~kinematics.model.Robot`: the same chain, in SymPy.

Every numeric quantity of the model becomes an exact SymPy number
(:mod:`.exact`: π/2 stays π/2, 0.4318 becomes 2159/5000). With
``symbolic_params=True`` the DH lengths and offsets become symbols instead
(``a2``, ``d4``, … in the usual DH names, or the course's names a robot file gives in
its ``[symbols]`` table: :attr:`~kinematics.model.Robot.param_names`), which is how a course
writes J.

Joint variables are the real symbols ``q1 … qn``; their display names
(θᵢ for a revolute joint, dᵢ for a prismatic one) are kept in
:attr:`SymbolicModel.display` for the printers.
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..conventions import FRAMES, Frame
from ..dh import dh_factors
from ..errors import JacobianLabError
from ..model import Robot
from ..parts import Convention
from .exact import SYMPY_OPS, exact_number
from .snap import LENGTH_NOISE, SNAP_TOL, Snap, Snapper, snap_summary
from .typeset.escape import plain

__all__ = [
    "SymbolicError",
    "SymbolicModel",
    "build_model",
    "check_frame",
    "FRAMES",
]


class SymbolicError(JacobianLabError):
    """A symbolic request is invalid: unknown frame or option, or a robot it cannot handle."""


def check_frame(frame: object) -> Frame:
    """Return ``frame`` if it is one of :data:`FRAMES` (``"base"``, ``"tool"``), else a SymbolicError."""
    for f in FRAMES:
        if isinstance(frame, str) and frame == f:
            return f
    raise SymbolicError(f"frame must be 'base' or 'tool', got {frame!r}")


@dataclass(frozen=True, eq=False)
class SymbolicModel:
    """A robot's chain in SymPy: ``T_base_tool = base · Π_k [parent_joint[k] · M_k · joint_child[k]] · tool``.

    Attributes:
        robot: The numeric robot this model was built from.
        q: Joint symbols ``q1 … qn`` (real).
        kinds: ``"revolute"`` or ``"prismatic"`` per axis.
        axis_joint: Index into ``q`` of the joint driving each axis.
        axis_value: θ [rad] or d [m] of each axis, ``multiplier · q_j + offset``.
        parent_joint, joint_child: The fixed 4×4 transforms around each axis.
        base, tool: 4×4 transforms.
        params: Symbolic parameters → their values [m] or [rad] (empty unless ``symbolic_params``).
        display: LaTeX display names of the joint and parameter symbols.
        symbolic_params: Whether DH lengths and offsets are symbols.
        snaps: Rounded values of the robot replaced by exact ones (:mod:`.snap`).
        dh: (θ, d, a, α) of each DH row as the model holds them (θ or d includes the joint
            symbol); empty for a robot without a DH table.
        exact: Every number as the robot file gives it (nothing snapped to π/12 multiples or 0).
    """

    robot: Robot
    q: tuple[sp.Symbol, ...]
    kinds: tuple[str, ...]
    axis_joint: tuple[int, ...]
    axis_value: tuple[sp.Expr, ...]
    parent_joint: tuple[sp.Matrix, ...]
    joint_child: tuple[sp.Matrix, ...]
    base: sp.Matrix
    tool: sp.Matrix
    params: dict[sp.Symbol, float] = field(default_factory=dict)
    display: dict[sp.Symbol, str] = field(default_factory=dict)
    symbolic_params: bool = False
    snaps: tuple[Snap, ...] = ()
    dh: tuple[tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr], ...] = ()
    exact: bool = False

    @property
    def snap_note(self) -> str:
        """The note saying which values were snapped and the largest change ("" if none)."""
        return snap_summary(self.snaps)

    @property
    def dof(self) -> int:
        """Number of joint symbols."""
        return len(self.q)

    @property
    def joint_kinds(self) -> tuple[str, ...]:
        """``"revolute"`` or ``"prismatic"`` per joint symbol."""
        return self.robot.joint_types

    def cache_key(self) -> str:
        """Text identifying the model for caches: fingerprint, option and parameter names."""
        names = ",".join(sorted(str(s) for s in self.params))
        tol = "none (exact)" if self.exact else SNAP_TOL
        return f"{self.robot.fingerprint()}|params={self.symbolic_params}|{names}|snap={tol}"

    def angle_offsets(self) -> dict[sp.Symbol, sp.Expr]:
        """Joint symbol → constant offset of its revolute axis, for offsets that are not multiples of π/2.

        Only for one axis per joint driving it with multiplier 1 (θ = q + offset).
        """
        out = {}
        for kind, j, value in zip(self.kinds, self.axis_joint, self.axis_value, strict=True):
            off = sp.expand(value - self.q[j])
            if (
                kind == "revolute"
                and off != 0
                and not off.has(*self.q)
                and not (off / (sp.pi / 2)).is_Integer
            ):
                out[self.q[j]] = off
        return out if len(self.kinds) == self.dof else {}

    def exact_values(self) -> dict[sp.Symbol, sp.Expr]:
        """Parameter symbols → their exact values (what the model holds with ``symbolic_params=False``)."""
        S = Snapper(0.0 if self.exact else SNAP_TOL)  # the values the model holds, not recorded again
        return {s: S.angle(v, "") if _is_angle(s) else S.length(v, "") for s, v in self.params.items()}

    def numeric_values(self) -> dict[sp.Symbol, sp.Float]:
        """Parameter symbols → their values as SymPy floats (for evaluating an expression)."""
        return {s: sp.Float(v, 17) for s, v in self.params.items()}


class _Params:
    """Collects parameter symbols while a model is built."""

    def __init__(self, robot: Robot, enabled: bool, exact: bool = False) -> None:
        self.enabled = enabled
        # Course names from the robot (Robot.param_names, checked there). Default names are the DH
        # ones (a{i}, alpha{i}, d{i}, theta{i}; for the modified convention a and alpha of row i are
        # Craig's a_{i-1}, alpha_{i-1}), d{i}0 / theta{i}0 for the constant offset of a joint
        # variable, and xt, yt, zt / xb, yb, zb for the tool / base translation.
        self.snap = Snapper(0.0 if exact else SNAP_TOL)
        self.rename = dict(robot.param_names)
        self.values: dict[sp.Symbol, float] = {}
        self.display: dict[sp.Symbol, str] = {}

    def length(self, name: str, value: float, latex: str, where: str) -> sp.Expr:
        if not self.enabled or abs(value) <= LENGTH_NOISE:
            return self.snap.length(value, where)
        return self._symbol(name, value, latex)

    def angle(self, name: str, value: float, latex: str, where: str) -> sp.Expr:
        snapped = self.snap.snapped_angle(value)
        if not self.enabled or (snapped is not None and (snapped / (sp.pi / 2)).is_Integer):
            return self.snap.angle(value, where)
        return self._symbol(name, value, latex)

    def _symbol(self, name: str, value: float, latex: str) -> sp.Symbol:
        if re.fullmatch(r"[A-Za-z][A-Za-z0-9]{0,15}", str(self.rename.get(name, ""))):  # never markup
            name = self.rename[name]
            latex = _generic_latex(name)
        sym = sp.Symbol(name, real=True)
        self.values[sym] = float(value)
        self.display[sym] = latex
        return sym


def _is_angle(s: sp.Symbol) -> bool:
    return str(s).startswith(("alpha", "theta"))


def _generic_latex(name: str) -> str:
    stem = name.rstrip("0123456789")
    digits = name[len(stem) :]
    greek = {"alpha", "theta", "beta", "gamma"}
    head = f"\\{stem}" if stem in greek else stem
    return f"{head}_{{{digits}}}" if digits else head


DHValues = tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]
"""(θ, d, a, α) of one DH row, the joint symbol in θ or d."""
_DHAxes = tuple[list[sp.Matrix], list[sp.Matrix], list[sp.Expr], list[DHValues]]


def _dh_axes(robot: Robot, P: _Params) -> _DHAxes | None:
    """(parent_joint, joint_child, offsets, (theta, d, a, alpha) per row) rebuilt from the DH table;
    None if it does not match the axes."""
    if robot.dh is None or len(robot.axes) != len(robot.dh):
        return None
    convention: Convention = "modified" if robot.convention == "modified" else "standard"
    modified = convention == "modified"
    pj, jc, offsets, table = [], [], [], []
    for i, (row, ax) in enumerate(zip(robot.dh, robot.axes, strict=True), start=1):
        k = i - 1 if modified else i  # Craig's a_{i-1}, alpha_{i-1}
        at = f"DH row {i}:"
        a = P.length(f"a{k}", row.a, f"a_{{{k}}}", f"{at} a")
        alpha = P.angle(f"alpha{k}", row.alpha, f"\\alpha_{{{k}}}", f"{at} alpha")
        revolute = row.joint == "revolute"
        if revolute:
            d = P.length(f"d{i}", row.d, f"d_{{{i}}}", f"{at} d")
            theta = P.angle(f"theta{i}0", row.theta, f"\\theta_{{{i}}}^{{0}}", f"{at} theta")
        else:
            d = P.length(f"d{i}0", row.d, f"d_{{{i}}}^{{0}}", f"{at} d")
            theta = P.angle(f"theta{i}", row.theta, f"\\theta_{{{i}}}", f"{at} theta")
        T_pj, T_jc = dh_factors(
            SYMPY_OPS, revolute, "modified" if modified else "standard", a, alpha, d, theta
        )
        pj.append(T_pj)
        jc.append(T_jc)
        offsets.append(theta if revolute else d)
        table.append((theta, d, a, alpha))
        if ax.kind != row.joint or ax.joint_index != i - 1 or ax.multiplier != 1.0:
            return None
    return pj, jc, offsets, table


def _frame(T: np.ndarray, P: _Params, side: str) -> sp.Matrix:
    M = P.snap.transform(T, f"{side} transform")
    for r, axis in enumerate("xyz"):
        if M[r, 3] != 0:
            where = f"{side} transform: translation {axis}"
            M[r, 3] = P.length(f"{axis}{side[0]}", float(T[r, 3]), f"{axis}_{{\\mathrm{{{side[0]}}}}}", where)
    return M


def _numeric_mismatch(model: SymbolicModel) -> bool:
    """True if the exact transforms do not reproduce the robot's numeric ones (to 1e-9, or to the
    size of what was snapped)."""
    vals = model.numeric_values()
    scale = 1.0 + max((float(np.abs(ax.T_parent_joint[:3, 3]).max()) for ax in model.robot.axes), default=0.0)
    largest = max((s.change for s in model.snaps), default=0.0)
    atol = 1e-9 + 2 * largest * scale
    for ax, pj, jc in zip(model.robot.axes, model.parent_joint, model.joint_child, strict=True):
        for S, N in ((pj, ax.T_parent_joint), (jc, ax.T_joint_child)):
            if not np.allclose(np.array(S.xreplace(vals).evalf(), dtype=float), N, atol=atol):
                return True
    return False


@functools.lru_cache(maxsize=64)
def build_model(robot: Robot, symbolic_params: bool = False, exact: bool = False) -> SymbolicModel:
    """The :class:`SymbolicModel` of ``robot`` (cached per robot object and option).

    Args:
        robot: Any robot (DH or URDF chain).
        symbolic_params: Keep DH lengths and offsets, and base/tool translations, as symbols.
        exact: Keep every number of the robot file as written (no snapping of 1.5708 to π/2): what a
            controller wants, at the cost of longer formulas.

    Raises:
        SymbolicError: ``symbolic_params`` for a robot that has no DH table.
    """
    if not isinstance(robot, Robot):
        raise SymbolicError(f"expected a kinematics.Robot, got {type(robot).__name__}")
    if not isinstance(symbolic_params, bool):
        raise SymbolicError(f"symbolic_params must be True or False, got {symbolic_params!r}")
    P = _Params(robot, symbolic_params, exact)
    n = robot.dof
    q = tuple(sp.Symbol(f"q{i + 1}", real=True) for i in range(n))
    kinds = tuple(ax.kind for ax in robot.axes)
    dh = _dh_axes(robot, P)
    if dh is None and symbolic_params:
        raise SymbolicError(
            f"robot {robot.name!r}: symbolic parameters need a robot built from a DH table "
            "(this one is a URDF or hand-built chain); use symbolic_params=False"
        )
    table: tuple[DHValues, ...] = ()
    if dh is not None:
        pj, jc, offsets, rows = dh
        values = [q[ax.joint_index] + off for ax, off in zip(robot.axes, offsets, strict=True)]
        table = tuple(
            (v, d, a, alpha) if kind == "revolute" else (theta, v, a, alpha)
            for v, kind, (theta, d, a, alpha) in zip(values, kinds, rows, strict=True)
        )
    else:
        pj = [P.snap.transform(ax.T_parent_joint, f"joint {plain(ax.name, 60)!r}") for ax in robot.axes]
        jc = [
            P.snap.transform(ax.T_joint_child, f"joint {plain(ax.name, 60)!r} (after the axis)")
            for ax in robot.axes
        ]
        values = [
            exact_number(ax.multiplier) * q[ax.joint_index]
            + (
                P.snap.angle(ax.offset, f"joint {plain(ax.name, 60)!r}: offset")
                if ax.kind == "revolute"
                else P.snap.length(ax.offset, f"joint {plain(ax.name, 60)!r}: offset")
            )
            for ax in robot.axes
        ]
    display = {
        s: (f"\\theta_{{{i + 1}}}" if k == "revolute" else f"d_{{{i + 1}}}")
        for i, (s, k) in enumerate(zip(q, robot.joint_types, strict=True))
    }
    base, tool = _frame(robot.base, P, "base"), _frame(robot.tool, P, "tool")
    model = SymbolicModel(
        robot,
        q,
        kinds,
        tuple(ax.joint_index for ax in robot.axes),
        tuple(values),
        tuple(pj),
        tuple(jc),
        base,
        tool,
        dict(P.values),
        {**display, **P.display},
        symbolic_params,
        tuple(P.snap.snaps),
        table,
        exact,
    )
    if dh is not None and _numeric_mismatch(model):  # a DH table that does not describe the axes
        raise SymbolicError(f"robot {robot.name!r}: its DH table does not reproduce its axes")
    return model
