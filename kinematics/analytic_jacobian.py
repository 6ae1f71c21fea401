"""The analytic Jacobian: joint rates to position and Euler-angle rates.

The geometric Jacobian gives the angular velocity ω; a task written with
Euler angles φ needs φ̇ instead. They are related by ω = B(φ) φ̇, so

    J_A(q) = blockdiag(I, B(φ)⁻¹) · J(q),   rows [v; φ̇].

B(φ) loses rank at the representation's own singularity (pitch = ±90° for
ZYX, θ = 0 or π for ZYZ), whatever the robot does: there the analytic
Jacobian does not exist and :class:`RepresentationSingularityError` is raised.

Conventions (angles in the order of the rotations in the name):

* ``"zyx"`` (roll-pitch-yaw): R = Rz(yaw) · Ry(pitch) · Rx(roll), φ = (yaw, pitch, roll);
* ``"zyz"``: R = Rz(φ) · Ry(θ) · Rz(ψ), φ = (φ, θ, ψ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .conventions import FloatArray
from .errors import ConfigurationError, RepresentationSingularityError
from .model import Robot
from .motion.ik import solve
from .numeric import as_configuration, fk, jacobian
from .transforms import EulerConvention, check_euler_convention, euler_angles, euler_rotation
from .validation import finite_array

__all__ = [
    "EulerConvention",
    "euler_angles",
    "euler_rate_matrix",
    "euler_rotation",
    "analytic_jacobian",
    "analytic_parts",
    "AnalyticParts",
    "representation_singularity",
    "EULER_TOL",
]

EULER_TOL = 1e-6
"""|det B(φ)| below this is a representation singularity."""


def euler_rate_matrix(angles: npt.ArrayLike, convention: EulerConvention = "zyx") -> FloatArray:
    """B(φ) (3×3) with ω = B(φ) φ̇, ω in the base frame.

    Its columns are the axes of the three elementary rotations, each rotated
    by the ones before it: ZYX: z, Rz(α) y, Rz(α) Ry(β) x.
    """
    check_euler_convention(convention)
    a, b, _ = (float(v) for v in finite_array(angles, ((3,),), "angles"))
    ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
    if convention == "zyx":
        return np.array([[0.0, -sa, ca * cb], [0.0, ca, sa * cb], [1.0, 0.0, -sb]])
    return np.array([[0.0, -sa, ca * sb], [0.0, ca, sa * sb], [1.0, 0.0, cb]])


@dataclass(frozen=True, eq=False)
class AnalyticParts:
    """The analytic Jacobian's pieces at one tool orientation.

    Attributes:
        phi: The tool's Euler angles (3,) [rad].
        B: B(φ) (3, 3), ω = B(φ) φ̇ (the course's M(φ)).
        det_B: det B(φ).
        J_A: blockdiag(I, B(φ)⁻¹) J (6, n), rows [v; φ̇]; ``None`` at the representation singularity.
    """

    phi: FloatArray
    B: FloatArray
    det_B: float
    J_A: FloatArray | None


def analytic_parts(
    R_base_tool: FloatArray, J: FloatArray, convention: EulerConvention = "zyx", tol: float = EULER_TOL
) -> AnalyticParts:
    """φ, B(φ), det B and J_A for a tool orientation and its base-frame Jacobian J (6, n) already at
    hand (an app redrawing on every move has both); ``J_A`` is ``None`` where |det B| < ``tol``."""
    convention = check_euler_convention(convention)
    phi = euler_angles(R_base_tool, convention)
    B = euler_rate_matrix(phi, convention)
    det = float(np.linalg.det(B))
    if abs(det) < tol:
        return AnalyticParts(phi, B, det, None)
    JA = np.array(J, dtype=float)
    JA[3:] = np.linalg.solve(B, JA[3:])
    return AnalyticParts(phi, B, det, JA if np.isfinite(JA).all() else None)


def analytic_jacobian(
    robot: Robot, q: npt.ArrayLike, convention: EulerConvention = "zyx", tol: float = EULER_TOL
) -> FloatArray:
    """Analytic Jacobian J_A (6, n), rows [v; φ̇] with φ the tool's Euler angles in the base frame.

    Raises:
        RepresentationSingularityError: B(φ) is singular at the tool's orientation
            (|det B| < ``tol``): ZYX at pitch = ±90°, ZYZ at θ = 0 or π.
    """
    convention = check_euler_convention(convention)
    q = as_configuration(robot, q)
    if q.ndim != 1:
        raise ConfigurationError(f"analytic_jacobian takes one configuration ({robot.dof},), got {q.shape}")
    parts = analytic_parts(fk(robot, q)[:3, :3], jacobian(robot, q), convention, tol)
    if parts.J_A is None:
        which = "pitch = ±90°" if convention == "zyx" else "θ = 0 or 180°"
        raise RepresentationSingularityError(
            f"{convention.upper()} Euler angles are singular at this tool orientation ({which}, "
            f"det B = {parts.det_B:.2e}): no Euler-angle rate represents every angular velocity; "
            "use the geometric Jacobian or another convention"
        )
    return parts.J_A


def representation_singularity(
    robot: Robot, q: npt.ArrayLike, convention: EulerConvention, lo: FloatArray, hi: FloatArray
) -> FloatArray:
    """Joint values near ``q`` (within [lo, hi]) where the tool keeps its position and its Euler angles
    are singular: ZYX pitch = ±90° (the tool's x axis along ∓z of the base), ZYZ θ = 0 or 180°
    (the tool's z axis along ±z of the base). Newton's method from ``q``; the closer solution wins.

    Raises:
        ConfigurationError: the arm reaches no such orientation from here within [lo, hi].
    """
    convention = check_euler_convention(convention)
    q = as_configuration(robot, q)
    T_tool = fk(robot, q)
    a, _, c = euler_angles(T_tool[:3, :3], convention)
    middles = (math.pi / 2, -math.pi / 2) if convention == "zyx" else (0.0, math.pi)
    best: FloatArray | None = None
    for b in middles:
        T = np.array(T_tool, dtype=float)
        T[:3, :3] = euler_rotation(np.array([a, b, c]), convention)
        result = solve(robot, T, q, method="newton", rows=(0, 1, 2, 3, 4, 5), max_iterations=200)
        x = np.asarray(result.q, dtype=float)
        if not result.converged or not np.isfinite(x).all() or (x < lo - 1e-9).any() or (x > hi + 1e-9).any():
            continue
        if best is None or np.linalg.norm(x - q) < np.linalg.norm(best - q):
            best = x
    if best is None:
        which = "pitch = ±90°" if convention == "zyx" else "θ = 0 or 180°"
        raise ConfigurationError(
            f"no configuration within the joint limits puts the tool at {which} here; "
            "move the arm elsewhere and try again"
        )
    return best
