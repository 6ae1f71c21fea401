"""Where a manipulability climb leaves the self-motion: its s and its (s, w) chart (pure)."""

from __future__ import annotations

import numpy as np

from .motion_state import MotionState, readonly

__all__ = ["ROW_WORDS", "climbed_along"]

ROW_WORDS = ("vx", "vy", "vz", "ωx", "ωy", "ωz")


def climbed_along(m: MotionState, q0: np.ndarray, q1: np.ndarray, w0: float, w1: float) -> MotionState:
    """The self-motion's s and (s, w) chart after a climb step from ``q0`` (w = ``w0``) to ``q1``
    (w = ``w1``): the climb moves along the same null-space curve as the self-motion slider, so s grows by
    the step's joint-space length [rad | m], signed by the curve's positive direction (the climb's own
    first step when the slider has not set one)."""
    st = m.self_trace if len(m.self_trace) else np.array([[m.s, w0]])
    dq = np.asarray(q1, float) - np.asarray(q0, float)
    length = float(np.linalg.norm(dq))
    if length == 0.0:
        return m.replace(self_trace=readonly(st))
    u = dq / length
    direction = u if m.direction is None else np.asarray(m.direction, float)
    sign = 1.0 if float(u @ direction) >= 0.0 else -1.0
    s = m.s + sign * length
    trace = readonly(np.vstack([st, [[s, w1]]])[-600:])
    return m.replace(s=float(s), self_trace=trace, direction=readonly(sign * u))
