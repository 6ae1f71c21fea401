"""The state of one browser tab: a frozen value, changed only by :func:`app.core.reducer.reduce`.

:class:`LabState` is everything a tab has chosen (robot, joint values,
joint rates, desired tool twist, applied wrench, display options, whether
the joints are moving in time). It is immutable: its arrays are read-only
and a new state is made with :func:`dataclasses.replace` (the reducer does
it), so a presenter can hand the same state to sixty tabs, a recorder can
keep every state, and a test can build one without a browser.

Units are SI with radians, like :mod:`kinematics`; degrees exist only on
the sliders.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from kinematics import Robot
from kinematics.analysis import task_rows

from .motion_state import MotionState
from .options import Frame, Options

__all__ = ["Options", "LabState", "Frame", "frozen", "default_options"]


def frozen(values: object, length: int | None = None) -> np.ndarray:
    """A read-only float copy of ``values`` (shape (length,) when given)."""
    a = np.array(values, dtype=float)
    if length is not None and a.shape != (length,):
        raise ValueError(f"expected {length} values, got shape {a.shape}")
    a.flags.writeable = False
    return a


def default_options(robot: Robot, keep: Options | None = None) -> Options:
    """Options for ``robot``: glyphs that fit its task (rotational ones for an orientation task).

    ``keep``: options whose non-glyph choices (scale, frame, damping, frames, labels) are kept.
    """
    base = keep if keep is not None else Options()
    angular_task = set(task_rows(robot)) <= {3, 4, 5}
    return dataclasses.replace(
        base,
        columns=not angular_task,
        angular_columns=angular_task,
        velocity_ellipsoid=not angular_task,
        rotational_ellipsoid=angular_task,
        force_ellipsoid=False,
        workspace=False,
        # q1 of most arms turns everything about the base axis and leaves w unchanged: map q2, q3.
        map_i=1 if robot.dof >= 3 else 0,
        map_j=2 if robot.dof >= 3 else min(1, robot.dof - 1),
        derive_step=0,  # a new robot's walk starts at its joint 1, not at the last robot's step
    )


@dataclass(frozen=True, eq=False)
class LabState:
    """Everything one tab has chosen.

    Attributes:
        robot_name: Catalogue name of the robot (library name or file).
        robot: The immutable robot model.
        q: Joint values (n,) [rad | m], read-only.
        qd: Joint rates of the forward view v = J q̇ (n,) [rad/s | m/s], read-only.
        qdd: Joint accelerations q̈ (n,) [rad/s² | m/s²] of the acceleration map ẍ = J q̈ + J̇ q̇,
            read-only (given empty, as by an older presenter's state: zeros). Play does not
            integrate them: they are the instant's accelerations, as q̇ is the instant's rates.
        v_desired: Desired tool twist (6,) [m/s; rad/s], base axes, rows [v; ω];
            only the robot's task rows are used. Read-only.
        wrench: Force and moment applied at the tool point (6,) [N; N·m], base axes. Read-only.
        options: Display options.
        configuration: Name of the named configuration the arm is at ("" when none).
        playing: The joints move at q̇ in time (a ticker dispatches :class:`~app.core.actions.Step`).
        time: Time moved so far [s].
        stopped: Why the last motion stopped ("" when it did not), shown to the user.
        chain: Tip link of the URDF chain shown ("" for the default chain or a non-URDF robot).
        motion: What Play runs, where it started, what it traced
            (:class:`~app.core.motion_state.MotionState`).
        started: The tab has changed something since it opened (the first hint, "what to do first",
            is gone for good).
        tool_path: The path y(t) chosen in the Motion tab's path folder ("line", "circle"; "" none):
            drawn in the 3-D view before and while it is followed; a new robot has none.
    """

    robot_name: str
    robot: Robot
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray = field(default_factory=lambda: frozen(np.zeros(0)))
    v_desired: np.ndarray = field(default_factory=lambda: frozen(np.zeros(6)))
    wrench: np.ndarray = field(default_factory=lambda: frozen(np.zeros(6)))
    options: Options = field(default_factory=Options)
    configuration: str = ""
    playing: bool = False
    time: float = 0.0
    stopped: str = ""
    chain: str = ""
    motion: MotionState = field(default_factory=MotionState)
    started: bool = False
    tool_path: str = ""

    def __post_init__(self) -> None:
        n = self.robot.dof
        if np.size(self.qdd) == 0:
            object.__setattr__(self, "qdd", frozen(np.zeros(n)))
        for name, length in (("q", n), ("qd", n), ("qdd", n), ("v_desired", 6), ("wrench", 6)):
            value = getattr(self, name)
            if not (isinstance(value, np.ndarray) and not value.flags.writeable and value.shape == (length,)):
                object.__setattr__(self, name, frozen(value, length))
            if not np.isfinite(getattr(self, name)).all():
                raise ValueError(f"LabState.{name} must be finite")

    @classmethod
    def initial(
        cls, robot_name: str, robot: Robot, options: Options | None = None, chain: str = ""
    ) -> LabState:
        """A fresh state for ``robot`` at its home configuration, at rest, no force."""
        home = next((c.name for c in robot.configurations if c.name == "home"), "")
        return cls(
            robot_name=robot_name,
            robot=robot,
            q=frozen(robot.home),
            qd=frozen(np.zeros(robot.dof)),
            options=default_options(robot, options),
            configuration=home,
            chain=chain,
        )

    def replace(self, **changes: object) -> LabState:
        """A new state with ``changes`` (arrays are copied read-only)."""
        return dataclasses.replace(self, **changes)  # type: ignore[arg-type]
