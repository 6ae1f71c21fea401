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
from typing import Literal, cast

import numpy as np

from .errors import ArrayError, ConfigurationError, OptionError, RepresentationSingularityError
from .model import Robot
from .numeric import as_configuration, fk, jacobian
from .validation import show

__all__ = ["EulerConvention", "euler_angles", "euler_rate_matrix", "analytic_jacobian", "EULER_TOL"]

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
    phi = euler_angles(fk(robot, q)[:3, :3], convention)
    B = euler_rate_matrix(phi, convention)
    det = float(np.linalg.det(B))
    if abs(det) < tol:
        which = "pitch = ±90°" if convention == "zyx" else "θ = 0 or 180°"
        raise RepresentationSingularityError(
            f"{convention.upper()} Euler angles are singular at this tool orientation ({which}, "
            f"det B = {det:.2e}): no Euler-angle rate represents every angular velocity; "
            "use the geometric Jacobian or another convention"
        )
    J = jacobian(robot, q)
    JA = J.copy()
    JA[3:] = np.linalg.solve(B, J[3:])
    return JA
