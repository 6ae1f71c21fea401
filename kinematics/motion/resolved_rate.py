"""Resolved-rate motion: the course's q_{k+1} = q_k + Δt · J(q_k)⁻¹ v.

:func:`resolved_rate_step` is one step (what the app's ticker calls once per animation frame);
:func:`resolved_rate` runs it repeatedly and records σmin, κ and w along the way. Both use the
same step, so the app and the library agree exactly.

A step is *refused* (q stays where it is, and a :class:`Stop` says why) when

* ``"singular"``: the task rows of J lose rank (σmin ≤ 1e-9 · max(σmax, 1)) and no damping is
  used: J⁻¹ does not exist, the course's scheme has no answer;
* ``"rate bound"``: some |q̇ᵢ| exceeds ``rate_limit`` [rad/s | m/s] (the joint named is the one
  with the largest |q̇ᵢ| / rate_limit);
* ``"joint limit"``: q + Δt q̇ would cross a joint limit: the part of the step up to the first limit
  met is taken, so the motion ends exactly AT that limit (that joint on its bound, the others moved
  along the same step: a critical point of the course's 002) and q never leaves the limits; a joint
  already outside its limits only stops when moving further out (then q stays).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from ..analysis import DEFAULT_RTOL, Part, part_rows, task_rows
from ..conventions import FloatArray
from ..errors import ArrayError, ConfigurationError, OptionError
from ..kernel import batched_jacobian, kernel
from ..model import Robot
from ..numeric import Frame, as_configuration, check_frame, jacobian
from ..validation import is_number, show
from .ik import pinv_solve

__all__ = ["Stop", "StopKind", "Trajectory", "resolved_rate", "resolved_rate_step", "RATE_LIMIT"]

RATE_LIMIT = 10.0
"""Default bound on every |q̇ᵢ| [rad/s | m/s]."""

StopKind = Literal["joint limit", "rate bound", "singular"]


@dataclass(frozen=True)
class Stop:
    """Why a resolved-rate motion stopped.

    Attributes:
        kind: ``"joint limit"``, ``"rate bound"`` or ``"singular"``.
        joint: Index (0-based) of the joint concerned, or None (``"singular"``).
        step: Index of the refused step (0 for a lone :func:`resolved_rate_step`); the
            trajectory holds q_0 … q_step (and a joint limit's partial step after them, if it
            moved).
        message: One line for a status bar, e.g. ``"joint 3 'q3' would pass its upper limit 170°"``.
        share: The part s ∈ [0, 1) of the refused step taken before stopping: a joint limit's step up
            to the limit (q + s·Δt·q̇); 0 for the other kinds.
    """

    kind: StopKind
    joint: int | None
    step: int
    message: str
    share: float = 0.0


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A resolved-rate motion of k ≤ steps steps.

    Attributes:
        q: (k+1, n) configurations [rad | m], q[0] = q0.
        qd: (k, n) joint rates used for each step [rad/s | m/s].
        time: (k+1,) [s].
        sigma_min: (k+1,) smallest singular value of the task rows of J (base frame).
        kappa: (k+1,) their condition number σmax/σmin; ``inf`` where singular
            (σmin ≤ 1e-9 · max(σmax, 1), as :func:`kinematics.analysis.condition_number`).
        inverse_kappa: (k+1,) σmin/σmax in [0, 1], always finite: plot this.
        w: (k+1,) manipulability √det(J Jᵀ) of the task rows.
        stopped: None if every step was taken, else the :class:`Stop` of the refused step (a joint
            limit's partial step, when it moved, is the last row of ``q``, ``qd`` and ``time``).
    """

    q: FloatArray
    qd: FloatArray
    time: FloatArray
    sigma_min: FloatArray
    kappa: FloatArray
    inverse_kappa: FloatArray
    w: FloatArray
    stopped: Stop | None


def _positive(x: object, what: str, unit: str) -> float:
    if not (is_number(x) and 0.0 < x < math.inf):
        raise OptionError(f"{what} must be a positive number [{unit}], got {show(x)}")
    return float(x)


def _twist(twist: object, rows: list[int]) -> FloatArray:
    try:
        a = np.asarray(twist)
    except (TypeError, ValueError, OverflowError):
        raise ArrayError(f"twist must be an array of numbers, got {show(twist)}") from None
    if a.dtype.kind not in "iuf" or a.ndim != 1 or len(a) not in (6, len(rows)):
        raise ArrayError(
            f"twist must be [v; ω] (6,) [m/s, rad/s] or its task part ({len(rows)},) for rows {tuple(rows)}, "
            f"got {show(twist)}"
        )
    a = a.astype(float)
    if not np.isfinite(a).all():
        raise ArrayError("twist contains NaN or infinity")
    return a[rows] if len(a) == 6 else a


def _value(robot: Robot, i: int, x: float) -> str:
    if robot.joints[i].kind == "revolute":
        return f"{math.degrees(x):.4g}°"
    return f"{x:.4g} m"


def _check(
    robot: Robot,
    q: object,
    twist: object,
    dt: object,
    frame: object,
    damping: object,
    rate_limit: object,
    rows: Part | tuple[int, ...] | None,
) -> tuple[FloatArray, FloatArray, float, Frame, float, float, list[int]]:
    qa = as_configuration(robot, q)
    if qa.ndim != 1:
        raise ConfigurationError(f"q must be one configuration ({robot.dof},), got shape {qa.shape}")
    chosen = list(task_rows(robot) if rows is None else part_rows(rows))
    v = _twist(twist, chosen)
    if not (is_number(damping) and 0.0 <= damping < math.inf):
        raise OptionError(f"damping must be a finite number ≥ 0, got {show(damping)}")
    return (
        qa,
        v,
        _positive(dt, "dt", "s"),
        check_frame(frame),
        float(damping),
        _positive(rate_limit, "rate_limit", "rad/s or m/s"),
        chosen,
    )


def _step(
    robot: Robot,
    q: FloatArray,
    v: FloatArray,
    dt: float,
    frame: Frame,
    lam: float,
    limit: float,
    rows: list[int],
) -> tuple[FloatArray, FloatArray, Stop | None]:
    """One step on checked input."""
    J = jacobian(robot, q, frame)[rows]
    if lam == 0.0:
        s = np.linalg.svd(J, compute_uv=False)
        k = min(J.shape)
        if J.shape[0] > J.shape[1] or s[k - 1] <= DEFAULT_RTOL * max(float(s[0]), 1.0):
            msg = "the task rows of J lost rank: J⁻¹ does not exist here (use damping > 0)"
            return q, np.zeros_like(q), Stop("singular", None, 0, msg)
    qd = pinv_solve(J, v, lam)
    ratio = np.abs(qd) / limit
    i = int(np.argmax(ratio))
    if ratio[i] > 1.0:
        unit = "rad/s" if robot.joints[i].kind == "revolute" else "m/s"
        need = f"|q̇| = {abs(qd[i]):.4g} {unit} > {limit:g} {unit}"
        msg = f"joint {i + 1} {robot.joints[i].name!r} would need {need}"
        return q, qd, Stop("rate bound", i, 0, msg)
    q_next, met, side, share = _to_limit(robot, q, dt * qd)
    if met is not None:
        value = robot.qlim[0 if side == "lower" else 1, met]
        name, where = robot.joints[met].name, _value(robot, met, value)
        msg = f"joint {met + 1} {name!r} would pass its {side} limit {where}"
        return q_next, qd, Stop("joint limit", met, 0, msg, share)
    return q_next, qd, None


def _to_limit(robot: Robot, q: FloatArray, dq: FloatArray) -> tuple[FloatArray, int | None, str, float]:
    """q + dq, or when that would cross a joint limit the part s·dq (0 ≤ s < 1) that ends exactly at the
    first limit met, that joint set to its bound and the others moved along the same step (a joint
    already outside its limits and moving further out: s = 0).

    Returns it, the joint met (None: none), its side and s (1 when none is met)."""
    lo, hi = robot.qlim
    q_full = q + dq
    over = (q_full > hi) & (dq > 0)
    under = (q_full < lo) & (dq < 0)
    if not (over.any() or under.any()):
        return q_full, None, "", 1.0
    bound = np.where(over, hi, lo)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(over | under, (bound - q) / np.where(dq != 0, dq, 1.0), np.inf)
    i = int(np.argmin(share))
    s = float(min(max(share[i], 0.0), 1.0))
    side = "upper" if over[i] else "lower"
    if s == 0.0:
        return q.copy(), i, side, 0.0
    q_next = q + s * dq
    inside = (q >= lo) & (q <= hi)
    q_next = np.where(inside & over, np.minimum(q_next, hi), q_next)
    q_next = np.where(inside & under, np.maximum(q_next, lo), q_next)
    q_next[i] = bound[i]
    return q_next, i, side, s


def resolved_rate_step(
    robot: Robot,
    q: npt.ArrayLike,
    twist: npt.ArrayLike,
    *,
    dt: float,
    frame: Frame = "base",
    damping: float = 0.0,
    rate_limit: float = RATE_LIMIT,
    rows: Part | tuple[int, ...] | None = None,
) -> tuple[FloatArray, FloatArray, Stop | None]:
    """One resolved-rate step: q̇ = J⁻¹ v (J⁺ v if J is not square; DLS if ``damping`` > 0).

    Args:
        robot: The robot.
        q: Current configuration (n,) [rad | m].
        twist: Desired tool twist [v; ω] (6,) [m/s, rad/s], or only its task part (one value
            per row in ``rows``).
        dt: Time step [s].
        frame: ``"base"``: twist in base axes; ``"tool"``: in tool axes (so a constant twist
            is constant in the moving tool frame).
        damping: λ of damped least squares Jᵀ(JJᵀ + λ²I)⁻¹ (0: the pseudo-inverse).
        rate_limit: Largest |q̇ᵢ| accepted [rad/s | m/s].
        rows: Rows of J that form the task; default the robot's task rows.

    Returns:
        ``(q_next, qd, stop)``: the next configuration, the joint rates of this step (those the
        step would have needed when refused for a rate bound or joint limit; zeros when
        singular), and None or the :class:`Stop` (with ``step`` = 0). When refused, ``q_next``
        equals ``q``, except at a joint limit: then it is q + s·Δt·q̇ (``stop.share`` = s), ending
        exactly at the limit met.
    """
    qa, v, dt_, frame_, lam, limit, chosen = _check(robot, q, twist, dt, frame, damping, rate_limit, rows)
    return _step(robot, qa, v, dt_, frame_, lam, limit, chosen)


def resolved_rate(
    robot: Robot,
    q0: npt.ArrayLike,
    twist: npt.ArrayLike,
    *,
    dt: float,
    steps: int,
    frame: Frame = "base",
    damping: float = 0.0,
    rate_limit: float = RATE_LIMIT,
    rows: Part | tuple[int, ...] | None = None,
) -> Trajectory:
    """Follow a constant twist for up to ``steps`` steps of :func:`resolved_rate_step`.

    Stops early at the first refused step (see the module docstring); ``stopped`` says why.
    Arguments as :func:`resolved_rate_step`; ``steps`` is an int ≥ 0.
    """
    q, v, dt_, frame_, lam, limit, chosen = _check(robot, q0, twist, dt, frame, damping, rate_limit, rows)
    if not (isinstance(steps, (int, np.integer)) and not isinstance(steps, bool) and steps >= 0):
        raise OptionError(f"steps must be an int ≥ 0, got {show(steps)}")
    qs, qds, times = [q], [], [0.0]
    stopped = None
    for k in range(int(steps)):
        q_next, qd, stop = _step(robot, q, v, dt_, frame_, lam, limit, chosen)
        if stop is not None:
            stopped = dataclasses.replace(stop, step=k)
            if stop.share > 0.0:  # the part of the step up to the joint limit
                qs.append(q_next)
                qds.append(qd)
                times.append(dt_ * (k + stop.share))
            break
        q = q_next
        qs.append(q)
        qds.append(qd)
        times.append(dt_ * (k + 1))
    Q = np.array(qs)
    sigma_min, kappa, inverse_kappa, w = measures(robot, Q, chosen)
    return Trajectory(
        q=Q,
        qd=np.array(qds).reshape(len(qds), robot.dof),
        time=np.array(times, dtype=np.float64),
        sigma_min=sigma_min,
        kappa=kappa,
        inverse_kappa=inverse_kappa,
        w=w,
        stopped=stopped,
    )


def measures(
    robot: Robot, Q: FloatArray, rows: list[int]
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """σmin, κ (``inf`` where singular), σmin/σmax and w of the task rows, for a batch Q (N, n)."""
    _, J = batched_jacobian(kernel(robot), Q)
    Js = J[:, rows]
    s = np.linalg.svd(Js, compute_uv=False).astype(np.float64, copy=False)
    missing = Js.shape[1] > Js.shape[2]
    smin = np.zeros(len(Q)) if missing else s[:, -1]
    smax = s[:, 0]
    singular = smin <= DEFAULT_RTOL * np.maximum(smax, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = np.where(singular, np.inf, smax / np.where(singular, 1.0, smin))
        inverse = np.where(smax > 0, smin / np.where(smax > 0, smax, 1.0), 0.0)
    w = np.zeros(len(Q)) if missing else np.prod(s, axis=1)
    return smin, kappa, inverse, w
