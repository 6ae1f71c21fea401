"""The pace of a resolved-rate motion: slower near a singularity, so a teacher can narrate the blow-up.

Held at real time, the course's q̇ = J⁻¹ v blows up in the last half second before a singularity
(the Puma's q̇₄ goes from 32 to 502 °/s in 0.5 s). Here the motion's own time runs slower than the
clock whenever a step would make the joint rates grow faster than :data:`RATE_GROWTH` per second of
the clock: the physics is unchanged (every step is still q_{k+1} = q_k + Δt J⁻¹ v with the same v,
and the charts are against the motion's time), only the film is slowed down near the singularity.

Pure: a function of the robot, q and the twist; the clock's Δt comes in as an argument.
"""

from __future__ import annotations

import math

import numpy as np

from kinematics import Robot
from kinematics.motion import resolved_rate

__all__ = ["RATE_GROWTH", "paced_step", "rate_growth"]

RATE_GROWTH = math.log(1.5)
"""Largest growth of the joint rates [1/s of the clock], as d ln‖q̇‖/dt: ×1.5 per second at most, so
32 → 502 °/s takes about seven seconds to watch instead of half a second."""
_TRIES = 16
"""Shorter steps tried before the shortest is taken."""


def rate_growth(before: np.ndarray, after: np.ndarray) -> float:
    """ln(‖q̇ after‖ / ‖q̇ before‖): how much the joint rates grew (0 when either is zero)."""
    r0, r1 = float(np.linalg.norm(before)), float(np.linalg.norm(after))
    return math.log(r1 / r0) if r0 > 0.0 and r1 > 0.0 else 0.0


def paced_step(
    robot: Robot,
    q: np.ndarray,
    twist: np.ndarray,
    *,
    clock_dt: float,
    speed: float,
    frame: str,
    damping: float,
    rate_limit: float,
    rows: tuple[int, ...],
) -> tuple[np.ndarray, np.ndarray, resolved_rate.Stop | None, float]:
    """One resolved-rate step of ``clock_dt`` seconds of the clock at ``speed``, slowed down so the joint
    rates at the next configuration are at most exp(RATE_GROWTH · clock_dt) times those of this one.

    Returns:
        ``(q_next, qd, stop, dt)``: as :func:`kinematics.motion.resolved_rate.resolved_rate_step`,
        and ``dt`` [s], the motion's own time step (``clock_dt · speed`` far from singularities).
    """

    def step(at: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray, resolved_rate.Stop | None]:
        return resolved_rate.resolved_rate_step(
            robot,
            at,
            twist,
            dt=dt,
            frame=frame,  # type: ignore[arg-type]
            damping=damping,
            rate_limit=rate_limit,
            rows=rows,
        )

    dt = clock_dt * speed
    q_next, qd, stop = step(q, dt)
    allowed = RATE_GROWTH * clock_dt
    if stop is not None or not np.any(qd):  # a joint limit's step ends at the limit: its part of dt
        return q_next, qd, stop, dt * stop.share if stop is not None else dt
    # The local growth per second of the motion's time, from a tiny step: the first guess of the pace.
    h = min(dt, 1e-4)
    slope = rate_growth(qd, step(q + h * qd, h)[1]) / h
    if slope * dt > allowed:
        dt = 0.9 * allowed / slope
        q_next = q + dt * qd
    for _ in range(_TRIES):
        # At the next configuration and half-way there (a long step could jump over the singularity
        # to where the rates are as small again, as the 2R arm's elbow flipping through q2 = 0).
        grown = max(rate_growth(qd, step(q + 0.5 * dt * qd, dt)[1]), rate_growth(qd, step(q_next, dt)[1]))
        if grown <= allowed:
            break
        # ln‖q̇‖ grows about linearly in a short step: aim just under the bound.
        dt *= min(max(0.9 * allowed / grown, 0.05), 0.9)
        q_next = q + dt * qd
    return q_next, qd, None, dt
