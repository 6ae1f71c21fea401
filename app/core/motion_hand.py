"""The motions a student makes by hand: dragging the tool's target (inverse kinematics) and the
self-motion slider (the null space of a redundant arm, the tool held).

Pure functions of (state, action), called by :func:`app.core.reducer.reduce` through
:mod:`app.core.motion_rules`.
"""

from __future__ import annotations

import math

import numpy as np

from kinematics import Robot, jacobian
from kinematics.analysis import manipulability, task_rows
from kinematics.errors import JacobianLabError
from kinematics.motion import ik, redundancy
from kinematics.numeric import fk
from kinematics.text import words

from .i18n import N_
from .motion_state import IkInfo, MotionRefused, readonly, slider_bounds
from .state import LabState, frozen

__all__ = [
    "drive_tool",
    "self_move",
    "redundancy_rows",
    "IK_DAMPING",
    "IK_ITERATIONS",
    "IK_STEP",
    "SELF_STEP",
]

IK_DAMPING = 0.02
"""λ of "drive the tool" by damped least squares [m] (the View option's λ when larger)."""
IK_ITERATIONS = 25
"""Iterations per drag event: warm-started from the last q, a few suffice away from singularities."""
IK_STEP = 0.25
"""Largest joint step of one IK iteration [rad | m]: a far target pulls the arm, never flings it."""
SELF_STEP = 0.02
"""Largest self-motion step [rad | m along the null space]; larger moves are split."""


def redundancy_rows(robot: Robot) -> tuple[int, ...] | None:
    """The task rows self-motion and the climb hold: the robot's task rows when it has more joints
    than rows (the Panda, the iiwa), else its position rows when that leaves exactly one spare joint
    (the 3R planar arm holding only its tool point); ``None`` when neither."""
    rows = task_rows(robot)
    if robot.dof > len(rows):
        return rows
    linear = tuple(r for r in rows if r < 3)
    return linear if linear != rows and robot.dof - len(linear) == 1 else None


def drive_tool(state: LabState, values: tuple[float, ...]) -> LabState:
    """Solve IK towards the dragged target from the current q and move there (clamped to the sliders)."""
    robot = state.robot
    T = np.array(values, dtype=float)
    if T.shape != (16,) or not np.isfinite(T).all():
        raise MotionRefused(words(N_("the dragged target must be 16 finite numbers (a 4×4 pose)")))
    T = T.reshape(4, 4)
    rows = task_rows(robot)
    o = state.options
    pose = o.ik_mode == "pose" and any(r >= 3 for r in rows)
    target = T if pose else T[:3, 3]
    damping = max(o.damping, IK_DAMPING) if o.ik_method == "dls" else 0.0
    try:
        result = ik.solve(
            robot,
            target,
            state.q,
            method=o.ik_method,
            damping=damping,
            max_iterations=IK_ITERATIONS,
            step_limit=IK_STEP,
        )
    except JacobianLabError as exc:
        raise MotionRefused(str(exc)) from None
    if result.iterations == 0 and result.converged and state.motion.ik is not None:
        # The handle's release repeats the last pose, already reached: the readout keeps the solve
        # that got there (else every drag would end on "0 iterations").
        return state
    lo, hi = slider_bounds(state.robot)
    q = np.clip(np.array(result.q, dtype=float), lo, hi)
    reached = fk(robot, q)[:3, 3]
    linear = [r for r in rows if r < 3]
    departure = float(np.linalg.norm((T[:3, 3] - reached)[linear]))
    info = IkInfo(
        method=o.ik_method,
        iterations=int(result.iterations),
        converged=bool(result.converged),
        residual=float(np.linalg.norm(result.residual)),
        departure=departure,
        target=(float(T[0, 3]), float(T[1, 3]), float(T[2, 3])),
    )
    return state.replace(q=frozen(q), configuration="", playing=False, motion=state.motion.replace(ik=info))


def self_move(state: LabState, s: float) -> LabState:
    """Move along the null space to parameter ``s``, the tool held at the anchor (set on the first move)."""
    robot = state.robot
    rows = redundancy_rows(robot)
    if rows is None:
        raise MotionRefused(
            words(N_("{robot} has no self-motion: no joint to spare on its task"), robot=robot.name)
        )
    m = state.motion
    ds = s - m.s
    if ds == 0.0:
        return state
    steps = max(1, math.ceil(abs(ds) / SELF_STEP))
    anchor = m.anchor if m.anchor is not None else readonly(fk(robot, state.q))
    q, direction = np.array(state.q), m.direction
    for _ in range(steps):
        q, d = redundancy.self_motion_step(
            robot, q, step=ds / steps, rows=rows, direction=direction, hold=anchor
        )
        direction = d  # the positive direction of s, kept from step to step
    lo, hi = slider_bounds(state.robot)
    if ((q < lo) | (q > hi)).any():
        bad = ", ".join(robot.joints[i].name for i in np.flatnonzero((q < lo) | (q > hi)))
        return state.replace(stopped=f"self-motion stops here: {bad} would leave its range")
    w = float(manipulability(jacobian(robot, q), rows))
    st = m.self_trace
    if len(st) == 0:
        st = np.array([[m.s, float(manipulability(jacobian(robot, state.q), rows))]])
    trace = readonly(np.vstack([st, [[s, w]]])[-600:])
    motion_state = m.replace(s=float(s), anchor=anchor, self_trace=trace, direction=readonly(direction))
    return state.replace(q=frozen(q), configuration="", stopped="", motion=motion_state)
