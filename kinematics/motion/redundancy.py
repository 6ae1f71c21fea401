"""Redundancy: joint motions that leave the tool's task where it is.

A robot with more joints than task rows has a null space of J: joint rates q̇ with J q̇ = 0.

* :func:`self_motion` walks along it (the unit null-space direction, its sign kept from step to
  step), correcting the first-order drift with Newton steps back onto the initial tool pose.
* :func:`climb` follows the course's q̇ = (I − J⁺J) ∇w, raising Yoshikawa's manipulability
  w = √det(J Jᵀ) of the task rows while the tool stays put. ∇w is taken by central finite
  differences (h = 1e-6), all 2n Jacobians in one batched evaluation.

Both hold the task rows of the tool pose (position and/or orientation, as the rows say) to
about 1e-12 per step, and each has a single-step form for the app (:func:`self_motion_step`,
:func:`climb_step`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

import numpy as np
import numpy.typing as npt

from ..analysis import Part, null_space, part_rows, task_rows
from ..conventions import FloatArray
from ..errors import ConfigurationError, OptionError
from ..kernel import batched_jacobian, kernel
from ..model import Robot
from ..numeric import as_configuration, fk, jacobian
from ..validation import is_number, show
from .ik import pinv_solve, solve

__all__ = [
    "SelfMotion",
    "Climb",
    "self_motion",
    "self_motion_step",
    "climb",
    "climb_step",
    "task_manipulability",
    "manipulability_gradient",
]

FD_STEP = 1e-6
"""Central-difference step [rad | m] of :func:`manipulability_gradient`."""
HOLD_TOL = 1e-12
"""Error norm the drift correction aims for (m and rad)."""


@dataclass(frozen=True, eq=False)
class SelfMotion:
    """A self-motion: ``q`` (steps+1, n) [rad | m]; ``w`` (steps+1,) task manipulability;
    ``s`` (steps+1,) the parameter k · step (joint-space distance along the null direction)."""

    q: FloatArray
    w: FloatArray
    s: FloatArray


@dataclass(frozen=True, eq=False)
class Climb:
    """A manipulability climb: ``q`` (steps+1, n) [rad | m]; ``w`` (steps+1,), non-decreasing."""

    q: FloatArray
    w: FloatArray


def _setup(robot: Robot, q: object, rows: Part | tuple[int, ...] | None) -> tuple[FloatArray, list[int]]:
    qa = as_configuration(robot, q)
    if qa.ndim != 1:
        raise ConfigurationError(f"q must be one configuration ({robot.dof},), got shape {qa.shape}")
    chosen = list(task_rows(robot) if rows is None else part_rows(rows))
    if robot.dof <= len(chosen):
        raise OptionError(
            f"robot {robot.name!r} has no redundancy on rows {tuple(chosen)}: {robot.dof} joints for "
            f"{len(chosen)} task rows (self-motion needs more joints than rows; pass fewer rows)"
        )
    return qa, chosen


def _hold(robot: Robot, q: FloatArray, hold: object) -> FloatArray:
    return fk(robot, q) if hold is None else np.asarray(hold, dtype=float)


def _count(x: object, what: str) -> int:
    if not (isinstance(x, (int, np.integer)) and not isinstance(x, bool) and x >= 0):
        raise OptionError(f"{what} must be an int ≥ 0, got {show(x)}")
    return int(x)


def _project(robot: Robot, q: FloatArray, T_hold: FloatArray, rows: list[int]) -> FloatArray:
    """Newton steps (minimum-norm, so they add no self-motion) back onto the held pose."""
    return solve(robot, T_hold, q, rows=tuple(rows), tol=HOLD_TOL, max_iterations=8).q


def task_manipulability(robot: Robot, Q: FloatArray, rows: list[int]) -> FloatArray:
    """w = √det(J Jᵀ) of the task rows for a batch Q (N, n) (rows ≤ n)."""
    _, J = batched_jacobian(kernel(robot), Q)
    Js = J[:, rows]
    det = np.linalg.det(Js @ Js.transpose(0, 2, 1))
    return cast(FloatArray, np.sqrt(np.maximum(det, 0.0)))


def manipulability_gradient(robot: Robot, q: FloatArray, rows: list[int]) -> FloatArray:
    """∇w (n,) at q by central differences (step :data:`FD_STEP`), one batch of 2n Jacobians."""
    n = len(q)
    H = FD_STEP * np.eye(n)
    w = task_manipulability(robot, np.concatenate([q + H, q - H]), rows)
    return (w[:n] - w[n:]) / (2.0 * FD_STEP)


def self_motion_step(
    robot: Robot,
    q: npt.ArrayLike,
    *,
    step: float,
    rows: Part | tuple[int, ...] | None = None,
    direction: object = None,
    hold: object = None,
) -> tuple[FloatArray, FloatArray]:
    """One self-motion step of length ``step`` [rad | m in joint space].

    Args:
        robot: A robot with more joints than task rows.
        q: Current configuration (n,).
        step: Step length along the unit null-space direction (negative: the other way).
        rows: Task rows held; default the robot's task rows.
        direction: The previous step's direction (n,): the new one is chosen with a positive
            dot product with it (and, for a null space of several dimensions, as close to it as
            possible). None: the null-space basis vector whose largest component is positive.
        hold: ``T_base_tool`` to hold (4, 4); default the tool pose at ``q``. Pass the pose at
            the start of the motion so that drift never accumulates.

    Returns:
        ``(q_next, direction)``: the corrected configuration and the unit direction used.
    """
    qa, chosen = _setup(robot, q, rows)
    if not (is_number(step) and math.isfinite(step)):
        raise OptionError(f"step must be a finite number [rad | m], got {show(step)}")
    T_hold = _hold(robot, qa, hold)
    N = null_space(jacobian(robot, qa), tuple(chosen))
    if direction is None:
        d = N[:, 0]
        d = d if d[np.argmax(np.abs(d))] > 0 else -d
    else:
        prev = np.asarray(direction, dtype=float)
        if prev.shape != (robot.dof,) or not np.isfinite(prev).all():
            raise OptionError(f"direction must be a finite ({robot.dof},) vector, got {show(direction)}")
        d = N @ (N.T @ prev)
        norm = float(np.linalg.norm(d))
        d = d / norm if norm > 1e-12 else N[:, 0]
        if d @ prev < 0:
            d = -d
    return _project(robot, qa + float(step) * d, T_hold, chosen), d


def self_motion(
    robot: Robot, q0: npt.ArrayLike, *, step: float, steps: int, rows: Part | tuple[int, ...] | None = None
) -> SelfMotion:
    """``steps`` steps of :func:`self_motion_step` from ``q0``, holding the tool pose at ``q0``.

    Raises:
        OptionError: the robot has no more joints than task rows (no self-motion), bad step/steps.
    """
    q, chosen = _setup(robot, q0, rows)
    count = _count(steps, "steps")
    T_hold = fk(robot, q)
    qs, d = [q], None
    for _ in range(count):
        q, d = self_motion_step(robot, q, step=step, rows=tuple(chosen), direction=d, hold=T_hold)
        qs.append(q)
    Q = np.array(qs)
    return SelfMotion(
        q=Q, w=task_manipulability(robot, Q, chosen), s=float(step) * np.arange(len(Q), dtype=np.float64)
    )


def climb_step(
    robot: Robot,
    q: npt.ArrayLike,
    *,
    gain: float = 1.0,
    max_step: float = 0.1,
    rows: Part | tuple[int, ...] | None = None,
    hold: object = None,
) -> tuple[FloatArray, float]:
    """One step of q̇ = (I − J⁺J) ∇w with the tool held; w never decreases.

    The step is Δq = gain · (I − J⁺J) ∇w, scaled down to a norm of at most ``max_step``
    [rad | m], then projected back onto the held pose. If w would drop (a step past the
    maximum along the self-motion), the step is halved, up to 20 times; if w still drops, q is
    returned unchanged (a maximum is reached).

    Returns:
        ``(q_next, w_next)``.
    """
    qa, chosen = _setup(robot, q, rows)
    for value, what in ((gain, "gain"), (max_step, "max_step")):
        if not (is_number(value) and 0.0 < value < math.inf):
            raise OptionError(f"{what} must be a positive number, got {show(value)}")
    T_hold = _hold(robot, qa, hold)
    J = jacobian(robot, qa)[chosen]
    g = manipulability_gradient(robot, qa, chosen)
    dq = float(gain) * (g - pinv_solve(J, J @ g))  # (I − J⁺J) ∇w
    norm = float(np.linalg.norm(dq))
    if norm > max_step:
        dq *= max_step / norm
    w0 = float(task_manipulability(robot, qa[None], chosen)[0])
    for _ in range(21):
        q_new = _project(robot, qa + dq, T_hold, chosen)
        w_new = float(task_manipulability(robot, q_new[None], chosen)[0])
        if w_new >= w0:
            return q_new, w_new
        dq *= 0.5
    return qa, w0


def climb(
    robot: Robot,
    q0: npt.ArrayLike,
    *,
    steps: int,
    gain: float = 1.0,
    max_step: float = 0.1,
    rows: Part | tuple[int, ...] | None = None,
) -> Climb:
    """``steps`` steps of :func:`climb_step` from ``q0``, holding the tool pose at ``q0``."""
    q, chosen = _setup(robot, q0, rows)
    count = _count(steps, "steps")
    T_hold = fk(robot, q)
    qs = [q]
    ws = [float(task_manipulability(robot, q[None], chosen)[0])]
    for _ in range(count):
        q, w = climb_step(robot, q, gain=gain, max_step=max_step, rows=tuple(chosen), hold=T_hold)
        qs.append(q)
        ws.append(w)
    return Climb(q=np.array(qs), w=np.array(ws))
