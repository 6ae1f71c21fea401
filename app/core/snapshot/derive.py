"""What the Derive tab shows at one state: the DH frames and the course's derivations as numbers.

:func:`derivation` is called by :func:`app.core.snapshot.compute` when the tab walks through a
method (``Options.derive``, a key of :data:`kinematics.steps.METHODS`). Every step has the link
frames i−1 and i (Aᵢ = ⁱ⁻¹Tᵢ and ⁰Tᵢ); the method's own numbers come from its record's ``step``
(Whitney's columns, one joint's derivative and the tool's path, the link velocities outward, the
joint loads inward), so the panel and the 3-D view draw the same values.

A method that needs joint rates or a wrench takes the tab's; when they are all zero, which shows
nothing, a unit example is used instead (q̇ᵢ = 1 for every joint; a 1 N force along the base x
axis) and the panel says so.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS as STEP_METHODS
from kinematics.steps import PATH_POINTS

from ..options import OPTION
from ..ranges import reach
from ..state import LabState

__all__ = [
    "Method",
    "METHODS",
    "Derivation",
    "derivation",
    "PATH_POINTS",
    "UNIT_WRENCH",
    "sub",
    "axis_names",
    "tool_name",
]

Method = str
"""A key of :data:`kinematics.steps.METHODS` ("" for none)."""
METHODS: dict[str, str] = dict(zip(OPTION["derive"].choices, OPTION["derive"].labels, strict=True))
"""Option value → the label the tab's dropdown shows."""
UNIT_WRENCH = np.array([1.0, 0.0, 0.0, 0.0, 0.0, 0.0])


_SUB = str.maketrans("0123456789-+n", "₀₁₂₃₄₅₆₇₈₉₋₊ₙ")


def sub(i: int | str) -> str:
    """``i`` as a Unicode subscript: ``sub(12)`` → ``₁₂``."""
    return str(i).translate(_SUB)


def axis_names(robot: Robot, j: int) -> tuple[str, str]:
    """(axis name, point name) of joint ``j`` (0-based) in the course's notation: ("z₀", "p₀")."""
    k = j if robot.convention == "standard" else j + 1
    return f"z{sub(k)}", f"p{sub(k)}"


def tool_name(robot: Robot) -> str:
    """The tool point's name: pₙ, or pₑ when a tool transform follows frame n."""
    return "pₑ" if robot.dh is not None and not np.allclose(robot.tool, np.eye(4)) else "pₙ"


@dataclass(frozen=True, eq=False)
class Derivation:
    """The numbers of one step of one method at the state's q.

    Attributes:
        method: Which walk-through (a key of :data:`kinematics.steps.METHODS`).
        joint: The step: joint i (0-based); row i + 1 of the DH table.
        axes: The axes of that joint (more than one only for URDF mimic joints).
        T0: ⁰Tᵢ of the step's link frame (4, 4), in frame 0's axes.
        A: Aᵢ = ⁱ⁻¹Tᵢ of the step's link frame (4, 4).
        frames: T_base_frame of frames i−1 and i (2, 4, 4), for drawing.
        numbers: What the method's ``step`` gives (``None`` for the DH frames).
        inputs: The joint rates (n,) or wrench (6,) the method used (empty when it needs none).
        assumed: The rates or wrench are the unit example (the tab's were all zero).
        tool: The DH walk's last step: the tool frame as row n + 1 of the DH table (001's frame 4 of
            the 3R), ``A`` = ⁿTₙ₊₁ (the tool transform), ``T0`` = ⁰Tₙ₊₁, ``joint`` = n.
    """

    method: Method
    joint: int
    axes: tuple[int, ...]
    T0: np.ndarray
    A: np.ndarray
    frames: np.ndarray
    numbers: Any = None
    inputs: np.ndarray = field(default_factory=lambda: np.zeros(0))
    assumed: bool = False
    tool: bool = False


def _inputs(state: LabState, kind: str) -> tuple[np.ndarray, bool]:
    """The tab's joint rates or wrench for a method that needs them, or the unit example when all zero."""
    if kind == "rates":
        qd = np.array(state.qd)
        return (np.ones(state.robot.dof), True) if not np.any(qd) else (qd, False)
    if kind == "wrench":
        wrench = np.array(state.wrench)
        return (UNIT_WRENCH.copy(), True) if not np.any(wrench) else (wrench, False)
    return np.zeros(0), False


def derivation(state: LabState, L: np.ndarray) -> Derivation | None:
    """The Derive tab's numbers for ``state`` (``None`` when it walks through nothing); ``L``: its link
    frames (the snapshot has them)."""
    if not state.options.derive:
        return None
    method = STEP_METHODS[state.options.derive]
    robot, q = state.robot, np.array(state.q)
    if method.key == "dh" and state.options.derive_step >= robot.dof:  # the tool frame's row
        return Derivation(
            method=method.key,
            joint=robot.dof,
            axes=(),
            T0=np.linalg.inv(L[0]) @ L[-1],
            A=np.linalg.inv(L[-2]) @ L[-1],
            frames=L[[-2, -1]],
            tool=True,
        )
    j = min(state.options.derive_step, robot.dof - 1)
    axes = tuple(k for k, ax in enumerate(robot.axes) if ax.joint_index == j)
    k = axes[0]  # the step's link frame is k + 1, the one before it k
    inputs, assumed = _inputs(state, method.inputs)
    numbers = None if method.step is None else method.step(robot, q, j, inputs, reach(robot))
    return Derivation(
        method=method.key,
        joint=j,
        axes=axes,
        T0=np.linalg.inv(L[0]) @ L[k + 1],
        A=np.linalg.inv(L[k]) @ L[k + 1],
        frames=L[[k, k + 1]],
        numbers=numbers,
        inputs=inputs,
        assumed=assumed,
    )
