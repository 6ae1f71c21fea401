"""What the Derive tab shows at one state: the DH frames and the course's derivations as numbers.

:func:`derivation` is called by :func:`app.core.snapshot.compute` when the tab walks through a
method (``Options.derive``); it only asks :mod:`kinematics.steps` and :mod:`kinematics`
for numbers, so the panel and the 3-D view draw the same values:

* ``"dh"``: row i of the DH table: the link transform Aᵢ = ⁱ⁻¹Tᵢ and the product ⁰Tᵢ at q,
  frames i−1 and i drawn with their axes named;
* ``"whitney"``: column i as zᵢ₋₁ × (pₙ − pᵢ₋₁), zᵢ₋₁ with the three vectors drawn;
* ``"differentiation"``: ∂p/∂qᵢ as the tangent of the path the tool traces when only qᵢ moves;
* ``"propagation"``: ωₖ and vₖ link by link for the tab's joint rates q̇;
* ``"force"``: the tab's tool wrench carried inward to τᵢ (the transpose view, τ = Jᵀ F).

Joint rates and wrench that are all zero show nothing, so a unit example is used instead
(q̇ᵢ = 1 for every joint; a 1 N force along the base x axis) and the panel says so.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from kinematics import Robot, fk
from kinematics.steps import (
    DerivativeColumn,
    JointLoad,
    LinkVelocity,
    WhitneyColumn,
    differentiation,
    force_propagation,
    propagation,
    whitney,
)

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

Method = Literal["", "dh", "whitney", "differentiation", "propagation", "force"]
METHODS: dict[str, str] = dict(zip(OPTION["derive"].choices, OPTION["derive"].labels, strict=True))
"""Option value → the label the tab's dropdown shows."""
PATH_POINTS = 41
"""Points of the tool path drawn for a differentiation step."""
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
        method: Which walk-through ("dh", "whitney", …).
        joint: The step: joint i (0-based); row i + 1 of the DH table.
        axes: The axes of that joint (more than one only for URDF mimic joints).
        T0: ⁰Tᵢ of the step's link frame (4, 4), in frame 0's axes.
        A: Aᵢ = ⁱ⁻¹Tᵢ of the step's link frame (4, 4).
        frames: T_base_frame of frames i−1 and i (2, 4, 4), for drawing.
        whitney: Whitney's columns of every axis (Whitney only).
        derivative: ∂/∂qᵢ of the forward kinematics for the step's joint (differentiation only).
        path: Tool points (PATH_POINTS, 3) as qᵢ alone sweeps around its value (differentiation).
        links: Link velocities outward (propagation), the tool last.
        qd: The joint rates used (propagation).
        loads: Axis loads inward (force).
        wrench: The wrench used (force).
        assumed: The rates or wrench are the unit example (the tab's were all zero).
    """

    method: Method
    joint: int
    axes: tuple[int, ...]
    T0: np.ndarray
    A: np.ndarray
    frames: np.ndarray
    whitney: tuple[WhitneyColumn, ...] = ()
    derivative: DerivativeColumn | None = None
    path: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    links: tuple[LinkVelocity, ...] = ()
    qd: np.ndarray = field(default_factory=lambda: np.zeros(0))
    loads: tuple[JointLoad, ...] = ()
    wrench: np.ndarray = field(default_factory=lambda: np.zeros(6))
    assumed: bool = False


def _sweep(robot: Robot, q: np.ndarray, j: int) -> np.ndarray:
    """Tool points as joint j alone moves ±30° (±a tenth of the arm's reach for a slide) about q."""
    half = np.radians(30.0) if robot.joints[j].kind == "revolute" else 0.1 * max(reach(robot), 0.1)
    Q = np.repeat(q[None], PATH_POINTS, axis=0)
    Q[:, j] += np.linspace(-half, half, PATH_POINTS)
    return fk(robot, Q)[:, :3, 3]


def derivation(state: LabState, L: np.ndarray) -> Derivation | None:
    """The Derive tab's numbers for ``state`` (``None`` when it walks through nothing); ``L``: its link
    frames (the snapshot has them)."""
    method = state.options.derive
    if not method:
        return None
    robot, q = state.robot, np.array(state.q)
    j = min(state.options.derive_step, robot.dof - 1)
    axes = tuple(k for k, ax in enumerate(robot.axes) if ax.joint_index == j)
    k = axes[0]  # the step's link frame is k + 1, the one before it k
    common = dict(
        method=method,
        joint=j,
        axes=axes,
        T0=np.linalg.inv(L[0]) @ L[k + 1],
        A=np.linalg.inv(L[k]) @ L[k + 1],
        frames=L[[k, k + 1]],
    )
    if method == "dh":
        return Derivation(**common)
    if method == "whitney":
        return Derivation(**common, whitney=whitney(robot, q))
    if method == "differentiation":
        d = differentiation(robot, q, joints=(j,))[0]
        return Derivation(**common, derivative=d, path=_sweep(robot, q, j))
    if method == "propagation":
        qd = np.array(state.qd)
        assumed = not np.any(qd)
        qd = np.ones(robot.dof) if assumed else qd
        return Derivation(**common, links=propagation(robot, q, qd), qd=qd, assumed=assumed)
    wrench = np.array(state.wrench)
    assumed = not np.any(wrench)
    wrench = UNIT_WRENCH if assumed else wrench
    loads = force_propagation(robot, q, wrench)
    return Derivation(**common, loads=loads, wrench=wrench, assumed=assumed)
