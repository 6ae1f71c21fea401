"""The reducer's motion rules: Play, one step in time, presets, dragging the tool, self-motion.

Pure functions of (state, action), called by :func:`app.core.reducer.reduce`. The maths is
:mod:`kinematics` (``motion``, ``ik``, ``redundancy``); here only what a tab sees: when a motion
starts and stops and why, what it traced, where Reset goes back to.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from kinematics import jacobian
from kinematics.analysis import condition_number, manipulability, singular_values, task_rows
from kinematics.conventions import FRAMES
from kinematics.motion import redundancy
from kinematics.numeric import fk
from kinematics.text import words

from . import pacing
from .i18n import N_
from .motion_hand import (
    IK_DAMPING,
    IK_ITERATIONS,
    IK_STEP,
    SELF_STEP,
    drive_tool,
    redundancy_rows,
    self_move,
)
from .motion_state import MOTIONS, MotionRefused, MotionState, Trace, readonly, slider_bounds
from .ranges import twist_ranges
from .self_motion import ROW_WORDS, climbed_along
from .state import LabState, frozen

__all__ = [
    "play",
    "step",
    "reset",
    "apply_preset",
    "drive_tool",
    "self_move",
    "follow_path",
    "redundancy_rows",
    "resample",
    "FRAME_DT",
    "IK_DAMPING",
    "IK_ITERATIONS",
    "IK_STEP",
    "SELF_STEP",
    "MotionRefused",
]

FRAME_DT = 1.0 / 30.0
"""One frame of a motion [s] (the Step button's step, the ticker's period)."""
CLIMB_GAIN = 1.0
"""Gain of the manipulability climb q̇ = k (I − J⁺J) ∇w."""
CLIMB_STEP = 0.02
"""Largest climb step per frame [rad | m]: slow enough to watch."""


def _bounds(state: LabState) -> tuple[np.ndarray, np.ndarray]:
    return slider_bounds(state.robot)


RATE_BOUND = 4.0 * math.pi
"""A resolved-rate motion stops when a joint would need more than this [rad/s | m/s]: two turns a
second, four times the rate sliders' full scale, so the blow-up near a singularity is seen first."""


def sample(
    state: LabState,
    q: np.ndarray,
    qd: np.ndarray,
    trace: Trace | None,
    t: float,
    rows: tuple[int, ...] | None = None,
) -> Trace:
    """``trace`` with the measures at ``q`` appended (of ``rows`` of J, default the task rows)."""
    robot = state.robot
    rows = rows if rows is not None else task_rows(robot)
    J = jacobian(robot, q)
    sigma = singular_values(J, rows)
    kappa = float(condition_number(J, rows))
    w = float(manipulability(J, rows))
    base = trace if trace is not None else Trace.empty(robot.dof)
    tool = fk(robot, q)[:3, 3]
    return base.append(t, float(sigma[-1]) if sigma.size else 0.0, kappa, w, qd, tool)


def play(state: LabState, playing: bool, kind: str) -> LabState:
    """Start or pause the motion ``kind``."""
    if not playing:
        return state.replace(playing=False)
    if kind not in MOTIONS or kind == "path":
        raise MotionRefused(
            words(
                N_("unknown motion {kind}; the motions are {motions}"),
                kind=repr(kind),
                motions=", ".join(MOTIONS[:3]),
            )
        )
    if kind == "joints" and not np.any(state.qd):
        return state.replace(playing=False, stopped="set a joint rate q̇ first")
    if kind == "resolved_rate" and not np.any(state.v_desired[list(task_rows(state.robot))]):
        return state.replace(playing=False, stopped="set a tool velocity v first (or choose a preset)")
    if kind == "climb" and redundancy_rows(state.robot) is None:
        return state.replace(playing=False, stopped=f"{state.robot.name} has no redundancy to climb with")
    m = state.motion
    fresh = m.kind != kind or m.trace is None or m.start is None
    if fresh:
        m = MotionState(
            kind=kind,
            start=readonly(state.q),
            preset=m.preset if kind == "resolved_rate" else "",
            trace=sample(
                state,
                np.array(state.q),
                np.zeros(state.robot.dof),
                None,
                0.0,
                redundancy_rows(state.robot) if kind == "climb" else None,
            ),
            anchor=readonly(fk(state.robot, state.q)) if kind == "climb" else None,
        )
    return state.replace(playing=True, stopped="", motion=m, time=0.0 if fresh else state.time)


def step(state: LabState, dt: float, force: bool = False) -> LabState:
    """Advance the running motion by ``dt`` [s] of real time (times the speed option).

    ``force``: one step even while paused (the Step button).
    """
    if (not state.playing and not force) or dt <= 0.0:
        return state
    kind = state.motion.kind
    if kind == "resolved_rate":
        return _resolved_rate(state, dt)
    dt = dt * state.options.speed
    if kind == "joints":
        return _joints(state, dt)
    if kind == "climb":
        return _climb(state)
    return _path(state)


def _stop(state: LabState, why: str, **changes: object) -> LabState:
    return state.replace(playing=False, stopped=why, **changes)


def _moved(
    state: LabState,
    q: np.ndarray,
    t: float,
    trace: Callable[[np.ndarray], Trace | None],
    touching: bool = False,
) -> tuple[LabState, bool]:
    """The state with q (clamped to the sliders) at time t and ``trace(q)``; stopped, naming the joints,
    when q passed a slider end (``touching``: or reached it). Returns it and whether it stopped."""
    lo, hi = _bounds(state)
    hit = np.flatnonzero((q <= lo) | (q >= hi) if touching else (q < lo) | (q > hi))
    q = np.clip(q, lo, hi)
    changes: dict[str, object] = {
        "q": frozen(q),
        "time": t,
        "configuration": "",
        "motion": state.motion.replace(trace=trace(q)),
    }
    if hit.size:
        names = ", ".join(state.robot.joints[i].name for i in hit)
        changes.update(playing=False, stopped=f"stopped: {names} reached the end of its range")
    return state.replace(**changes), bool(hit.size)


def _joints(state: LabState, dt: float) -> LabState:
    """q ← q + q̇ dt, stopping at a slider end (saying which joint stopped)."""
    m, qd = state.motion, np.array(state.qd)
    t = state.time + dt

    def trace(q: np.ndarray) -> Trace | None:
        return sample(state, q, qd, m.trace, t) if m.kind == "joints" else m.trace

    return _moved(state, np.array(state.q) + qd * dt, t, trace, touching=True)[0]


def _resolved_rate(state: LabState, clock_dt: float) -> LabState:
    """One step of q_{k+1} = q_k + Δt J⁺ v, paced (:mod:`app.core.pacing`: slower near a singularity);
    stops at a slider end, when a rate passes its bound, or AT a joint limit (the step's part up to it:
    a critical point, which the status then names)."""
    o = state.options
    q_next, qd, stop, dt = pacing.paced_step(
        state.robot,
        np.array(state.q),
        np.array(state.v_desired),
        clock_dt=clock_dt,
        speed=o.speed,
        frame=o.twist_frame,
        damping=o.damping,
        rate_limit=RATE_BOUND,
        rows=task_rows(state.robot),
    )
    m = state.motion.replace(pace=dt / (clock_dt * o.speed) if o.speed > 0 else 1.0)
    t = state.time + dt
    if stop is not None and stop.share > 0.0:  # the step up to the joint limit: the motion ends AT it
        rates = np.asarray(qd, float)
        moved = _moved(state.replace(motion=m), q_next, t, lambda q: sample(state, q, rates, m.trace, t))[0]
        return _stop(moved, f"stopped: {stop.message}")
    if stop is not None:
        trace = sample(state, np.array(state.q), np.asarray(qd, float), m.trace, t)
        return _stop(state, f"stopped: {stop.message}", motion=m.replace(trace=trace))
    rates = np.asarray(qd, float)
    return _moved(state.replace(motion=m), q_next, t, lambda q: sample(state, q, rates, m.trace, t))[0]


def _climb(state: LabState) -> LabState:
    """One step of the manipulability climb with the tool held; stops at a maximum of w."""
    m = state.motion
    rows = redundancy_rows(state.robot)
    if rows is None:
        return _stop(state, f"{state.robot.name} has no redundancy to climb with")
    anchor = m.anchor if m.anchor is not None else fk(state.robot, state.q)
    q_next, w1 = redundancy.climb_step(
        state.robot, state.q, gain=CLIMB_GAIN, max_step=CLIMB_STEP, rows=rows, hold=anchor
    )
    w0 = float(m.trace.w[-1]) if m.trace is not None and len(m.trace) else 0.0
    t = state.time + FRAME_DT
    q0 = np.array(state.q)
    moved, stopped = _moved(
        state, q_next, t, lambda q: sample(state, q, (q - q0) / FRAME_DT, m.trace, t, rows)
    )
    w_start = float(manipulability(jacobian(state.robot, q0), rows))
    moved = moved.replace(motion=climbed_along(moved.motion, q0, np.array(moved.q), w_start, w1))
    if not stopped and w1 - w0 <= 1e-6 * max(w0, 1e-12):
        held = ", ".join(ROW_WORDS[r] for r in rows)
        return moved.replace(
            playing=False,
            stopped=f"w of the held rows ({held}) reached a maximum with the tool held: w = {w1:.4g}",
        )
    return moved


def _path(state: LabState) -> LabState:
    m = state.motion
    path = m.path
    if path is None or m.index + 1 >= len(path):
        return _stop(state, m.found)
    index = m.index + 1
    q = np.array(path[index])
    t = state.time + FRAME_DT
    qd = (q - np.array(state.q)) / FRAME_DT
    m = m.replace(index=index, trace=sample(state, q, qd, m.trace, t))
    s = state.replace(q=frozen(q), time=t, configuration="", motion=m)
    if index + 1 >= len(path):
        return s.replace(playing=False, stopped=m.found)
    return s


def reset(state: LabState) -> LabState:
    """Stop; the arm back where the motion started; the trace cleared (the preset kept)."""
    m = state.motion
    q = m.start if m.start is not None else state.q
    kind = m.kind if m.kind != "path" else "joints"
    return state.replace(
        q=frozen(q), playing=False, stopped="", time=0.0, motion=MotionState(kind=kind, preset=m.preset)
    )


def apply_preset(
    state: LabState, name: str, q: tuple[float, ...], twist: tuple[float, ...], frame: str, speed: float
) -> LabState:
    """The arm at the preset's start, its twist desired, ready to Play (resolved rate)."""
    robot = state.robot
    if len(q) != robot.dof or len(twist) != 6 or frame not in FRAMES:
        raise MotionRefused(
            words(N_("preset {name} does not fit {robot}"), name=repr(name), robot=robot.name)
        )
    lo, hi = _bounds(state)
    qa = np.clip(np.array(q, dtype=float), lo, hi)
    ranges = twist_ranges(robot)
    v = np.array([r.clamp_si(float(x)) for r, x in zip(ranges, twist, strict=True)])
    if not (np.isfinite(qa).all() and np.isfinite(v).all()):
        raise MotionRefused(
            words(N_("preset {name} holds a value that is not a finite number"), name=repr(name))
        )
    options = dataclasses.replace(
        state.options, twist_frame="tool" if frame == "tool" else "base", speed=speed
    )
    fresh = state.replace(q=frozen(qa), v_desired=frozen(v), options=options)
    m = MotionState(
        kind="resolved_rate",
        start=readonly(qa),
        preset=name,
        trace=sample(fresh, qa, np.zeros(robot.dof), None, 0.0),
    )
    return fresh.replace(playing=False, stopped="", time=0.0, configuration="", motion=m)


def resample(path: np.ndarray, count: int, eased: bool = False) -> np.ndarray | None:
    """``path`` (k, n) as ``count`` configurations evenly spaced in joint-space length (``eased``: slow
    start and slow arrival), for playing it back at a steady pace; ``None`` when it has no length."""
    path = np.asarray(path, dtype=float)
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    if along[-1] <= 0.0:
        return None
    u = np.linspace(0.0, 1.0, count)
    s = (0.5 - 0.5 * np.cos(np.pi * u) if eased else u) * along[-1]
    return np.column_stack([np.interp(s, along, path[:, j]) for j in range(path.shape[1])])


def follow_path(state: LabState, path: tuple[tuple[float, ...], ...], found: str) -> LabState:
    """Start playing back ``path`` (k, n) from its first configuration."""
    P = np.array(path, dtype=float)
    if P.ndim != 2 or P.shape[1] != state.robot.dof or len(P) == 0 or not np.isfinite(P).all():
        raise MotionRefused(
            words(N_("a path needs rows of {count} finite joint values"), count=state.robot.dof)
        )
    m = MotionState(
        kind="path",
        start=readonly(state.q),
        path=readonly(P),
        found=found,
        trace=sample(state, P[0], np.zeros(state.robot.dof), None, 0.0),
    )
    return state.replace(q=frozen(P[0]), playing=True, stopped="", time=0.0, configuration="", motion=m)
