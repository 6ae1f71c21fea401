"""The course's quantities the panels show beside J: J⁻¹ (or J⁺), the analytic Jacobian J_A and J̇ q̇.

Pure functions of numbers (called by :func:`app.core.snapshot.compute` and the
reducer), cheap enough for every redraw:

* :func:`inverse_view`: J⁻¹ of a square task J (``None`` where it does not
  exist: rank lost, det J = 0), J⁺ of a non-square one;
* :func:`analytic_view`: the tool's Euler angles φ, the course's M(φ)
  (``kinematics.analytic_jacobian`` calls it B(φ): ω = M(φ) φ̇) and
  J_A = diag(I, M(φ)⁻¹) J, or "does not exist" at the representation's singularity
  (:func:`kinematics.analytic_jacobian.analytic_parts`, named as the course names them).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal

import numpy as np

from kinematics import Robot
from kinematics.analytic_jacobian import analytic_parts
from kinematics.inverse import pinv
from kinematics.motion.closed_form import closed_form, closed_form_inverse_jacobian

from ..options import OPTION

__all__ = [
    "InverseView",
    "AnalyticView",
    "REPRESENTATIONS",
    "inverse_view",
    "with_closed_form",
    "analytic_view",
]

REPRESENTATIONS = dict(zip(OPTION["representation"].choices, OPTION["representation"].labels, strict=True))
"""Option value → the label of the J(q) tab's "Representation" dropdown."""


@dataclass(frozen=True, eq=False)
class InverseView:
    """The inverse of the task Jacobian the q̇ = J⁺ v tab uses.

    Attributes:
        kind: "inverse" (square, invertible), "none" (square, rank lost: det J = 0) or
            "pseudo" (not square: J⁺, the Moore–Penrose pseudo-inverse).
        matrix: J⁻¹ or J⁺ (n, rows) [units inverse to J's], ``None`` when kind is "none".
        det: det J (square), else ``None``.
        closed: Whether the robot has a closed-form IK (the planar 2R, the TRR): 002's third way.
        closed_form: J⁻¹ = ∂q/∂x of that closed-form IK (n, rows), base axes; ``None`` where it does
            not exist (singular), without a closed form, or with the twist in tool axes.
        closed_gap: max |J⁻¹ − ∂q/∂x| when both exist, else ``None``.
    """

    kind: Literal["inverse", "pseudo", "none"]
    matrix: np.ndarray | None
    det: float | None
    closed: bool = False
    closed_form: np.ndarray | None = None
    closed_gap: float | None = None


def inverse_view(J_task: np.ndarray, rank: int) -> InverseView:
    """J⁻¹ of the square ``J_task`` (k, n) of numerical rank ``rank``, or its J⁺ when k ≠ n.

    A square J whose rank is below n has no inverse (its det J is 0 up to round-off): kind "none",
    never a matrix of 10¹⁶s. Near that, J⁻¹ is finite and large: it blows up as det J → 0.
    """
    k, n = J_task.shape
    if k != n:
        return InverseView("pseudo", pinv(J_task), None)
    det = float(np.linalg.det(J_task))
    if rank < n or det == 0.0:
        return InverseView("none", None, 0.0)
    inv = np.linalg.inv(J_task)
    if not np.isfinite(inv).all():
        return InverseView("none", None, 0.0)
    return InverseView("inverse", inv, det)


def with_closed_form(view: InverseView, robot: Robot, q: np.ndarray, base_axes: bool) -> InverseView:
    """``view`` with 002's third J⁻¹, from the closed-form inverse kinematics, when ``robot`` has one
    (compared with J⁻¹ when both exist; computed in base axes only)."""
    if closed_form(robot) is None:
        return view
    closed = closed_form_inverse_jacobian(robot, q) if base_axes else None
    gap = None
    if closed is not None and view.kind == "inverse" and view.matrix is not None:
        gap = float(np.abs(view.matrix - closed).max())
    return dataclasses.replace(view, closed=True, closed_form=closed, closed_gap=gap)


@dataclass(frozen=True, eq=False)
class AnalyticView:
    """The analytic Jacobian at q for one Euler-angle convention.

    Attributes:
        convention: "zyx" (φ = yaw, pitch, roll) or "zyz" (φ = φ, θ, ψ).
        phi: The tool's Euler angles (3,) [rad] in the base frame.
        M: M(φ) (3, 3) with ω = M(φ) φ̇ (``kinematics.analytic_jacobian.euler_rate_matrix``).
        det_M: det M(φ) (−cos pitch for ZYX, −sin θ for ZYZ).
        J_A: diag(I, M(φ)⁻¹) J (6, n), rows [v; φ̇]; ``None`` at the representation singularity.
        regular_instead: At a representation singularity, the other convention when it is regular at
            this orientation (the fix the J(q) tab offers), else "".
    """

    convention: str
    phi: np.ndarray
    M: np.ndarray
    det_M: float
    J_A: np.ndarray | None
    regular_instead: str = ""

    @property
    def singular(self) -> bool:
        """Whether the representation is singular here (|det M| below ``EULER_TOL``)."""
        return self.J_A is None


def analytic_view(T_tool: np.ndarray, J_base: np.ndarray, convention: str) -> AnalyticView:
    """φ, M(φ) and J_A for the tool pose ``T_tool`` (4, 4) and the base-frame J (6, n)."""
    conv: Literal["zyx", "zyz"] = "zyz" if convention == "zyz" else "zyx"
    parts = analytic_parts(T_tool[:3, :3], J_base, conv)
    instead = ""
    if parts.J_A is None:
        other: Literal["zyx", "zyz"] = "zyx" if conv == "zyz" else "zyz"
        instead = other if analytic_parts(T_tool[:3, :3], J_base, other).J_A is not None else ""
    return AnalyticView(conv, parts.phi, parts.B, parts.det_B, parts.J_A, instead)
