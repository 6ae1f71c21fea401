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
from typing import Literal, cast

import numpy as np

from .errors import ArrayError, ConfigurationError, OptionError, RepresentationSingularityError
from .model import Robot
from .motion.ik import solve
from .numeric import as_configuration, fk, jacobian
from .transforms import rot_x, rot_y, rot_z
from .validation import show

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

EulerConvention = Literal["zyx", "zyz"]
EULER_TOL = 1e-6
"""|det B(φ)| below this is a representation singularity."""


def _check(convention: object) -> EulerConvention:
    if isinstance(convention, str) and convention in ("zyx", "zyz"):
        return cast(EulerConvention, convention)
    raise OptionError(f"Euler convention must be one of 'zyx', 'zyz', got {show(convention)}")


def _finite_array(x: object, shapes: tuple[tuple[int, ...], ...], what: str) -> np.ndarray:
    try:
        a = np.asarray(x)
    except (TypeError, ValueError, OverflowError):
        raise ArrayError(f"{what} must be an array of numbers, got {show(x)}") from None
    if a.dtype.kind not in "iuf" or a.shape not in shapes:
        expected = " or ".join(str(s) for s in shapes)
        raise ArrayError(f"{what} must be numbers of shape {expected}, got {show(x)}")
    a = a.astype(float, copy=False)
    if not np.isfinite(a).all():
        raise ArrayError(f"{what} contains NaN or infinity")
    return a


def euler_angles(R: np.ndarray, convention: EulerConvention = "zyx") -> np.ndarray:
    """Euler angles (3,) [rad] of the rotation matrix R (3×3) in ``convention``.

    ZYX: pitch in [-π/2, π/2]; ZYZ: θ in [0, π]. At the representation
    singularity the split between the first and last angle is arbitrary
    (all of it is put in the first).
    """
    _check(convention)
    R = _finite_array(R, ((3, 3), (4, 4)), "R")[:3, :3]
    if convention == "zyx":
        cb = math.hypot(R[0, 0], R[1, 0])
        pitch = math.atan2(-R[2, 0], cb)
        if cb < 1e-12:
            return np.array([math.atan2(-R[0, 1], R[1, 1]), pitch, 0.0])
        return np.array([math.atan2(R[1, 0], R[0, 0]), pitch, math.atan2(R[2, 1], R[2, 2])])
    st = math.hypot(R[0, 2], R[1, 2])
    theta = math.atan2(st, R[2, 2])
    if st < 1e-12:
        return np.array([math.atan2(R[1, 0], R[0, 0]), theta, 0.0])
    return np.array([math.atan2(R[1, 2], R[0, 2]), theta, math.atan2(R[2, 1], -R[2, 0])])


def euler_rate_matrix(angles: np.ndarray, convention: EulerConvention = "zyx") -> np.ndarray:
    """B(φ) (3×3) with ω = B(φ) φ̇, ω in the base frame.

    Its columns are the axes of the three elementary rotations, each rotated
    by the ones before it: ZYX: z, Rz(α) y, Rz(α) Ry(β) x.
    """
    _check(convention)
    a, b, _ = (float(v) for v in _finite_array(angles, ((3,),), "angles"))
    ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
    if convention == "zyx":
        return np.array([[0.0, -sa, ca * cb], [0.0, ca, sa * cb], [1.0, 0.0, -sb]])
    return np.array([[0.0, -sa, ca * sb], [0.0, ca, sa * sb], [1.0, 0.0, cb]])


def euler_rotation(angles: np.ndarray, convention: EulerConvention = "zyx") -> np.ndarray:
    """The rotation matrix (3, 3) of Euler angles (3,) [rad]: the inverse of :func:`euler_angles`.

    ZYX: Rz(yaw) Ry(pitch) Rx(roll); ZYZ: Rz(φ) Ry(θ) Rz(ψ).
    """
    convention = _check(convention)
    a, b, c = (float(v) for v in _finite_array(angles, ((3,),), "angles"))
    last = rot_x(c) if convention == "zyx" else rot_z(c)
    return (rot_z(a) @ rot_y(b) @ last)[:3, :3]


@dataclass(frozen=True, eq=False)
class AnalyticParts:
    """The analytic Jacobian's pieces at one tool orientation.

    Attributes:
        phi: The tool's Euler angles (3,) [rad].
        B: B(φ) (3, 3), ω = B(φ) φ̇ (the course's M(φ)).
        det_B: det B(φ).
        J_A: blockdiag(I, B(φ)⁻¹) J (6, n), rows [v; φ̇]; ``None`` at the representation singularity.
    """

    phi: np.ndarray
    B: np.ndarray
    det_B: float
    J_A: np.ndarray | None


def analytic_parts(
    R_base_tool: np.ndarray, J: np.ndarray, convention: EulerConvention = "zyx", tol: float = EULER_TOL
) -> AnalyticParts:
    """φ, B(φ), det B and J_A for a tool orientation and its base-frame Jacobian J (6, n) already at
    hand (an app redrawing on every move has both); ``J_A`` is ``None`` where |det B| < ``tol``."""
    convention = _check(convention)
    phi = euler_angles(R_base_tool, convention)
    B = euler_rate_matrix(phi, convention)
    det = float(np.linalg.det(B))
    if abs(det) < tol:
        return AnalyticParts(phi, B, det, None)
    JA = np.array(J, dtype=float)
    JA[3:] = np.linalg.solve(B, JA[3:])
    return AnalyticParts(phi, B, det, JA if np.isfinite(JA).all() else None)


def analytic_jacobian(
    robot: Robot, q: object, convention: EulerConvention = "zyx", tol: float = EULER_TOL
) -> np.ndarray:
    """Analytic Jacobian J_A (6, n), rows [v; φ̇] with φ the tool's Euler angles in the base frame.

    Raises:
        RepresentationSingularityError: B(φ) is singular at the tool's orientation
            (|det B| < ``tol``): ZYX at pitch = ±90°, ZYZ at θ = 0 or π.
    """
    convention = _check(convention)
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
    robot: Robot, q: object, convention: EulerConvention, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray:
    """Joint values near ``q`` (within [lo, hi]) where the tool keeps its position and its Euler angles
    are singular: ZYX pitch = ±90° (the tool's x axis along ∓z of the base), ZYZ θ = 0 or 180°
    (the tool's z axis along ±z of the base). Newton's method from ``q``; the closer solution wins.

    Raises:
        ConfigurationError: the arm reaches no such orientation from here within [lo, hi].
    """
    convention = _check(convention)
    q = as_configuration(robot, q)
    T_tool = fk(robot, q)
    a, _, c = euler_angles(T_tool[:3, :3], convention)
    middles = (math.pi / 2, -math.pi / 2) if convention == "zyx" else (0.0, math.pi)
    best: np.ndarray | None = None
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
