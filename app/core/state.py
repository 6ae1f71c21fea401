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
from typing import Literal

import numpy as np

from kinematics import Robot
from kinematics.analysis import task_rows

from .motion_state import MotionState

__all__ = ["Options", "LabState", "Frame", "frozen", "default_options"]

Frame = Literal["base", "tool"]


def frozen(values: object, length: int | None = None) -> np.ndarray:
    """A read-only float copy of ``values`` (shape (length,) when given)."""
    a = np.array(values, dtype=float)
    if length is not None and a.shape != (length,):
        raise ValueError(f"expected {length} values, got shape {a.shape}")
    a.flags.writeable = False
    return a


@dataclass(frozen=True)
class Options:
    """What the tab chose to see.

    Attributes:
        frames: Draw a triad at every DH/link frame and at the tool.
        labels: Name the joint axes in the 3-D view.
        columns: Draw the linear parts of J's columns as arrows from the tool point.
        angular_columns: Draw the angular parts of J's columns on the joint axes.
        velocity_ellipsoid: Draw the translational manipulability ellipsoid.
        rotational_ellipsoid: Draw the rotational (angular velocity) ellipsoid.
        force_ellipsoid: Draw the translational force ellipsoid (semi-axes 1/σ).
        scale: Multiplier on the automatic arrow and ellipsoid size.
        jacobian_frame: Frame of the Jacobian shown in the panel ("base" or "tool").
        damping: λ of damped least squares for q̇ = J⁺ v (0: the pseudo-inverse) [same units as J].
        twist_frame: Axes of the desired tool twist v ("base", or "tool": held in the moving tool axes).
        speed: Playback speed of every motion (1: real time; 0.1: ten times slower).
        gizmo: Show the drag handle at the tool ("drive the tool": IK every frame).
        ik_method: "dls" (damped least squares) or "newton" (the course's J⁻¹, J⁺ when not square).
        ik_mode: "position" (the tool point follows the handle) or "pose" (the whole tool frame).
        workspace: Show the workspace cloud (tool points of random configurations coloured by w).
        joint_map: Compute and show the map of w over two joints.
        map_i, map_j: The two joints of the map (indices).
        derive: The course derivation the Derive tab walks through ("" none, "dh", "whitney",
            "differentiation", "propagation", "force"; see :mod:`app.core.snapshot.derive`).
        derive_step: Its step: joint i (0-based), row i + 1 of the DH table.
        representation: What the J(q) tab shows: "geometric" J, or the analytic J_A with
            roll-pitch-yaw ("zyx") or Euler ZYZ ("zyz") angles.
        jdot_arrow: Draw J̇ q̇ (the tool's acceleration when the joints turn at constant rate) at the
            tool while joint rates are set.
        course_letters: Write the symbolic J, det J and J⁻¹ with the DH parameters as letters (l₁, a₂, d₄ …).
        symbolic_inverse: Show the symbolic J⁻¹ = adj(J) / det J (asked for with a button: it takes seconds).
    """

    frames: bool = False
    labels: bool = True
    columns: bool = True
    angular_columns: bool = False
    velocity_ellipsoid: bool = True
    rotational_ellipsoid: bool = False
    force_ellipsoid: bool = False
    scale: float = 1.0
    jacobian_frame: Frame = "base"
    damping: float = 0.0
    twist_frame: Frame = "base"
    speed: float = 1.0
    gizmo: bool = False
    ik_method: Literal["dls", "newton"] = "dls"
    ik_mode: Literal["position", "pose"] = "position"
    workspace: bool = False
    joint_map: bool = False
    map_i: int = 1
    map_j: int = 2
    derive: str = ""
    derive_step: int = 0
    representation: Literal["geometric", "zyx", "zyz"] = "geometric"
    jdot_arrow: bool = True
    course_letters: bool = False
    symbolic_inverse: bool = False


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
        derive_step=min(base.derive_step, robot.dof - 1),
    )


@dataclass(frozen=True, eq=False)
class LabState:
    """Everything one tab has chosen.

    Attributes:
        robot_name: Catalogue name of the robot (library name or file).
        robot: The immutable robot model.
        q: Joint values (n,) [rad | m], read-only.
        qd: Joint rates of the forward view v = J q̇ (n,) [rad/s | m/s], read-only.
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
    """

    robot_name: str
    robot: Robot
    q: np.ndarray
    qd: np.ndarray
    v_desired: np.ndarray = field(default_factory=lambda: frozen(np.zeros(6)))
    wrench: np.ndarray = field(default_factory=lambda: frozen(np.zeros(6)))
    options: Options = field(default_factory=Options)
    configuration: str = ""
    playing: bool = False
    time: float = 0.0
    stopped: str = ""
    chain: str = ""
    motion: MotionState = field(default_factory=MotionState)

    def __post_init__(self) -> None:
        n = self.robot.dof
        for name, length in (("q", n), ("qd", n), ("v_desired", 6), ("wrench", 6)):
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
