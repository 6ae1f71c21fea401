"""The state of one browser tab, as plain data: no handles, no threads.

:class:`LabState` is everything a client has chosen (robot, joint values,
joint rates, desired tool velocity, applied force, display options). It is
a value: :meth:`LabState.copy` gives an independent copy, so a future
classroom mode can mirror a presenter's state to every student, an
animation can step it, and a test can build one without a browser. The GUI
reads it to set its inputs and writes it from their callbacks; the maths
reads it in :func:`app.snapshot.compute`.

Units are SI with radians, like :mod:`kinematics`; degrees exist only on
the sliders.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from kinematics import Robot

__all__ = ["Options", "LabState"]

Frame = Literal["base", "tool"]


@dataclass
class Options:
    """What the client chose to see.

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


@dataclass
class LabState:
    """Everything one client has chosen.

    Attributes:
        robot_name: Catalogue name of the robot (library name or URDF path).
        robot: The immutable robot model.
        q: Joint values (n,) [rad | m].
        qd: Joint rates for the forward view v = J q̇ (n,) [rad/s | m/s].
        v_desired: Desired tool twist (6,) [m/s; rad/s], base axes, rows [v; ω];
            only the robot's task rows are used.
        wrench: Force and moment applied at the tool point (6,) [N; N·m], base axes.
        options: Display options.
        configuration: Name of the named configuration last visited ("" once a joint moves).
    """

    robot_name: str
    robot: Robot
    q: np.ndarray
    qd: np.ndarray
    v_desired: np.ndarray = field(default_factory=lambda: np.zeros(6))
    wrench: np.ndarray = field(default_factory=lambda: np.zeros(6))
    options: Options = field(default_factory=Options)
    configuration: str = ""

    @classmethod
    def initial(cls, robot_name: str, robot: Robot, options: Options | None = None) -> LabState:
        """A fresh state for ``robot`` at its home configuration, at rest, no force."""
        home = next((c.name for c in robot.configurations if c.name == "home"), "")
        return cls(
            robot_name=robot_name,
            robot=robot,
            q=np.array(robot.home, dtype=float),
            qd=np.zeros(robot.dof),
            options=dataclasses.replace(options) if options is not None else Options(),
            configuration=home,
        )

    def copy(self) -> LabState:
        """An independent copy (arrays and options copied; the robot is immutable and shared)."""
        return dataclasses.replace(
            self,
            q=self.q.copy(),
            qd=self.qd.copy(),
            v_desired=self.v_desired.copy(),
            wrench=self.wrench.copy(),
            options=dataclasses.replace(self.options),
        )
