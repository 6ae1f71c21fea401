"""Named actions: everything a tab can ask for, as plain frozen values.

Views, the ticker (:class:`~app.ticker.Ticker`) and the hub
(:class:`~app.hub.Hub`) only ever *dispatch* one of these; the pure
:func:`app.reducer.reduce` turns (state, action) into the next state.
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
    "SetDesired",
    "SetWrench",
    "ClearWrench",
    "SetOption",
    "ChooseRobot",
    "ChooseChain",
    "SetRobot",
    "ReplaceState",
    "Play",
    "Step",
    "RequestDownload",
    "COMMANDS",
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
    """Set display option ``name`` (a field of :class:`~app.state.Options`) to ``value``."""

    name: str
    value: object


@dataclass(frozen=True)
class ChooseRobot:
    """The user picked robot ``name`` of the catalogue (the session loads it, then dispatches SetRobot)."""

    name: str


@dataclass(frozen=True)
class ChooseChain:
    """The user picked the chain of the current URDF that ends at ``tip_link`` (a command: the session
    loads that chain, then dispatches SetRobot)."""

    tip_link: str


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
    """Start (``True``) or stop moving the joints at q̇ in time."""

    playing: bool


@dataclass(frozen=True)
class Step:
    """Advance time by ``dt`` [s]: while playing, q ← q + q̇ dt (stopping at the slider ends)."""

    dt: float


@dataclass(frozen=True)
class RequestDownload:
    """Send J(q) exported as ``label`` ("LaTeX", "Python" or "JSON") to this tab (a command)."""

    label: str


COMMANDS = (ChooseRobot, ChooseChain, RequestDownload)
"""Actions the session carries out itself (loading a robot, preparing a file) instead of reducing."""

Action = (
    SetJoint
    | SetConfiguration
    | GoTo
    | SetRate
    | StopRates
    | SetDesired
    | SetWrench
    | ClearWrench
    | SetOption
    | ChooseRobot
    | ChooseChain
    | SetRobot
    | ReplaceState
    | Play
    | Step
    | RequestDownload
)
