"""The course's quantities the panels show beside J: J⁻¹ (or J⁺), the analytic Jacobian J_A and J̇ q̇.

Pure functions of numbers (called by :func:`app.snapshot.compute` and the
reducer), cheap enough for every redraw:

* :func:`inverse_view`: J⁻¹ of a square task J (``None`` where it does not
  exist: rank lost, det J = 0), J⁺ of a non-square one;
* :func:`analytic_view`: the tool's Euler angles φ, the course's M(φ)
  (``kinematics.analytic`` calls it B(φ): ω = M(φ) φ̇) and
  J_A = diag(I, M(φ)⁻¹) J, or "does not exist" at the representation's singularity;
* :func:`representation_singular_q`: a configuration near ``q`` where the chosen
  Euler angles are singular (ZYX pitch ±90°, ZYZ θ = 0), by inverse kinematics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from kinematics import ik
from kinematics.analytic import EULER_TOL, euler_angles, euler_rate_matrix
from kinematics.inverse import pinv

__all__ = [
    "InverseView",
    "AnalyticView",
    "REPRESENTATIONS",
    "inverse_view",
    "analytic_view",
    "representation_singular_q",
]

REPRESENTATIONS = {
    "geometric": "geometric J",
    "zyx": "analytic J_A, roll-pitch-yaw (ZYX)",
    "zyz": "analytic J_A, Euler ZYZ",
}
"""Option value → the label of the J(q) tab's "Representation" dropdown."""


@dataclass(frozen=True, eq=False)
class InverseView:
    """The inverse of the task Jacobian the q̇ = J⁺ v tab uses.

    Attributes:
        kind: "inverse" (square, invertible), "none" (square, rank lost: det J = 0) or
            "pseudo" (not square: J⁺, the Moore–Penrose pseudo-inverse).
        matrix: J⁻¹ or J⁺ (n, rows) [units inverse to J's], ``None`` when kind is "none".
        det: det J (square), else ``None``.
    """

    kind: Literal["inverse", "pseudo", "none"]
    matrix: np.ndarray | None
    det: float | None


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


@dataclass(frozen=True, eq=False)
class AnalyticView:
    """The analytic Jacobian at q for one Euler-angle convention.

    Attributes:
        convention: "zyx" (φ = yaw, pitch, roll) or "zyz" (φ = φ, θ, ψ).
        phi: The tool's Euler angles (3,) [rad] in the base frame.
        M: M(φ) (3, 3) with ω = M(φ) φ̇ (``kinematics.analytic.euler_rate_matrix``).
        det_M: det M(φ) (−cos pitch for ZYX, −sin θ for ZYZ).
        J_A: diag(I, M(φ)⁻¹) J (6, n), rows [v; φ̇]; ``None`` at the representation singularity.
    """

    convention: str
    phi: np.ndarray
    M: np.ndarray
    det_M: float
    J_A: np.ndarray | None

    @property
    def singular(self) -> bool:
        """Whether the representation is singular here (|det M| below ``EULER_TOL``)."""
        return self.J_A is None


def analytic_view(T_tool: np.ndarray, J_base: np.ndarray, convention: str) -> AnalyticView:
    """φ, M(φ) and J_A for the tool pose ``T_tool`` (4, 4) and the base-frame J (6, n)."""
    conv: Literal["zyx", "zyz"] = "zyz" if convention == "zyz" else "zyx"
    phi = euler_angles(T_tool[:3, :3], conv)
    M = euler_rate_matrix(phi, conv)
    det = float(np.linalg.det(M))
    if abs(det) < EULER_TOL:
        return AnalyticView(conv, phi, M, det, None)
    J_A = np.array(J_base, dtype=float)
    J_A[3:] = np.linalg.solve(M, J_base[3:])
    return AnalyticView(conv, phi, M, det, J_A if np.isfinite(J_A).all() else None)


def _rotation(convention: str, a: float, b: float, c: float) -> np.ndarray:
    def rz(t: float) -> np.ndarray:
        return np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1.0]])

    def ry(t: float) -> np.ndarray:
        return np.array([[math.cos(t), 0, math.sin(t)], [0, 1.0, 0], [-math.sin(t), 0, math.cos(t)]])

    def rx(t: float) -> np.ndarray:
        return np.array([[1.0, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])

    return rz(a) @ ry(b) @ (rx(c) if convention == "zyx" else rz(c))


def representation_singular_q(
    robot, q: np.ndarray, T_tool: np.ndarray, convention: str, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray:
    """Joint values near ``q`` (within [lo, hi]) where the tool keeps its position and its Euler angles
    are singular: ZYX pitch = ±90° (the tool's x axis along ∓z of the base), ZYZ θ = 0 or 180°
    (the tool's z axis along ±z of the base).

    Raises:
        ValueError: the arm reaches no such orientation from here (the message says so).
    """
    conv: Literal["zyx", "zyz"] = "zyz" if convention == "zyz" else "zyx"
    a, _, c = euler_angles(T_tool[:3, :3], conv)
    middles = (math.pi / 2, -math.pi / 2) if conv == "zyx" else (0.0, math.pi)
    best: np.ndarray | None = None
    for b in middles:
        T = np.array(T_tool, dtype=float)
        T[:3, :3] = _rotation(conv, float(a), b, float(c))
        result = ik.solve(robot, T, q, method="newton", rows=(0, 1, 2, 3, 4, 5), max_iterations=200)
        x = np.asarray(result.q, dtype=float)
        if not result.converged or not np.isfinite(x).all() or (x < lo - 1e-9).any() or (x > hi + 1e-9).any():
            continue
        if best is None or np.linalg.norm(x - q) < np.linalg.norm(best - q):
            best = x
    if best is None:
        which = "pitch = ±90°" if conv == "zyx" else "θ = 0 or 180°"
        raise ValueError(
            f"no configuration within the joint limits puts the tool at {which} here; "
            "move the arm elsewhere and try again"
        )
    return best
