"""The course's Jacobian IK along a path y(t) (004), as a motion the Motion tab plays.

From the tool point where the arm stands, a line or a circle is laid out (:func:`laid_out`); Newton finds
q(t₀) on it and q̇ = J⁺ ẏ(t) (J⁻¹ ẏ for a square J; plus (I − J⁺J) ω for a redundant arm, here ω = 0) is
integrated over it (:func:`kinematics.motion.path.follow`). The configurations are played back one per
frame, so the rates chart shows q̇(t); what the error ‖y(t) − k(q(t))‖ reached is said when it ends. Near
a singularity q̇ blows up and the error grows: the method fails there, and the words say so.
"""

from __future__ import annotations

import numpy as np

from kinematics import fk
from kinematics.motion.path import ToolPath, circle, follow, line

from .motion_state import MotionState, readonly
from .ranges import reach
from .state import LabState

__all__ = [
    "SHAPES",
    "SECONDS",
    "HELD",
    "LOST",
    "FOLLOWED",
    "LEFT",
    "SAMPLES",
    "laid_out",
    "followed",
    "is_tool_path",
    "planned",
]

SHAPES = ("line", "circle")
"""The paths the Motion tab offers."""
SECONDS = 4.0
"""t_k − t₀ [s]: played back at one configuration per frame (30 per second)."""
SIZE = 0.15
"""Half the line's length and the circle's radius [m] (less for a small arm: a fifth of its reach)."""
SAMPLES = 121
"""Points of y(t) drawn for the chosen path (t₀ … t_k evenly, both ends included)."""
HELD = 1e-4
"""Largest error [m] still said to be held; beyond it the path was lost."""
LOST = 0.02
"""Error [m] at which the playback stops: the path is lost (the rates beyond mean nothing)."""
FOLLOWED = {
    "line": "the tool followed the line: q̇ = J⁺ẏ(t) held the error below {error} m",
    "circle": "the tool followed the circle: q̇ = J⁺ẏ(t) held the error below {error} m",
}
LEFT = {
    "line": (
        "the tool left the line near a singularity: the error reached {error} m, a joint rate {rate} rad/s"
    ),
    "circle": (
        "the tool left the circle near a singularity: the error reached {error} m, a joint rate {rate} rad/s"
    ),
}


def laid_out(state: LabState, shape: str) -> ToolPath:
    """The ``shape`` from the tool point: a line along the base y axis (across an arm stretched along x),
    or a circle in the base's x-y plane (a planar arm) or y-z plane; both start at the tool point."""
    p = fk(state.robot, np.array(state.q))[:3, 3]
    size = min(SIZE, 0.2 * reach(state.robot))
    if shape == "line":
        e = np.array([0.0, 1.0, 0.0])
        return line(p, p + 2.0 * size * e, SECONDS)
    normal = np.array([0.0, 0.0, 1.0]) if state.robot.planar else np.array([1.0, 0.0, 0.0])
    path = circle(p, size, normal, SECONDS)
    start = path.point(0.0)
    return circle(p - (start - p), size, normal, SECONDS)  # shifted so that it starts at the tool point


def followed(state: LabState, shape: str) -> tuple[np.ndarray, str]:
    """The configurations (k, n) of the course's method along ``shape`` (up to where the path is lost)
    and what it did, in English (one of :data:`FOLLOWED`, :data:`LEFT`)."""
    path = laid_out(state, shape)
    f = follow(state.robot, path, np.array(state.q), steps=int(round(SECONDS * 30)))
    ok = np.isfinite(f.error) & np.isfinite(f.q).all(axis=1)
    lost = np.flatnonzero(~ok | (f.error > LOST))
    end = int(lost[0]) + 1 if len(lost) else len(f.t)
    end = end if ok[:end].all() else end - 1
    error = float(f.error[:end].max())
    if error <= HELD:
        return readonly(f.q[:end]), FOLLOWED[shape].format(error=f"{max(error, 1e-12):.1e}")
    rate = float(np.abs(f.qd[:end]).max())
    return readonly(f.q[:end]), LEFT[shape].format(error=f"{error:.2g}", rate=f"{rate:.3g}")


def is_tool_path(m: MotionState) -> bool:
    """Whether ``m`` plays a path of :func:`followed` (it says one of :data:`FOLLOWED`, :data:`LEFT`)."""
    return m.kind == "path" and m.found.startswith("the tool ")


def followed_shape(m: MotionState) -> str:
    """The shape ``m`` plays (a path of :func:`followed`), else ""."""
    if m.kind != "path":
        return ""
    return next(
        (s for s in SHAPES if m.found.startswith((f"the tool followed the {s}", f"the tool left the {s}"))),
        "",
    )


def planned(state: LabState) -> np.ndarray | None:
    """y(t) of the chosen path (``state.tool_path``) at :data:`SAMPLES` evenly spaced times (SAMPLES, 3) [m]:
    laid out from where its playback started while the arm is on that playback (the path being or just
    followed stays put), else from the tool point (where the tool will go when it is followed from here);
    ``None`` when no path is chosen."""
    shape = state.tool_path
    if shape not in SHAPES:
        return None
    m = state.motion
    at = state
    if followed_shape(m) == shape and m.start is not None and m.path is not None and len(m.path):
        if np.array_equal(np.asarray(state.q), m.path[min(m.index, len(m.path) - 1)]):
            at = state.replace(q=m.start)
    path = laid_out(at, shape)
    return np.array([path.point(float(t)) for t in np.linspace(0.0, path.duration, SAMPLES)])
