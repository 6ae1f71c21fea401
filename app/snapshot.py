"""Everything one redraw needs, computed once per event by calling :mod:`kinematics`.

:func:`compute` is the only place the app asks for maths: forward
kinematics, the Jacobian in base and tool axes, the singularity report,
the measures the panel reads out, the ellipsoids, and the three mappings of
the course (v = J q̇, q̇ = J⁺ v, τ = Jᵀ F). The scene and the panel only
draw a :class:`Snapshot`; they never compute.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kinematics import jacobian, joint_frames, link_frames
from kinematics.analysis import (
    Ellipsoid,
    condition_number,
    force_ellipsoid,
    manipulability,
    rank,
    singular_values,
    task_rows,
    velocity_ellipsoid,
)
from kinematics.inverse import solve_rates
from kinematics.singularity import SingularityReport, assess

from .state import LabState

__all__ = ["Snapshot", "compute", "translational_rows"]


def translational_rows(planar: bool) -> tuple[int, ...]:
    """Rows of J measured for the translational condition number: (vx, vy) for a planar arm."""
    return (0, 1) if planar else (0, 1, 2)


@dataclass(frozen=True, eq=False)
class Snapshot:
    """The state of one client after one event, ready to draw.

    Attributes:
        q: Joint values (n,) [rad | m].
        link_frames: T_base_link (m + 2, 4, 4): frame 0, every link frame, the tool.
        joint_frames: T_base_joint (m, 4, 4): the frame of every moving axis (z = axis).
        J_base: Geometric Jacobian (6, n), rows [v; ω] in base axes.
        J_shown: The Jacobian in the frame the client chose (6, n).
        rows: Task rows of J (what the course's det J, cond J and rank refer to).
        report: Singularity report (status, kinds, lost direction).
        sigma: Singular values of the task rows, descending.
        manipulability: Yoshikawa's w = Π σᵢ of the task rows.
        det: det J of the task rows when they form a square matrix, else ``None``.
        rank: Numerical rank of the task rows.
        cond_translational, cond_rotational: Condition numbers of the linear and angular
            rows (``inf`` when singular); a planar arm has no rotational one (``None``).
        velocity, rotational, force: Ellipsoids at the tool point (base axes); a planar
            arm has no rotational ellipsoid (``None``).
        twist: J_base q̇ (6,) [m/s; rad/s].
        rates: Joint rates reaching the desired twist, J⁺ v (or damped) (n,).
        torques: Jᵀ F (n,) [N·m | N] balancing the applied wrench.
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
    force: Ellipsoid
    twist: np.ndarray
    rates: np.ndarray
    torques: np.ndarray

    @property
    def tool_point(self) -> np.ndarray:
        """Origin of the tool frame in base coordinates (3,) [m]."""
        return self.link_frames[-1, :3, 3]


def compute(state: LabState) -> Snapshot:
    """Evaluate everything the views draw for ``state`` (one call per event)."""
    robot, q = state.robot, state.q
    planar = robot.planar
    L = link_frames(robot, q)
    W = joint_frames(robot, q)
    J = jacobian(robot, q, "base")
    if state.options.jacobian_frame == "tool":
        J_shown = jacobian(robot, q, "tool")
    else:
        J_shown = J
    rows = task_rows(robot)
    report = assess(robot, q, J)
    J_task = J[list(rows)]
    square = J_task.shape[0] == J_task.shape[1]
    return Snapshot(
        q=q.copy(),
        link_frames=L,
        joint_frames=W,
        J_base=J,
        J_shown=J_shown,
        rows=rows,
        report=report,
        sigma=singular_values(J, rows),
        manipulability=float(manipulability(J, rows)),
        det=float(np.linalg.det(J_task)) if square else None,
        rank=int(rank(J, rows)),
        cond_translational=float(condition_number(J, translational_rows(planar))),
        cond_rotational=None if planar else float(condition_number(J, "angular")),
        velocity=velocity_ellipsoid(J, "linear"),
        rotational=velocity_ellipsoid(J, "angular") if not planar else None,
        force=force_ellipsoid(J, "linear"),
        twist=J @ state.qd,
        rates=solve_rates(J_task, state.v_desired[list(rows)], state.options.damping),
        torques=J.T @ state.wrench,
    )
