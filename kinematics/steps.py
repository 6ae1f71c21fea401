"""The course's derivations of J, step by step, as numbers at one configuration (for drawing).

:mod:`kinematics.symbolic.steps` gives each step as a formula; this module gives the same
steps as vectors at ``q``, cheap enough to redraw on every slider move:

* :func:`whitney`: for every axis, its direction z and a point p on it, the arm
  r = p_tool − p, and Whitney's column (z × r, z) for a revolute axis, (z, 0) for a
  prismatic one;
* :func:`differentiation`: ∂p/∂qⱼ and the ω part taken from (∂R/∂qⱼ) Rᵀ by central
  differences of the forward kinematics, one joint at a time: the derivative the course
  writes by hand, checked here against the definition;
* :func:`propagation`: the angular velocity ωₖ and origin velocity vₖ of every link frame,
  outward from the base (Craig's outward iteration), in base axes and in the link's own axes;
* :func:`force_propagation`: a wrench at the tool carried inward, joint by joint, to the
  torque (or force) each joint must supply: τ = Jᵀ F.

All vectors are in base axes unless a name says otherwise (``omega_own``: link axes).
With mimic axes (URDF) one joint drives several axes: every step is per axis, and
``joint`` says which actuated joint drives it (``multiplier`` scales its rate).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Literal, cast

import numpy as np
import numpy.typing as npt

from .conventions import FloatArray
from .errors import ArrayError
from .method_texts import INTROS, TITLES
from .model import Robot
from .numeric import as_configuration, chain_frames, fk, link_frames
from .parts import JointType
from .text import N_
from .validation import show

__all__ = [
    "WhitneyColumn",
    "whitney",
    "DerivativeColumn",
    "differentiation",
    "LinkVelocity",
    "propagation",
    "JointLoad",
    "force_propagation",
    "DIFF_STEP",
    "JointDerivative",
    "StepMethod",
    "METHODS",
    "DERIVATIONS",
    "PATH_POINTS",
]

DIFF_STEP = 1e-6
"""Step of the central differences in :func:`differentiation` [rad | m]."""


@dataclass(frozen=True)
class WhitneyColumn:
    """Whitney's column of one axis at q (base axes).

    Attributes:
        axis: Index of the axis in ``robot.axes``.
        joint: Index of the actuated joint that drives it.
        multiplier: Axis rate per joint rate (1 without mimic joints).
        kind: "revolute" or "prismatic".
        z: Unit direction of the axis (3,).
        p: A point on the axis (the joint frame's origin) (3,) [m].
        r: p_tool − p (3,) [m]: the arm from the axis to the tool point.
        linear: z × r (revolute) or z (prismatic) (3,): tool-point velocity per unit axis rate.
        angular: z (revolute) or 0 (prismatic) (3,).
    """

    axis: int
    joint: int
    multiplier: float
    kind: JointType
    z: FloatArray
    p: FloatArray
    r: FloatArray
    linear: FloatArray
    angular: FloatArray

    @property
    def column(self) -> FloatArray:
        """The column (6,) [linear; angular] this axis adds to J (times ``multiplier``)."""
        return self.multiplier * np.concatenate([self.linear, self.angular])


def whitney(robot: Robot, q: npt.ArrayLike) -> tuple[WhitneyColumn, ...]:
    """Whitney's construction of every column of J at ``q``: one :class:`WhitneyColumn` per axis.

    Summing ``column`` over the axes of joint j gives column j of :func:`kinematics.jacobian`.
    """
    W, T = chain_frames(robot, as_configuration(robot, q))
    p_tool = T[:3, 3]
    out = []
    for k, ax in enumerate(robot.axes):
        z, p = W[k, :3, 2].copy(), W[k, :3, 3].copy()
        r = p_tool - p
        revolute = ax.kind == "revolute"
        out.append(
            WhitneyColumn(
                axis=k,
                joint=ax.joint_index,
                multiplier=float(ax.multiplier),
                kind=ax.kind,
                z=z,
                p=p,
                r=r,
                linear=np.cross(z, r) if revolute else z,
                angular=z if revolute else np.zeros(3),
            )
        )
    return tuple(out)


@dataclass(frozen=True)
class DerivativeColumn:
    """Column j of J by differentiating the forward kinematics in qⱼ (base axes).

    Attributes:
        joint: The joint j.
        dp: ∂p_tool/∂qⱼ (3,) [m/rad | m/m].
        S: (∂R/∂qⱼ) Rᵀ (3, 3): skew-symmetric, its axial vector is the ω part.
        omega: The axial vector of S (3,).
    """

    joint: int
    dp: FloatArray
    S: FloatArray
    omega: FloatArray

    @property
    def column(self) -> FloatArray:
        return np.concatenate([self.dp, self.omega])


def differentiation(
    robot: Robot, q: npt.ArrayLike, h: float = DIFF_STEP, joints: Sequence[int] | None = None
) -> tuple[DerivativeColumn, ...]:
    """Columns of J as the derivative of the forward kinematics (central differences, step ``h``):
    every joint's, or those of ``joints``, in that order."""
    q = as_configuration(robot, q)
    R = fk(robot, q)[:3, :3]
    out = []
    for j in range(robot.dof) if joints is None else joints:
        dq = np.zeros(robot.dof)
        dq[j] = h
        Tp, Tm = fk(robot, q + dq), fk(robot, q - dq)
        dp = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        S = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ R.T
        omega = 0.5 * np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]])
        out.append(DerivativeColumn(joint=j, dp=dp, S=S, omega=omega))
    return tuple(out)


@dataclass(frozen=True)
class LinkVelocity:
    """Velocity of one link frame, propagated outward from the base.

    Attributes:
        frame: Index into :func:`kinematics.link_frames` (1 … m: after axis frame − 1; m + 1: the tool).
        origin: The frame's origin (3,) [m].
        R: Its orientation R_base_frame (3, 3).
        omega: Angular velocity (3,) [rad/s], base axes.
        v: Velocity of the frame's origin (3,) [m/s], base axes.
    """

    frame: int
    origin: FloatArray
    R: FloatArray
    omega: FloatArray
    v: FloatArray

    @property
    def omega_own(self) -> FloatArray:
        """ω in the frame's own axes (Craig's ⁱωᵢ)."""
        return cast(FloatArray, self.R.T @ self.omega)


def _axis_rates(robot: Robot, qd: FloatArray) -> FloatArray:
    return np.array([ax.multiplier * qd[ax.joint_index] for ax in robot.axes])


def propagation(robot: Robot, q: npt.ArrayLike, qd: npt.ArrayLike) -> tuple[LinkVelocity, ...]:
    """ωₖ and vₖ of every link frame and of the tool, outward from frame 0 (at rest).

    Link by link: ωₖ = ωₖ₋₁ + q̇ₖ zₖ (revolute), vₖ = vₖ₋₁ + ωₖ₋₁ × (oₖ − oₖ₋₁) + (rotation about
    the new axis) or + q̇ₖ zₖ (prismatic). The last entry is the tool: (v, ω) = J q̇.
    """
    q = as_configuration(robot, q)
    qd = as_configuration(robot, qd, "qd")
    L = link_frames(robot, q)
    W, _ = chain_frames(robot, q)
    rates = _axis_rates(robot, qd)
    omega, v, o_prev = np.zeros(3), np.zeros(3), L[0, :3, 3]
    out = []
    for k, ax in enumerate(robot.axes):
        z, p, o = W[k, :3, 2], W[k, :3, 3], L[k + 1, :3, 3]
        # The old frame's motion carried to the joint's axis point, then the joint's own motion.
        v_axis = v + np.cross(omega, p - o_prev)
        if ax.kind == "revolute":
            omega = omega + rates[k] * z
            v = v_axis + np.cross(omega, o - p)
        else:
            v = v_axis + rates[k] * z + np.cross(omega, o - p)
        o_prev = o
        out.append(LinkVelocity(k + 1, o.copy(), L[k + 1, :3, :3].copy(), omega.copy(), v.copy()))
    tool = L[-1, :3, 3]
    out.append(
        LinkVelocity(
            len(L) - 1, tool.copy(), L[-1, :3, :3].copy(), omega.copy(), v + np.cross(omega, tool - o_prev)
        )
    )
    return tuple(out)


@dataclass(frozen=True)
class JointLoad:
    """What one axis must supply to hold a wrench applied at the tool (statics, no gravity).

    Attributes:
        axis: Index of the axis; ``joint`` drives it (``multiplier`` scales its share).
        p: The axis point (3,) [m]; z: its direction (3,).
        force: Force carried through the axis (3,) [N], base axes (the tool force).
        moment: Moment about ``p`` (3,) [N·m], base axes: n + (p_tool − p) × f.
        load: z · moment (revolute) or z · force (prismatic) [N·m | N]: the axis' torque or force.
    """

    axis: int
    joint: int
    multiplier: float
    kind: JointType
    p: FloatArray
    z: FloatArray
    force: FloatArray
    moment: FloatArray
    load: float


def force_propagation(robot: Robot, q: npt.ArrayLike, wrench: npt.ArrayLike) -> tuple[JointLoad, ...]:
    """The wrench ``[f; n]`` at the tool point (base axes) carried inward, last axis first.

    τⱼ = Σ over the axes of joint j of ``multiplier · load``: equal to (Jᵀ F)ⱼ.
    """
    q = as_configuration(robot, q)
    F = np.asarray(wrench, dtype=float)
    if F.shape != (6,) or not np.isfinite(F).all():
        raise ArrayError(f"wrench must be 6 finite numbers [f; n] (N, N·m), got {show(wrench)}")
    W, T = chain_frames(robot, q)
    f, n, p_tool = F[:3], F[3:], T[:3, 3]
    out = []
    for k in reversed(range(len(robot.axes))):
        ax = robot.axes[k]
        z, p = W[k, :3, 2].copy(), W[k, :3, 3].copy()
        moment = n + np.cross(p_tool - p, f)
        load = float(z @ moment) if ax.kind == "revolute" else float(z @ f)
        out.append(JointLoad(k, ax.joint_index, float(ax.multiplier), ax.kind, p, z, f.copy(), moment, load))
    return tuple(out)


PATH_POINTS = 41
"""Points of the tool path of a differentiation step (:class:`JointDerivative`)."""


@dataclass(frozen=True)
class JointDerivative:
    """One differentiation step: joint j's derivative and the tool path as qⱼ alone sweeps about q.

    Attributes:
        derivative: ∂/∂qⱼ of the forward kinematics (:func:`differentiation`).
        path: Tool points (PATH_POINTS, 3) [m] as qⱼ moves ±30° (±a tenth of ``reach`` for a slide).
    """

    derivative: DerivativeColumn
    path: np.ndarray


def _sweep_step(robot: Robot, q: np.ndarray, j: int, reach: float) -> JointDerivative:
    half = np.radians(30.0) if robot.joints[j].kind == "revolute" else 0.1 * max(reach, 0.1)
    Q = np.repeat(np.asarray(q, dtype=float)[None], PATH_POINTS, axis=0)
    Q[:, j] += np.linspace(-half, half, PATH_POINTS)
    return JointDerivative(differentiation(robot, q, joints=(j,))[0], fk(robot, Q)[:, :3, 3])


def _unit(n: int, j: int) -> FloatArray:
    return cast(FloatArray, np.eye(n)[j])


def _whitney_column(robot: Robot, q: npt.ArrayLike, j: int) -> FloatArray:
    column = np.zeros(6)
    for c in whitney(robot, q):
        if c.joint == j:
            column = column + c.column
    return column


def _propagated_column(robot: Robot, q: npt.ArrayLike, j: int) -> FloatArray:
    tool = propagation(robot, q, _unit(robot.dof, j))[-1]
    return np.concatenate([tool.v, tool.omega])


def _force_column(robot: Robot, q: npt.ArrayLike, j: int) -> FloatArray:
    """Column j of J as row j of Jᵀ: τⱼ for a unit force or moment along each base axis."""
    loads = [
        [float(x.multiplier * x.load) for x in force_propagation(robot, q, _unit(6, r)) if x.joint == j]
        for r in range(6)
    ]
    return np.array([sum(row, 0.0) for row in loads], dtype=np.float64)


@dataclass(frozen=True)
class StepMethod:
    """One of the course's ways through J, as numbers (the symbolic steps of the same key are in
    :data:`kinematics.symbolic.steps.methods.METHODS`; the app's Derive tab and the handout read both).

    Attributes:
        key: The one spelling of the method (``Options.derive``, ``handout --method``, symbolic steps).
        label: Its name with its formula (the Derive tab's dropdown; marked for the app's catalogs).
        title: Heading of its section in a handout.
        intro: The paragraph that opens that section.
        inputs: What a step needs besides q: "" nothing, "rates" q̇ (n,), "wrench" [f; n] (6,).
        step: ``step(robot, q, joint, inputs, reach)`` → the numbers of one step (``None``: DH frames).
        column: ``column(robot, q, joint)`` → column ``joint`` of J (6,) as this method builds it.
        symbols: Key prefixes of its symbolic steps for one joint (see :mod:`kinematics.symbolic.steps`).
    """

    key: str
    label: str
    title: str
    intro: str
    inputs: Literal["", "rates", "wrench"]
    step: Callable[[Robot, np.ndarray, int, np.ndarray, float], Any] | None
    column: Callable[[Robot, np.ndarray, int], np.ndarray] | None
    symbols: tuple[str, ...]


METHODS: dict[str, StepMethod] = {
    m.key: m
    for m in (
        StepMethod("dh", N_("DH frames: Aᵢ and ⁰Tᵢ"), "DH frames", "", "", None, None, ("A", "T0_")),
        StepMethod(
            "whitney",
            N_("Whitney: Jᵢ = zᵢ₋₁ × (pₙ − pᵢ₋₁)"),
            TITLES["whitney"],
            INTROS["whitney"],
            "",
            lambda robot, q, j, inputs, reach: whitney(robot, q),
            _whitney_column,
            ("whitney.",),
        ),
        StepMethod(
            "differentiation",
            N_("Differentiation: ∂p/∂qᵢ"),
            TITLES["differentiation"],
            INTROS["differentiation"],
            "",
            lambda robot, q, j, inputs, reach: _sweep_step(robot, q, j, reach),
            lambda robot, q, j: differentiation(robot, q, joints=(j,))[0].column,
            ("diff.",),
        ),
        StepMethod(
            "propagation",
            N_("Velocity propagation: ωᵢ, vᵢ"),
            TITLES["propagation"],
            INTROS["propagation"],
            "rates",
            lambda robot, q, j, inputs, reach: propagation(robot, q, inputs),
            _propagated_column,
            ("prop.",),
        ),
        StepMethod(
            "force",
            N_("Force propagation: τ = Jᵀ F"),
            TITLES["force"],
            INTROS["force"],
            "wrench",
            lambda robot, q, j, inputs, reach: force_propagation(robot, q, inputs),
            _force_column,
            ("force.",),
        ),
    )
}
"""Every method by key, in the order the Derive tab lists them (the DH frames first)."""

DERIVATIONS: tuple[str, ...] = tuple(k for k, m in METHODS.items() if m.column is not None)
"""The keys of the methods that build J (every one but the DH frames)."""
