"""Everything one redraw needs, computed once per event by calling :mod:`kinematics`.

:func:`compute` is the only place the app asks for maths: forward
kinematics, the Jacobian in base and tool axes, the singularity report,
the measures the panel reads out, the ellipsoids, the lost direction
(rotations weighed by the arm's reach), and the three mappings of the
course: v = J q̇, q̇ = J⁺ v (with the twist it actually produces and what is
lost), τ = Jᵀ F. Views only draw a :class:`Snapshot`; they never compute.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kinematics import Robot, jacobian, jacobian_dot, jacobian_dot_alone
from kinematics.analysis import (
    Ellipsoid,
    condition_number,
    condition_of,
    force_ellipsoid,
    measures,
    task_rows,
    velocity_ellipsoid,
)
from kinematics.inverse import solve_rates
from kinematics.numeric import frames_and_jacobian
from kinematics.singularity import SingularityReport, assess
from kinematics.singularity.decoupling import Decoupling, decouple
from kinematics.singularity.limits import LimitContact, limit_contacts
from kinematics.singularity.lost import LostDirection, lost_direction
from kinematics.singularity.null_motion import NullMotion, null_motion

from ..ranges import reach
from ..state import LabState
from ..tool_path import planned
from .course import AnalyticView, InverseView, analytic_view, inverse_view, with_closed_form
from .derive import Derivation, derivation
from .losses import Loss, block_ellipsoids, losses
from .maps import Cloud, JointMap, joint_map, workspace_cloud

__all__ = ["Snapshot", "compute", "translational_rows", "Loss"]


def translational_rows(planar: bool) -> tuple[int, ...]:
    """Rows of J measured for the translational condition number: (vx, vy) for a planar arm."""
    return (0, 1) if planar else (0, 1, 2)


@dataclass(frozen=True, eq=False)
class Snapshot:
    """One tab's state after one event, ready to draw.

    Attributes:
        q: Joint values (n,) [rad | m].
        link_frames: T_base_link (m + 2, 4, 4): frame 0, every link frame, the tool.
        joint_frames: T_base_joint (m, 4, 4): the frame of every moving axis (z = axis).
        J_base: Geometric Jacobian (6, n), rows [v; ω] in base axes.
        J_shown: The Jacobian in the frame the tab chose (6, n).
        rows: Task rows of J (what det J, κ and rank refer to).
        report: Singularity report (status, kinds, σmin, κ).
        sigma: Singular values of the task rows, descending.
        manipulability: Yoshikawa's w = Π σᵢ of the task rows (0 with more rows than joints).
        det: det J of the task rows when square, else ``None``.
        rank: Numerical rank of the task rows.
        cond_translational, cond_rotational: κ of the v rows and of the ω rows (``inf`` when
            singular); a planar arm has no rotational one (``None``).
        velocity, rotational, force: Ellipsoids at the tool point (base axes); the rotational
            and force ellipsoids only when they are drawn (``None`` otherwise).
        lost: The lost direction, ω rows weighed by ``length`` (``None`` when regular: not shown).
        length: Characteristic length L [m] (the arm's reach) weighing rad/s against m/s.
        twist: J_base q̇ (6,) [m/s; rad/s].
        rates: Joint rates for the desired twist, J⁺ v or damped (n,).
        produced: The task twist those rates actually produce, J q̇ (task rows, others 0) (6,).
        shortfall: What is lost, v − J q̇ over the task rows (6,).
        torques: Jᵀ F (n,) [N·m | N] balancing the applied wrench.
        joint_map: w over the two chosen joints (when the map is shown), else ``None``.
        cloud: The workspace cloud (when shown), else ``None``.
        derive: The Derive tab's step as numbers (when it walks through a method), else ``None``.
        inverse: J⁻¹ (or J⁺) of the task J the q̇ = J⁺ v tab uses (``None`` only for a hand-built one).
        analytic: φ, M(φ) and J_A when the J(q) tab shows an analytic Jacobian, else ``None``.
        jdot_qd: J̇ q̇ (6,) [m/s²; rad/s²], base axes: the tool's acceleration at constant joint rates
            (zero when q̇ = 0).
        jdot: J̇ (6, n) [m/s; rad/s per rad or m], base axes, every moving joint counted (zero when q̇ = 0).
        jdot_alone: 000's per-joint J̇ᵢ as columns (6, n): column i for joint i moving alone.
        jdot_terms: 000's per-joint terms J̇ᵢ q̇ᵢ (6, n) [m/s²; rad/s²], column i with the course's J̇ᵢ
            (joint i moving alone); their sum equals J̇ q̇ only when one joint moves.
        j_qdd: J q̈ (6,) [m/s²; rad/s²], base axes: the acceleration map's other term.
        tool_accel: ẍ = J q̈ + J̇ q̇ (6,) [m/s²; rad/s²], base axes: the tool's acceleration.
        jdot_gap: J̇ q̇ − Σᵢ J̇ᵢ q̇ᵢ (6,): what 000's per-joint terms miss (zero when one joint moves).
        decoupling: J at the wrist centre in arm and wrist blocks (a spherical wrist), else ``None``.
        losses: Every lost direction, each at its own point (none when regular).
        arm_ellipsoid, wrist_ellipsoid: The decoupled blocks' ellipsoids at the wrist centre (the
            wrist centre's velocity by the arm joints, the angular velocity by the wrist joints), when
            the arm or the wrist block loses a direction (they are drawn only then), else ``None``.
        limits: The joints at a limit (a critical point of the course's 002: each can move one way only).
        null: A null joint motion (Ker J of the task rows) at a singularity, else ``None``.
        planned: The chosen path y(t) (k, 3) [m], base axes (:func:`app.core.tool_path.planned`), drawn
            before and while it is followed; ``None`` when no path is chosen.
        T_tool: T_base_tool (4, 4): the tool pose (where the drag handle sits).
    """

    q: np.ndarray
    link_frames: np.ndarray
    joint_frames: np.ndarray
    J_base: np.ndarray
    J_shown: np.ndarray
    rows: tuple[int, ...]
    report: SingularityReport
    sigma: np.ndarray
    manipulability: float
    det: float | None
    rank: int
    cond_translational: float
    cond_rotational: float | None
    velocity: Ellipsoid
    rotational: Ellipsoid | None
    force: Ellipsoid | None
    lost: LostDirection | None
    length: float
    twist: np.ndarray
    rates: np.ndarray
    produced: np.ndarray
    shortfall: np.ndarray
    torques: np.ndarray
    joint_map: JointMap | None = None
    cloud: Cloud | None = None
    derive: Derivation | None = None
    inverse: InverseView | None = None
    analytic: AnalyticView | None = None
    jdot_qd: np.ndarray | None = None
    jdot: np.ndarray | None = None
    jdot_alone: np.ndarray | None = None
    jdot_terms: np.ndarray | None = None
    j_qdd: np.ndarray | None = None
    tool_accel: np.ndarray | None = None
    jdot_gap: np.ndarray | None = None
    decoupling: Decoupling | None = None
    losses: tuple[Loss, ...] = ()
    arm_ellipsoid: Ellipsoid | None = None
    wrist_ellipsoid: Ellipsoid | None = None
    null: NullMotion | None = None
    limits: tuple[LimitContact, ...] = ()
    planned: np.ndarray | None = None

    @property
    def T_tool(self) -> np.ndarray:
        """The tool pose T_base_tool (4, 4)."""
        return self.link_frames[-1]

    @property
    def tool_point(self) -> np.ndarray:
        """Origin of the tool frame in base coordinates (3,) [m]."""
        return self.link_frames[-1, :3, 3]


def compute(state: LabState) -> Snapshot:
    """Evaluate everything the views draw for ``state`` (one call per event)."""
    robot, q = state.robot, state.q
    planar, n = robot.planar, robot.dof
    L, W, J = frames_and_jacobian(robot, q)  # one evaluation of the chain
    J_shown = jacobian(robot, q, "tool") if state.options.jacobian_frame == "tool" else J
    rows = task_rows(robot)
    report = assess(robot, q, J)
    J_task = J[list(rows)]
    square = J_task.shape[0] == n
    length = reach(robot)
    v_task = state.v_desired[list(rows)]
    J_twist = J_task if state.options.twist_frame == "base" else jacobian(robot, q, "tool")[list(rows)]
    rates = solve_rates(J_twist, v_task, state.options.damping) if np.any(v_task) else np.zeros(n)
    produced = np.zeros(6)
    produced[list(rows)] = J_twist @ rates
    m = measures(J, rows)  # σ, w, rank and κ of the task rows: one SVD
    rank_task = m.rank
    velocity = velocity_ellipsoid(J, "linear")
    t_rows = translational_rows(planar)
    # κ of the v rows: the velocity ellipsoid's radii are their singular values (zero-padded when n < 3).
    cond_v = condition_of(velocity.radii) if len(t_rows) == 3 else condition_number(J, t_rows)
    moving = bool(np.any(state.qd))
    representation = state.options.representation
    shortfall = np.zeros(6)
    shortfall[list(rows)] = state.v_desired[list(rows)] - produced[list(rows)]
    decoupled = decouple(robot, q, J)
    every_loss = losses(report, J, rows, length, L[-1, :3, 3], W, decoupled)
    # The blocks' ellipsoids are drawn only where a block loses a direction (two SVDs spared otherwise).
    blocks = {loss.part for loss in every_loss} & {"arm", "wrist"}
    arm_e, wrist_e = block_ellipsoids(decoupled) if blocks else (None, None)
    Jdot = jacobian_dot(robot, q, state.qd) if moving else np.zeros((6, n))
    Jdot_alone = jacobian_dot_alone(robot, q, state.qd) if moving else np.zeros((6, n))
    return Snapshot(
        q=np.array(q),
        link_frames=L,
        joint_frames=W,
        J_base=J,
        J_shown=J_shown,
        rows=rows,
        report=report,
        sigma=m.sigma,
        manipulability=m.manipulability,
        det=float(np.linalg.det(J_task)) if square else None,
        rank=rank_task,
        cond_translational=float(cond_v),
        cond_rotational=None if planar else float(condition_number(J, "angular")),
        velocity=velocity,
        rotational=velocity_ellipsoid(J, "angular")
        if state.options.rotational_ellipsoid and not planar
        else None,
        force=force_ellipsoid(J, "linear") if state.options.force_ellipsoid else None,
        lost=lost_direction(J, rows, length) if report.status != "regular" else None,
        length=length,
        twist=J @ state.qd,
        rates=rates,
        produced=produced,
        shortfall=shortfall,
        torques=J.T @ state.wrench,
        joint_map=_map(state),
        cloud=workspace_cloud(robot) if state.options.workspace else None,
        derive=derivation(state, L),
        inverse=with_closed_form(
            inverse_view(J_twist, rank_task), robot, q, state.options.twist_frame == "base"
        ),
        analytic=analytic_view(L[-1], J, representation) if representation != "geometric" else None,
        jdot_qd=Jdot @ state.qd,
        jdot=Jdot,
        jdot_alone=Jdot_alone,
        jdot_terms=Jdot_alone * state.qd,
        j_qdd=J @ state.qdd,
        tool_accel=J @ state.qdd + Jdot @ state.qd,
        jdot_gap=Jdot @ state.qd - Jdot_alone @ state.qd,
        decoupling=decoupled,
        losses=every_loss,
        arm_ellipsoid=arm_e,
        wrist_ellipsoid=wrist_e,
        null=_null(robot, q) if report.status != "regular" else None,
        limits=limit_contacts(robot, q),
        planned=planned(state),
    )


def _null(robot: Robot, q: np.ndarray) -> NullMotion | None:
    """The null motion where the task rows lose rank (``None`` near, but not at, a singularity)."""
    found = null_motion(robot, q)
    return found if found.dimension else None


def _map(state: LabState) -> JointMap | None:
    o = state.options
    if not o.joint_map or state.robot.dof < 2 or o.map_i == o.map_j:
        return None
    return joint_map(state.robot, np.array(state.q), o.map_i, o.map_j)
