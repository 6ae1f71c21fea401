"""The pure reducer: ``reduce(state, action) -> state``. No handles, no threads, no clock.

Every rule about what an input means lives here, once: values are finite
or refused with a message naming the input; a joint value is clamped to its
slider and snapped onto a named configuration's value when it comes within
reach; the configuration name follows q; a robot switch keeps the display
choices that do not depend on the robot; time moves the joints at q̇ and
stops, saying why, at the end of a slider.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any

import numpy as np

from kinematics import Robot
from kinematics.analytic_jacobian import representation_singularity
from kinematics.errors import ConfigurationError
from kinematics.singularity.null_motion import null_motion
from kinematics.text import words

from . import motion_rules
from .actions import (
    Action,
    ApplyPreset,
    ChooseToolPath,
    ClearWrench,
    DriveTool,
    EditRobot,
    FollowPath,
    FollowToolPath,
    GoTo,
    GoToRepresentationSingularity,
    IkSolutionsFound,
    Play,
    PlayNullMotion,
    ReplaceState,
    ResetMotion,
    SelectIkSolution,
    SelfMove,
    SetAcceleration,
    SetConfiguration,
    SetDesired,
    SetJoint,
    SetOption,
    SetRate,
    SetRobot,
    SetWrench,
    Step,
    StepOnce,
    StopRates,
    Wait,
)
from .build_table import edited_state
from .i18n import N_
from .motion_rules import FRAME_DT, MotionRefused
from .motion_state import readonly
from .options import OPTION
from .ranges import accel_ranges, joint_ranges, rate_ranges, snap_joint, twist_ranges, wrench_ranges
from .self_motion import NULL_FOUND, null_motion_path, null_motion_text
from .state import LabState, Options, default_options, frozen
from .tool_path import SHAPES, followed

__all__ = ["reduce", "InvalidAction", "named_configuration_at"]


class InvalidAction(ValueError):
    """An action the state cannot take (a NaN, an unknown option or configuration), with the reason."""


def _finite(value: object, what: str) -> float:
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise InvalidAction(f"{what} must be a number, got {str(value)[:40]!r}") from None
    if math.isnan(x):
        raise InvalidAction(f"{what} must be a finite number; the value given is not a number")
    if math.isinf(x):
        raise InvalidAction(f"{what} must be a finite number, got {'−' if x < 0 else ''}∞")
    return x


def _index(i: object, n: int, what: str) -> int:
    if not isinstance(i, (int, np.integer)) or isinstance(i, bool) or not 0 <= int(i) < n:
        raise InvalidAction(f"{what} index must be 0 to {n - 1}, got {i!r}")
    return int(i)


def _with(a: np.ndarray, i: int, x: float) -> np.ndarray:
    b = a.copy()
    b[i] = x
    return frozen(b)


def named_configuration_at(state: LabState, q: np.ndarray) -> str:
    """The name of the robot's named configuration (or "home") equal to ``q`` (within 1e-12), else ""."""
    names, table = _named_table(state.robot)
    hit = np.flatnonzero((np.abs(table - q) <= 1e-12).all(axis=1))
    return names[hit[0]] if hit.size else ""


@functools.lru_cache(maxsize=64)  # bounded: a table edited in the browser makes a robot per edit
def _named_table(robot: Robot) -> tuple[tuple[str, ...], np.ndarray]:
    """The robot's named configurations and then home, as names and one (k, n) array."""
    names = (*(c.name for c in robot.configurations), "home")
    return names, np.array([*(c.q for c in robot.configurations), robot.home], dtype=float)


def reduce(state: LabState, action: Action) -> LabState:
    """The state after ``action``.

    Raises:
        InvalidAction: the action cannot apply (the message names the input and the reason).
    """
    try:
        after = _reduce(state, action)
    except MotionRefused as exc:  # its words (a catalogs' sentence) kept for the tab's language
        raise InvalidAction(exc.args[0] if len(exc.args) == 1 else str(exc)) from None
    if not after.started and after is not state and not isinstance(action, (ReplaceState, Step)):
        after = after.replace(started=True)  # the first change: the first hint goes
    m = after.motion
    if m.anchor is not None and m.kind != "climb" and not isinstance(action, (SelfMove, Step)):
        if after.q is not state.q or after.robot is not state.robot:  # moved by hand: a new self-motion
            after = after.replace(
                motion=m.replace(s=0.0, anchor=None, self_trace=m.self_trace[:0], direction=None)
            )
    return after


def _reduce(state: LabState, action: Action) -> LabState:
    robot, n = state.robot, state.robot.dof
    match action:
        case SetJoint(index=i, value=value):
            i = _index(i, n, "joint")
            x = joint_ranges(robot)[i].clamp_si(_finite(value, f"joint {robot.joints[i].name}"))
            q = _with(state.q, i, snap_joint(robot, i, x, float(state.q[i])))
            return state.replace(q=q, configuration=named_configuration_at(state, q), stopped="")
        case SetConfiguration(q=values, name=name):
            if len(values) != n:
                raise InvalidAction(f"a configuration needs {n} joint values, got {len(values)}")
            q = np.array([_finite(v, "joint value") for v in values])
            return state.replace(q=frozen(q), configuration=name or named_configuration_at(state, q))
        case GoTo(name=name):
            if name == "home":
                q = robot.home
            else:
                names = [c.name for c in robot.configurations]
                if name not in names:
                    raise InvalidAction(f"{robot.name} has no configuration {name!r}; it has {names}")
                q = robot.configuration(name)
            return state.replace(q=frozen(q), configuration=name, playing=False, stopped="")
        case SetRate(index=i, value=value):
            i = _index(i, n, "joint rate")
            x = rate_ranges(robot)[i].clamp_si(_finite(value, f"rate of {robot.joints[i].name}"))
            return state.replace(qd=_with(state.qd, i, x))
        case SetAcceleration(index=i, value=value):
            i = _index(i, n, "joint acceleration")
            x = accel_ranges(robot)[i].clamp_si(_finite(value, f"acceleration of {robot.joints[i].name}"))
            return state.replace(qdd=_with(state.qdd, i, x))
        case StopRates():
            return state.replace(qd=frozen(np.zeros(n)), playing=False)
        case SetDesired(row=r, value=value):
            r = _index(r, 6, "twist row")
            x = twist_ranges(robot)[r].clamp_si(_finite(value, "desired tool velocity"))
            return state.replace(v_desired=_with(state.v_desired, r, x))
        case SetWrench(row=r, value=value):
            r = _index(r, 6, "wrench row")
            x = wrench_ranges(robot)[r].clamp_si(_finite(value, "applied force"))
            return state.replace(wrench=_with(state.wrench, r, x))
        case ClearWrench():
            return state.replace(wrench=frozen(np.zeros(6)))
        case SetOption(name=name, value=value):
            return state.replace(options=_option(state.options, name, value, n))
        case SetRobot(name=name, robot=new, chain=chain):
            return LabState.initial(name, new, default_options(new, state.options), chain)
        case EditRobot(name=name, robot=new, keep=keep):
            return edited_state(state, name, new, keep)
        case ReplaceState(state=other):
            return other
        case Play(playing=playing, kind=kind):
            return motion_rules.play(state, bool(playing), kind)
        case Step(dt=dt):
            return motion_rules.step(state, _finite(dt, "time step"))
        case StepOnce(kind=kind):
            if state.playing:
                return state
            if state.motion.kind != kind or state.motion.trace is None:
                started = motion_rules.play(state, True, kind)
                if not started.playing:
                    return started
                state = started.replace(playing=False)
            return motion_rules.step(state, FRAME_DT, force=True)
        case ResetMotion():
            return motion_rules.reset(state)
        case ApplyPreset(name=name, q=q, twist=twist, frame=frame, speed=speed):
            speed = min(max(_finite(speed, "preset speed"), OPTION["speed"].lo), OPTION["speed"].hi)
            after = motion_rules.apply_preset(state, name, q, twist, frame, speed)
            return after.replace(configuration=named_configuration_at(after, after.q))
        case GoToRepresentationSingularity(convention=convention):
            return _representation_singularity(state, convention)
        case DriveTool(T_base_target=values):
            return motion_rules.drive_tool(state, values)
        case SelfMove(s=s):
            return motion_rules.self_move(state, _finite(s, "self-motion"))
        case FollowPath(path=path, found=found):
            return motion_rules.follow_path(state, path, found)
        case FollowToolPath(shape=shape):
            if shape not in SHAPES:
                raise InvalidAction(f"shape must be one of {', '.join(SHAPES)}, got {str(shape)[:40]!r}")
            configurations, said = followed(state, shape)
            rows = tuple(tuple(float(x) for x in row) for row in configurations)
            return motion_rules.follow_path(state.replace(tool_path=shape), rows, said)
        case ChooseToolPath(shape=shape):
            if shape not in ("", *SHAPES):
                raise InvalidAction(
                    f"shape must be one of {', '.join(SHAPES)} or none, got {str(shape)[:40]!r}"
                )
            return state.replace(tool_path=shape)
        case IkSolutionsFound():
            return _ik_solutions(state, action)
        case SelectIkSolution(index=index):
            return _select_solution(state, index)
        case PlayNullMotion():
            return _null_motion(state)
        case Wait(note=note):
            return state.replace(playing=False, stopped=str(note))
    raise InvalidAction(f"{action!r} is not a state change (a command is carried out by the session)")


def _ik_solutions(state: LabState, found: IkSolutionsFound) -> LabState:
    """The IK solutions found away from the drawing thread, kept in the motion state (the arm does not
    move); dropped when the robot or the arm has moved since the search began (they belong to another
    pose)."""
    if found.robot != state.robot_name or tuple(found.q) != tuple(state.q):
        return state
    n = state.robot.dof
    refused = InvalidAction(f"IK solutions need a 4×4 pose and rows of {n} finite joint values")
    try:
        solutions = np.array(found.solutions, dtype=float).reshape(len(found.solutions), n)
        pose = np.array(found.pose, dtype=float).reshape(4, 4)
    except (TypeError, ValueError):
        raise refused from None
    if not (np.isfinite(pose).all() and np.isfinite(solutions).all()):
        raise refused
    return state.replace(motion=state.motion.replace(solutions=readonly(solutions), pose=readonly(pose)))


def _select_solution(state: LabState, index: object) -> LabState:
    """The arm at solution ``index`` of those found (checked against them)."""
    solutions = state.motion.solutions
    count = 0 if solutions is None else len(solutions)
    if solutions is None or not (
        isinstance(index, int) and not isinstance(index, bool) and 0 <= index < count
    ):
        raise InvalidAction(f"index must be an int 0…{count - 1} (one of the solutions found), got {index!r}")
    return state.replace(q=frozen(solutions[index]), configuration="", playing=False, stopped="")


def _null_motion(state: LabState) -> LabState:
    """Play the null joint motion of Ker J back and forth (refused where J has full rank)."""
    m = null_motion(state.robot, np.array(state.q))
    if m.dimension == 0:
        raise MotionRefused(words(N_("no null motion here: J has full rank (go to a singularity first)")))
    ranges = joint_ranges(state.robot)
    lo = np.array([r.clamp_si(-math.inf) for r in ranges])
    hi = np.array([r.clamp_si(math.inf) for r in ranges])
    path = null_motion_path(np.array(state.q), m.direction, lo, hi)
    if float(np.ptp(path, axis=0).max()) < 1e-6:
        raise MotionRefused(words(N_("no null motion here: it would leave a joint's range")))
    found = NULL_FOUND.format(motion=null_motion_text(m.direction))
    return motion_rules.follow_path(state, tuple(tuple(float(x) for x in row) for row in path), found)


def _representation_singularity(state: LabState, convention: object) -> LabState:
    if convention not in ("zyx", "zyz"):
        raise InvalidAction(f"the Euler convention must be 'zyx' or 'zyz', got {convention!r}")
    robot = state.robot
    if robot.dof < 6:
        raise InvalidAction(
            f"{robot.name} has {robot.dof} joints: it cannot turn its tool to any orientation"
        )
    ranges = joint_ranges(robot)
    lo = np.array([r.clamp_si(-math.inf) for r in ranges])
    hi = np.array([r.clamp_si(math.inf) for r in ranges])
    try:
        q = representation_singularity(robot, state.q, convention, lo, hi)
    except ConfigurationError as exc:
        raise InvalidAction(str(exc)) from None
    options = dataclasses.replace(state.options, representation=convention)
    return state.replace(
        q=frozen(q),
        configuration=named_configuration_at(state, q),
        playing=False,
        stopped="",
        options=options,
    )


def _option(options: Options, name: str, value: object, n: int) -> Options:
    """``options`` with ``name`` set to ``value``, checked against its row of :data:`OPTION`."""
    fields = {f.name for f in dataclasses.fields(Options)}
    if name not in fields or name not in OPTION:
        raise InvalidAction(f"unknown display option {name!r}; options are {sorted(fields)}")
    row = OPTION[name]
    if row.kind == "float":
        value = min(max(_finite(value, name), row.lo), row.hi)
    elif row.kind == "joint":
        value = _index(value, n, "map joint")
    elif row.kind == "step":  # the Derive tab's previous/next buttons: clamped, never refused
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool):
            raise InvalidAction(f"{name} is a joint index (an integer), got {value!r}")
        last = n if options.derive == "dh" else n - 1  # the DH walk ends with the tool frame's row
        value = min(max(int(value), 0), last)
    elif row.kind == "choice":
        if value not in row.choices:
            raise InvalidAction(f"{name} must be one of {row.choices}, got {value!r}")
    elif not isinstance(value, bool):
        raise InvalidAction(f"{name} is on or off (a bool), got {value!r}")
    changes: dict[str, Any] = {name: value}
    if name == "derive" and value != "dh" and options.derive_step > n - 1:
        changes["derive_step"] = n - 1  # off the DH walk's tool step: back on the last joint
    return dataclasses.replace(options, **changes)
