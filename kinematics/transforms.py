"""Small helpers for homogeneous transforms and rotations (numeric, NumPy).

All transforms are 4×4 homogeneous matrices ``T_a_b`` mapping coordinates in
frame *b* to frame *a*; angles are in radians, lengths in metres.
"""

from __future__ import annotations

import math
from typing import Literal, cast

import numpy as np
import numpy.typing as npt

from .conventions import FloatArray
from .errors import OptionError, RobotDefinitionError
from .validation import MAX_LENGTH, finite_array, show

__all__ = [
    "rot_x",
    "rot_y",
    "rot_z",
    "trans",
    "rpy_to_matrix",
    "matrix_to_rpy",
    "EulerConvention",
    "EULER_CONVENTIONS",
    "check_euler_convention",
    "euler_angles",
    "euler_rotation",
    "rotation_z_to",
    "check_rigid_transform",
    "rotation_log",
    "skew",
]


def rot_x(angle: float) -> FloatArray:
    """4×4 rotation about x by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def rot_y(angle: float) -> FloatArray:
    """4×4 rotation about y by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]])


def rot_z(angle: float) -> FloatArray:
    """4×4 rotation about z by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def trans(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> FloatArray:
    """4×4 pure translation by (x, y, z) [m]."""
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def rpy_to_matrix(roll: float, pitch: float, yaw: float) -> FloatArray:
    """3×3 rotation R = Rz(yaw) Ry(pitch) Rx(roll) (URDF's rpy convention) [rad]: ZYX Euler angles."""
    return euler_rotation(np.array([yaw, pitch, roll]), "zyx")


def matrix_to_rpy(R: npt.ArrayLike) -> FloatArray:
    """Inverse of :func:`rpy_to_matrix`: (roll, pitch, yaw) [rad], pitch in [-π/2, π/2].

    The ZYX :func:`euler_angles` in URDF's order (at gimbal lock all of the turn is in yaw).
    """
    return cast(FloatArray, euler_angles(R, "zyx")[::-1].copy())


EulerConvention = Literal["zyx", "zyz"]
EULER_CONVENTIONS: tuple[EulerConvention, ...] = ("zyx", "zyz")
"""Euler-angle conventions, named by the order of their rotations."""


def check_euler_convention(convention: object) -> EulerConvention:
    """``convention`` if it is one of :data:`EULER_CONVENTIONS`, else an OptionError listing them."""
    if isinstance(convention, str) and convention in EULER_CONVENTIONS:
        return convention
    raise OptionError(f"Euler convention must be one of 'zyx', 'zyz', got {show(convention)}")


def euler_angles(R: npt.ArrayLike, convention: EulerConvention = "zyx") -> FloatArray:
    """Euler angles (3,) [rad] of the rotation matrix R (3×3) in ``convention``.

    ZYX: pitch in [-π/2, π/2]; ZYZ: θ in [0, π]. At the representation
    singularity the split between the first and last angle is arbitrary
    (all of it is put in the first).
    """
    check_euler_convention(convention)
    R = finite_array(R, ((3, 3), (4, 4)), "R")[:3, :3]
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


def euler_rotation(angles: npt.ArrayLike, convention: EulerConvention = "zyx") -> FloatArray:
    """The rotation matrix (3, 3) of Euler angles (3,) [rad]: the inverse of :func:`euler_angles`.

    ZYX: Rz(yaw) Ry(pitch) Rx(roll); ZYZ: Rz(φ) Ry(θ) Rz(ψ).
    """
    convention = check_euler_convention(convention)
    a, b, c = (float(v) for v in finite_array(angles, ((3,),), "angles"))
    last = rot_x(c) if convention == "zyx" else rot_z(c)
    return (rot_z(a) @ rot_y(b) @ last)[:3, :3]


def rotation_z_to(axis: FloatArray) -> FloatArray:
    """A 3×3 rotation whose third column is the unit vector ``axis``.

    Used to make every joint move about its local z axis: a URDF joint with
    axis ``u`` becomes a joint about z in the frame rotated by this matrix.
    """
    u = np.asarray(axis, dtype=float)
    u = u / np.linalg.norm(u)
    if np.allclose(u, [0, 0, 1], atol=1e-12):
        return np.eye(3)
    # Pick the coordinate axis least aligned with u to build an orthonormal basis.
    helper = np.eye(3)[int(np.argmin(np.abs(u)))]
    x = np.cross(helper, u)
    x /= np.linalg.norm(x)
    y = np.cross(u, x)
    return np.column_stack([x, y, u])


def check_rigid_transform(T: npt.ArrayLike, what: str, tol: float = 1e-6) -> FloatArray:
    """Return ``T`` as a float 4×4 rigid transform, or raise naming ``what`` and the defect.

    Checks: numbers only (no strings, bools or objects), shape (4, 4), finite, last row
    [0, 0, 0, 1], an orthonormal upper-left block with det +1 (to ``tol``) and a translation
    within :data:`~kinematics.validation.MAX_LENGTH`.

    Raises:
        RobotDefinitionError: The message starts with ``what``.
    """
    try:
        raw = np.asarray(T)
    except (TypeError, ValueError, OverflowError) as exc:
        raise RobotDefinitionError(f"{what}: expected a 4×4 numeric matrix ({exc})") from None
    if raw.dtype.kind not in "iuf":
        raise RobotDefinitionError(
            f"{what}: expected a 4×4 numeric matrix of ints or floats, got {_dtype_text(raw.dtype)}"
        )
    A = np.array(raw, dtype=float)
    if A.shape != (4, 4):
        raise RobotDefinitionError(f"{what}: expected a 4×4 homogeneous transform, got shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise RobotDefinitionError(f"{what}: contains a non-finite number (NaN or infinity)")
    if not np.allclose(A[3], [0, 0, 0, 1], atol=tol):
        raise RobotDefinitionError(f"{what}: last row must be [0, 0, 0, 1], got {A[3].tolist()}")
    R = A[:3, :3]
    if not np.allclose(R.T @ R, np.eye(3), atol=tol) or np.linalg.det(R) < 0:
        raise RobotDefinitionError(
            f"{what}: the upper-left 3×3 block is not a rotation (orthonormal, det = +1)"
        )
    if np.abs(A[:3, 3]).max() > MAX_LENGTH:
        raise RobotDefinitionError(
            f"{what}: translation {A[:3, 3].tolist()} m is out of range; "
            f"expected each component within ±{MAX_LENGTH:g} m"
        )
    A[3] = (0, 0, 0, 1)
    return A


def _dtype_text(dtype: np.dtype) -> str:
    names = {"b": "bools", "U": "strings", "S": "bytes", "c": "complex numbers", "O": "objects"}
    return names.get(dtype.kind, f"dtype {dtype}")


def skew(w: FloatArray) -> FloatArray:
    """3×3 skew-symmetric matrix [w]× with [w]× v = w × v."""
    x, y, z = w
    return np.array([[0, -z, y], [z, 0, -x], [-y, x, 0.0]])


def rotation_log(R: npt.ArrayLike) -> FloatArray:
    """Rotation vector (axis · angle) [rad] of a 3×3 rotation matrix, angle in [0, π]."""
    R = np.asarray(R, dtype=float)
    cos_angle = np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)
    angle = math.acos(cos_angle)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if angle < 1e-6:
        return 0.5 * w
    if math.pi - angle < 1e-6:
        # Near π: the axis is the dominant column of (R + I) / 2.
        M = (R + np.eye(3)) / 2.0
        k = int(np.argmax(np.diag(M)))
        axis = M[:, k] / math.sqrt(max(M[k, k], 1e-300))
        return axis * angle
    return w * (angle / (2.0 * math.sin(angle)))
