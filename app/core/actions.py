"""Reducible actions: every change of a tab's state, as plain frozen values.

Views, the ticker (:class:`~app.tab.ticker.Ticker`) and the classroom
(:class:`~app.services.classroom.Classroom`) *dispatch* these, or one of the session's
commands (:mod:`app.core.commands`: load a robot, prepare a file, join the classroom); the pure
:func:`app.core.reducer.reduce` turns (state, action) into the next state. The two unions,
:data:`Action` here and :data:`app.core.commands.Command`, are told apart by type.
Values are in SI units with radians (the views convert from degrees).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from kinematics import Robot

    from .state import LabState

__all__ = [
    "Action",
    "SetJoint",
    "SetConfiguration",
    "GoTo",
    "SetRate",
    "StopRates",
    "SetAcceleration",
    "SetDesired",
    "SetWrench",
    "ClearWrench",
    "SetOption",
    "SetRobot",
    "ReplaceState",
    "Play",
    "Step",
    "StepOnce",
    "ResetMotion",
    "ApplyPreset",
    "DriveTool",
    "SelfMove",
    "FollowPath",
    "PlayNullMotion",
    "FollowToolPath",
    "ChooseToolPath",
    "IkSolutionsFound",
    "SelectIkSolution",
    "Wait",
    "GoToRepresentationSingularity",
    "EditRobot",
]


@dataclass(frozen=True)
class SetJoint:
    """Move joint ``index`` to ``value`` [rad | m] (clamped to its slider, snapped to named values)."""

    index: int
    value: float


@dataclass(frozen=True, eq=False)
class SetConfiguration:
    """Move every joint to ``q`` (n,) [rad | m]; ``name`` if it is a named configuration."""

    q: tuple[float, ...]
    name: str = ""


@dataclass(frozen=True)
class GoTo:
    """Move to the named configuration ``name`` ("home" or one of the robot's)."""

    name: str


@dataclass(frozen=True)
class SetRate:
    """Set joint rate q̇ᵢ [rad/s | m/s] of the forward view v = J q̇."""

    index: int
    value: float


@dataclass(frozen=True)
class StopRates:
    """Set every joint rate to zero (and stop moving)."""


@dataclass(frozen=True)
class SetAcceleration:
    """Set joint acceleration q̈ᵢ [rad/s² | m/s²] of the acceleration map ẍ = J q̈ + J̇ q̇."""

    index: int
    value: float


@dataclass(frozen=True)
class SetDesired:
    """Set component ``row`` (0..5, [vx vy vz ωx ωy ωz]) of the desired tool twist [m/s | rad/s]."""

    row: int
    value: float


@dataclass(frozen=True)
class SetWrench:
    """Set component ``row`` (0..5, [Fx Fy Fz Mx My Mz]) of the wrench at the tool [N | N·m]."""

    row: int
    value: float


@dataclass(frozen=True)
class ClearWrench:
    """Remove the applied force and moment."""


@dataclass(frozen=True)
class SetOption:
    """Set display option ``name`` (a field of :class:`~app.core.state.Options`) to ``value``."""

    name: str
    value: object


@dataclass(frozen=True, eq=False)
class SetRobot:
    """Switch to the loaded ``robot`` listed as ``name`` (at its home, display choices kept);
    ``chain``: the tip link of the URDF chain it is ("" for the default chain or a non-URDF robot)."""

    name: str
    robot: Robot
    chain: str = ""


@dataclass(frozen=True, eq=False)
class ReplaceState:
    """Take over a whole state (a presenter's, a recording's)."""

    state: LabState


@dataclass(frozen=True)
class Play:
    """Start (``True``) or pause the motion ``kind`` in time.

    ``kind`` (see :data:`app.core.motion_state.MOTIONS`): "joints" moves the joints at q̇, "resolved_rate"
    holds the desired tool twist (q̇ = J⁺ v), "climb" raises w with the tool held. Pausing ignores it.
    """

    playing: bool
    kind: str = "joints"


@dataclass(frozen=True)
class Step:
    """Advance time by ``dt`` [s]: while playing, q ← q + q̇ dt (stopping at the slider ends)."""

    dt: float


@dataclass(frozen=True)
class StepOnce:
    """One frame of the motion ``kind`` (while paused), for working through it step by step."""

    kind: str = "resolved_rate"


@dataclass(frozen=True)
class ResetMotion:
    """Stop and put the arm back where the motion started (its trace cleared)."""


@dataclass(frozen=True, eq=False)
class ApplyPreset:
    """Set up the resolved-rate preset ``name``: the arm at ``q``, the desired twist ``twist`` (6,)
    [m/s; rad/s] in ``frame`` axes, ready to Play at playback ``speed``."""

    name: str
    q: tuple[float, ...]
    twist: tuple[float, ...]
    frame: str = "base"
    speed: float = 1.0


@dataclass(frozen=True, eq=False)
class DriveTool:
    """The tool was dragged to ``T_base_target`` (16 numbers, a 4×4 row-major): solve IK from the
    current q (the option's method and mode) and move there."""

    T_base_target: tuple[float, ...]


@dataclass(frozen=True)
class SelfMove:
    """Move the self-motion parameter to ``s`` [rad | m]: the arm moves in the null space of J, the
    tool held where it was when the self-motion began."""

    s: float


@dataclass(frozen=True, eq=False)
class FollowPath:
    """Play back the configurations ``path`` (k, n) (e.g. the descent to the nearest singularity);
    ``found`` is said when it ends."""

    path: tuple[tuple[float, ...], ...]
    found: str


@dataclass(frozen=True)
class PlayNullMotion:
    """At a singularity, play the null joint motion (Ker J) back and forth: the joints move, the tool
    stands still."""


@dataclass(frozen=True)
class FollowToolPath:
    """Lay out a ``shape`` ("line" or "circle") through the tool point and follow it by the course's
    Jacobian method (Newton for q(t₀), then q̇ = J⁺ẏ(t)), played back."""

    shape: str


@dataclass(frozen=True)
class ChooseToolPath:
    """Choose the path y(t) ``shape`` ("line", "circle"; "" for none) of the path folder: it is drawn in
    the 3-D view from the tool point (where the tool would go), before it is followed."""

    shape: str


@dataclass(frozen=True, eq=False)
class IkSolutionsFound:
    """The several IK solutions (elbow up / down, wrist flip …) of the pose ``pose`` (16 numbers, the
    4×4 ⁰T_tool row by row) that robot ``robot`` reaches at ``q``, found away from the drawing thread
    (:class:`~app.core.commands.FindIkSolutions`): the reducer only keeps them, and drops them when the
    arm has moved since ``q``."""

    robot: str
    q: tuple[float, ...]
    pose: tuple[float, ...]
    solutions: tuple[tuple[float, ...], ...]


@dataclass(frozen=True)
class SelectIkSolution:
    """Move the arm to IK solution ``index`` (0-based) of those found."""

    index: int


@dataclass(frozen=True)
class Wait:
    """Stop any motion and say ``note`` while the tab waits for a command's result (the nearest
    singularity being looked for away from the drawing thread)."""

    note: str


@dataclass(frozen=True)
class GoToRepresentationSingularity:
    """Move the arm (inverse kinematics from q, tool position kept) to where the Euler angles of
    ``convention`` are singular: ZYX pitch = ±90°, ZYZ θ = 0 or 180°."""

    convention: str


@dataclass(frozen=True, eq=False)
class EditRobot:
    """The Build tab's DH table became ``robot`` (listed as ``name``): show it, keeping the display
    choices; ``keep[i]`` is the joint of the robot shown whose value row ``i`` keeps (``None``: a new
    row, at home). See :func:`app.core.build_table.edited_state`."""

    name: str
    robot: Robot
    keep: tuple[int | None, ...] = ()


Action = (
    SetJoint
    | SetConfiguration
    | GoTo
    | SetRate
    | StopRates
    | SetAcceleration
    | SetDesired
    | SetWrench
    | ClearWrench
    | SetOption
    | SetRobot
    | ReplaceState
    | Play
    | Step
    | StepOnce
    | ResetMotion
    | ApplyPreset
    | DriveTool
    | SelfMove
    | FollowPath
    | PlayNullMotion
    | FollowToolPath
    | ChooseToolPath
    | IkSolutionsFound
    | SelectIkSolution
    | Wait
    | GoToRepresentationSingularity
    | EditRobot
)
"""Everything :func:`app.core.reducer.reduce` takes (a union, told apart by type)."""
