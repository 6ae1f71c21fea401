"""Where a manipulability climb leaves the self-motion: its s and its (s, w) chart (pure)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from kinematics.singularity.null_motion import null_motion_path as _sweep

from .motion_state import MotionState, readonly

NULL_FOUND = "the null motion {motion} moved the joints; the tool stood still"
"""What the null-motion playback says when it ends (a template of :mod:`app.core.refusals`)."""
NULL_AMPLITUDE = 1.2
"""How far the null motion swings each way [rad | m along the unit direction] (less near a limit)."""

__all__ = [
    "ROW_WORDS",
    "climbed_along",
    "null_motion_text",
    "null_motion_path",
    "NULL_FOUND",
    "is_null_motion",
]

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


def _coefficient(c: float, number: Callable[[float], str]) -> str:
    """c written before a joint rate: "" for 1, "−" for −1, else the number."""
    if abs(c - 1.0) < 1e-9:
        return ""
    if abs(c + 1.0) < 1e-9:
        return "−"
    return number(c).replace("-", "−") + " "


def _plain(c: float) -> str:
    return f"{c:.4g}"


def null_motion_text(direction: np.ndarray, number: Callable[[float], str] = _plain) -> str:
    """The null motion in the course's words: each moving joint's rate as a multiple of the largest
    one's (of equal ones the last), e.g. "q̇4 = −q̇6" (the Puma's wrist) or "q̇1 = −0.5 q̇2"; joints
    that do not move are left out. ``number`` writes a coefficient (4 significant digits, a point)."""
    d = np.asarray(direction, dtype=float)
    moving = [int(i) for i in np.flatnonzero(d)]
    if len(moving) < 2:
        return f"q̇{moving[0] + 1} ≠ 0" if moving else ""
    big = float(np.abs(d).max())
    ref = max(i for i in moving if abs(d[i]) >= big - 1e-9)
    parts = [f"q̇{i + 1} = {_coefficient(float(d[i] / d[ref]), number)}q̇{ref + 1}" for i in moving if i != ref]
    return ", ".join(parts)


def null_motion_path(
    q: np.ndarray, direction: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> np.ndarray:
    """One back-and-forth swing along ``direction`` from ``q``, its amplitude kept within the limits."""
    d = np.asarray(direction, dtype=float)
    room = NULL_AMPLITUDE
    for i in np.flatnonzero(d):
        room = min(room, float((upper[i] - q[i]) / abs(d[i])), float((q[i] - lower[i]) / abs(d[i])))
    return _sweep(q, d, max(room, 0.0), 30)


def is_null_motion(m: MotionState) -> bool:
    """Whether ``m`` plays the null motion (a path that says :data:`NULL_FOUND` when it ends)."""
    return m.kind == "path" and m.found.startswith(NULL_FOUND.split("{", 1)[0])
