"""Inverse kinematics by the course's Newton iteration (or damped least squares).

The course solves k(q) = y_d by ``q_{k+1} = q_k + J(q_k)⁻¹ (y_d − k(q_k))`` (``J⁺`` when J is not
square). :func:`solve` does exactly that on the robot's task rows of the base-frame geometric
Jacobian; the error of a pose target is the position error [m] and the rotation vector [rad] of
``R_target R_toolᵀ`` (in base axes, the quantity J's ω rows change), so one Newton step is one
linearised solve. ``method="dls"`` replaces J⁺ by Jᵀ(JJᵀ + λ²I)⁻¹: slower to converge, but its
steps stay bounded near a singularity.

Solving never raises for a target that cannot be reached (out of reach, singular start): the
result says ``converged=False`` and holds the best (finite) configuration found.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, cast

import numpy as np
import numpy.typing as npt

from ..analysis import DEFAULT_RTOL, PART_ROWS, Part, part_rows, task_rows
from ..conventions import FloatArray
from ..errors import ArrayError, ConfigurationError, OptionError
from ..kernel import Kernel, chain_single, jacobian_from_frames, kernel
from ..model import Robot
from ..numeric import as_configuration
from ..validation import is_number, show

__all__ = ["IkResult", "Method", "METHODS", "solve", "pose_error", "target_rows", "pinv_solve"]

Method = Literal["newton", "dls"]
METHODS: tuple[Method, ...] = ("newton", "dls")
STALL_STEP = 1e-15
"""A step with max |Δq| below STALL_STEP · (1 + max |q|) that leaves the error unchanged: "stalled"."""


@dataclass(frozen=True, eq=False)
class IkResult:
    """What :func:`solve` found.

    Attributes:
        q: (n,) the iterate with the smallest error norm [rad | m] (the last one when converged).
        converged: True when ‖error‖ ≤ tol.
        iterations: Number of steps taken.
        errors: (iterations + 1,) error norm of every iterate, starting with ``q0``'s
            (mixed units: m for position rows, rad for orientation rows).
        residual: Error vector (one entry per row solved for) at ``q``.
        reason: ``"converged"``, ``"iteration limit"`` or ``"stalled"`` (a step no longer
            changes q: a singular or unreachable target).
    """

    q: FloatArray
    converged: bool
    iterations: int
    errors: FloatArray
    residual: FloatArray
    reason: str


def target_rows(robot: Robot, target_is_point: bool, rows: Part | tuple[int, ...] | None) -> list[int]:
    """The rows of J solved for: ``rows`` (default the robot's task rows); only v rows for a point."""
    chosen = task_rows(robot) if rows is None else part_rows(rows)
    if target_is_point:
        chosen = tuple(r for r in chosen if r in PART_ROWS["linear"])
        if not chosen:
            raise OptionError(
                f"rows {show(rows)} hold no position row (0-2) to solve for a position target; "
                "pass a 4×4 pose target or include rows 0-2"
            )
    return list(chosen)


def pose_error(T_base_tool: FloatArray, target: FloatArray) -> FloatArray:
    """Error (6,) [m, rad] from the tool pose to ``target`` (a 4×4 pose or a (3,) point).

    ``[p_target − p_tool; log(R_target R_toolᵀ)]`` in base axes; the rotation part is zero for a
    point target.
    """
    e = np.zeros(6)
    if target.shape == (3,):
        e[:3] = target - T_base_tool[:3, 3]
        return e
    e[:3] = target[:3, 3] - T_base_tool[:3, 3]
    R = target[:3, :3] @ T_base_tool[:3, :3].T
    w = (R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1])
    s = 0.5 * math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])  # sin(angle)
    cos_angle = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    angle = math.atan2(s, cos_angle)
    if cos_angle < 0.0 and s < 1e-3:
        # Near π the skew part w is tiny: take the axis u from the symmetric part,
        # (R + Rᵀ)/2 − cos I = (1 − cos) uuᵀ (its dominant column), signed along w.
        S = (R + R.T) * 0.5
        S[np.diag_indices(3)] -= cos_angle
        k = int(np.argmax(np.diag(S)))
        axis = S[:, k] / math.sqrt(S[k, k] * (1.0 - cos_angle))
        if axis @ np.array(w) < 0.0:
            axis = -axis
        e[3:] = angle * axis
        return e
    f = 0.5 if s < 1e-12 else 0.5 * angle / s
    e[3], e[4], e[5] = f * w[0], f * w[1], f * w[2]
    return e


def pinv_solve(J: FloatArray, e: FloatArray, damping: float = 0.0, rtol: float = DEFAULT_RTOL) -> FloatArray:
    """J⁺ e (σ below ``rtol · max(σmax, 1)`` dropped, as :func:`kinematics.inverse.pinv`), or the
    damped least-squares Jᵀ(JJᵀ + λ²I)⁻¹ e for ``damping`` λ > 0. Inputs are not checked.

    A well-conditioned J with no more rows than columns is solved through JJᵀ (a 6×6 solve, a
    few times cheaper than the SVD); anything else goes through the SVD.
    """
    m, n = J.shape
    if m <= n:
        A = J @ J.T
        scale = float(np.trace(A)) / m  # mean σ²
        if damping > 0.0:
            A[np.diag_indices(m)] += damping * damping
        try:
            x = np.linalg.solve(A, e)
        except np.linalg.LinAlgError:
            x = None
        if x is not None:
            dq: FloatArray = J.T @ x
            ee = float(e @ e)
            if damping > 0.0:
                if np.isfinite(dq).all():
                    return dq
            # Newton: accept when the implied gain ‖dq‖/‖e‖ is far below the SVD cut-off (κ ≲ 1e6)
            # and J dq reproduces e (a numerically singular JJᵀ can give neither).
            elif (dq @ dq) * scale * _FAST_GAIN <= ee:
                r = J @ dq - e
                if r @ r <= 1e-16 * ee:
                    return dq
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    if damping > 0.0:
        f = s / (s * s + damping * damping)
    else:
        keep = s > rtol * max(float(s[0]) if s.size else 0.0, 1.0)
        f = np.where(keep, 1.0 / np.where(keep, s, 1.0), 0.0)
    return cast(FloatArray, Vt.T @ (f * (U.T @ e)))


_FAST_GAIN = 1e-12  # (1e-6)²: the JJᵀ path is used only while ‖dq‖ ≤ 1e6 ‖e‖ / σ_rms


def _check_target(target: object) -> FloatArray:
    try:
        a = np.asarray(target)
    except (TypeError, ValueError, OverflowError):
        raise ArrayError(f"target must be a point (3,) or a pose (4, 4), got {show(target)}") from None
    if a.dtype.kind not in "iuf" or a.shape not in ((3,), (4, 4)):
        raise ArrayError(
            f"target must be a tool position (3,) [m] or a pose T_base_target (4, 4), got {show(target)}"
        )
    a = a.astype(float)
    if not np.isfinite(a).all():
        raise ArrayError("target contains NaN or infinity")
    if a.shape == (4, 4):
        R = a[:3, :3]
        rigid = np.abs(R.T @ R - np.eye(3)).max() <= 1e-6 and np.linalg.det(R) > 0
        if not rigid or np.abs(a[3] - (0.0, 0.0, 0.0, 1.0)).max() > 1e-6:
            raise ArrayError(
                "target: a pose must be a rigid transform (orthonormal rotation block with det +1, "
                "last row [0, 0, 0, 1])"
            )
    return a


def _check_options(
    method: object, damping: object, tol: object, max_iterations: object, step_limit: object
) -> None:
    if not (isinstance(method, str) and method in METHODS):
        raise OptionError(f"method must be one of 'newton', 'dls', got {show(method)}")
    if not (is_number(damping) and 0.0 <= damping < math.inf):
        raise OptionError(f"damping must be a finite number ≥ 0, got {show(damping)}")
    if not (is_number(tol) and 0.0 < tol < math.inf):
        raise OptionError(f"tol must be a positive number, got {show(tol)}")
    if not (isinstance(max_iterations, (int, np.integer)) and not isinstance(max_iterations, bool)):
        raise OptionError(f"max_iterations must be an int ≥ 0, got {show(max_iterations)}")
    if max_iterations < 0:
        raise OptionError(f"max_iterations must be an int ≥ 0, got {show(max_iterations)}")
    if step_limit is not None and not (is_number(step_limit) and 0.0 < step_limit < math.inf):
        raise OptionError(f"step_limit must be None or a positive number [rad | m], got {show(step_limit)}")


def solve(
    robot: Robot,
    target: npt.ArrayLike,
    q0: npt.ArrayLike,
    *,
    method: Method = "newton",
    damping: float = 0.05,
    rows: Part | tuple[int, ...] | None = None,
    tol: float = 1e-10,
    max_iterations: int = 100,
    step_limit: float | None = None,
) -> IkResult:
    """Joint values that put the tool on ``target``, iterating from ``q0``.

    Args:
        robot: The robot.
        target: Tool position (3,) [m] or tool pose ``T_base_target`` (4, 4), base frame.
        q0: Start configuration (n,) [rad | m] (the app's current q: a warm start).
        method: ``"newton"``: q += J⁺ e (the course's J⁻¹ e for a square J; σ below the
            relative tolerance of :func:`kinematics.inverse.pinv` dropped, so a singular J
            still gives a finite step); ``"dls"``: q += Jᵀ(JJᵀ + λ²I)⁻¹ e.
        damping: λ of ``"dls"`` [units of the rows]; ignored by Newton.
        rows: Rows of J (and of the error) to solve for; default the robot's task rows. With a
            point target only the position rows among them are used.
        tol: Convergence threshold on the error norm.
        max_iterations: Most steps taken.
        step_limit: If set, a step is scaled down so that max |Δqᵢ| ≤ step_limit [rad | m].

    Returns:
        :class:`IkResult`. Never raises for an unreachable target.

    Raises:
        ConfigurationError: ``q0`` is not one configuration of the robot.
        ArrayError: ``target`` is not a finite (3,) point or a rigid 4×4 pose.
        OptionError: unknown method, negative damping, bad tol, max_iterations, step_limit or rows.
    """
    c = kernel(robot)
    q = as_configuration(robot, q0, "q0").copy()
    if q.ndim != 1:
        raise ConfigurationError(f"q0 must be one configuration ({robot.dof},), got shape {q.shape}")
    goal = _check_target(target)
    _check_options(method, damping, tol, max_iterations, step_limit)
    chosen = target_rows(robot, goal.shape == (3,), rows)
    lam = float(damping) if method == "dls" else 0.0
    return _iterate(c, q, goal, chosen, lam, float(tol), int(max_iterations), step_limit)


def _iterate(
    c: Kernel,
    q: FloatArray,
    goal: FloatArray,
    rows: list[int],
    lam: float,
    tol: float,
    max_iterations: int,
    step_limit: float | None,
) -> IkResult:
    """The Newton / DLS loop on checked input."""
    bound = c.bound
    W, T = chain_single(c, q)
    e = pose_error(T, goal)[rows]
    err = float(np.linalg.norm(e))
    errors = [err]
    best = (err, q, e)
    reason = "iteration limit"
    k = 0
    while True:
        if err <= tol:
            reason = "converged"
            break
        if k >= max_iterations:
            break
        J = jacobian_from_frames(c, W, T)[rows]
        dq = pinv_solve(J, e, lam)
        biggest = float(np.abs(dq).max())
        if step_limit is not None and biggest > step_limit:
            dq *= step_limit / biggest
        q_new = q + dq
        if not (np.abs(q_new) <= bound).all():  # a runaway step: keep q within the model's range
            q_new = np.clip(q_new, -bound, bound)
        k += 1
        if biggest <= STALL_STEP * (1.0 + float(np.abs(q).max())):
            errors.append(err)
            reason = "stalled"
            break
        q = q_new
        W, T = chain_single(c, q)
        e = pose_error(T, goal)[rows]
        err = float(np.linalg.norm(e))
        errors.append(err)
        if err < best[0]:
            best = (err, q, e)
    if reason == "converged":
        best = (err, q, e)
    return IkResult(
        q=best[1],
        converged=reason == "converged",
        iterations=k,
        errors=np.array(errors),
        residual=best[2],
        reason=reason,
    )
