"""Numeric forward kinematics and geometric Jacobians (NumPy).

Every function takes an immutable :class:`~kinematics.model.Robot` and a
configuration ``q``: shape (n,) for one configuration or (N, n) for a batch.
Batches are vectorised over N (no Python loop over configurations) and are
processed in cache-sized chunks.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from .errors import ConfigurationError
from .model import Robot

__all__ = ["fk", "joint_frames", "link_frames", "jacobian", "jacobian_dot", "as_configuration"]

Frame = Literal["base", "tool"]
_CHUNK = 2048  # configurations per chunk in batched kernels (keeps working arrays in cache)


def as_configuration(robot: Robot, q: object) -> np.ndarray:
    """Return ``q`` as a float array of shape (n,) or (N, n), or raise ConfigurationError.

    Args:
        robot: The robot (defines n = ``robot.dof``).
        q: Joint values [rad] for revolute, [m] for prismatic joints.
    """
    try:
        a = np.asarray(q, dtype=float)
    except (TypeError, ValueError):
        raise ConfigurationError(f"q must be numeric, got {q!r}") from None
    if a.ndim not in (1, 2) or a.shape[-1] != robot.dof:
        raise ConfigurationError(
            f"q has shape {a.shape}; robot {robot.name!r} expects ({robot.dof},) or (N, {robot.dof})"
        )
    if not np.isfinite(a).all():
        raise ConfigurationError("q contains NaN or infinity; every joint value must be finite")
    return a


# --------------------------------------------------------------------- single
def _chain_single(robot: Robot, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joint frames T_base_joint (m, 4, 4) (before each axis moves) and T_base_tool."""
    c = robot._compiled  # type: ignore[attr-defined]
    qa = q if c.simple else q[c.index] * c.multiplier
    qa = qa + c.offset
    # Rz(θ) · F = cos θ · (Dc F) + sin θ · (Ds F) + (E F), precomputed per axis, so that the
    # moved-and-fixed transform of every axis comes from a few whole-stack operations.
    if c.all_revolute:
        cs = np.cos(qa - _SIN_SHIFT)  # row 0: cos, row 1: sin
        P = cs[0, :, None, None] * c.rz_cos + cs[1, :, None, None] * c.rz_sin + c.rz_const
    else:
        cs = np.cos(qa * c.revolute - _SIN_SHIFT)
        P = cs[0, :, None, None] * c.rz_cos + cs[1, :, None, None] * c.rz_sin + c.rz_const
        P += (qa * c.prismatic)[:, None, None] * c.tz_lin
    # Prefix products A_0 · A_1 ⋯ A_k by a parallel scan: log2(m + 1) stacked matmuls.
    A = np.concatenate((c.fixed[:1], P))
    step = 1
    while step < len(A):
        A[step:] = np.matmul(A[:-step], A[step:])
        step *= 2
    return A[:-1], A[-1]


_SIN_SHIFT = np.array([[0.0], [np.pi / 2]])
# Levi-Civita tensor as a (3, 9) map: (z @ _SKEW).reshape(3, 3) is the cross-product matrix [z]x.
_SKEW = np.zeros((3, 3, 3))
for _i, _j, _k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    _SKEW[_k, _i, _j] = -1.0
    _SKEW[_k, _j, _i] = 1.0
_SKEW = _SKEW.reshape(3, 9)


def _axis_jacobian(robot: Robot, W: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Per-axis Jacobian columns (6, m) from the joint frames W and the tool pose T."""
    c = robot._compiled  # type: ignore[attr-defined]
    m = len(W)
    z = W[:, :3, 2]
    r = T[:3, 3] - W[:, :3, 3]
    J = np.empty((6, m))
    # z × r for every axis at once: [z]x r as one batched matrix-vector product.
    np.matmul((z @ _SKEW).reshape(m, 3, 3), r[:, :, None], out=J[:3].T[:, :, None])
    J[3:] = z.T
    if not c.all_revolute:
        pri = c.prismatic_index
        J[:3, pri] = z[pri].T
        J[3:, pri] = 0.0
    return J


def _jacobian_from_frames(robot: Robot, W: np.ndarray, T: np.ndarray) -> np.ndarray:
    c = robot._compiled  # type: ignore[attr-defined]
    J = _axis_jacobian(robot, W, T)
    return J if c.simple else J @ c.selection


# -------------------------------------------------------------------- batched
def _lin(terms: list[tuple[float, np.ndarray]]) -> np.ndarray | float:
    """Σ coefficient · array, skipping zero coefficients and multiplications by ±1.

    Returns the input array itself (no copy) for a single unit term: arrays
    are never modified in place, so sharing is safe.
    """
    out = None
    for coef, arr in terms:
        if abs(coef) < 1e-15:
            continue
        if out is None:
            out = arr if coef == 1.0 else -arr if coef == -1.0 else coef * arr
        elif coef == 1.0:
            out = out + arr
        elif coef == -1.0:
            out = out - arr
        else:
            out = out + coef * arr
    return 0.0 if out is None else out


def _apply_fixed(cols: list, p, F: np.ndarray) -> tuple[list, object]:
    """(R, p) · F for a constant 4×4 F, with R given as its three columns (3, N)."""
    new_cols = [_lin([(F[k, j], cols[k]) for k in range(3)]) for j in range(3)]
    new_p = (
        _lin([(1.0, p)] + [(F[k, 3], cols[k]) for k in range(3)])
        if not np.isscalar(p)
        else (_lin([(F[k, 3], cols[k]) for k in range(3)]) + p)
    )
    return new_cols, new_p


def _chain_batch(robot: Robot, q: np.ndarray, want_jacobian: bool):
    """Component-wise chain over a chunk. Returns T (N,4,4) and, if asked, J (N,6,n)."""
    c = robot._compiled  # type: ignore[attr-defined]
    N = q.shape[0]
    m = len(c.offset)
    qa = (q if c.simple else q[:, c.index] * c.multiplier) + c.offset  # (N, m)
    F0 = c.fixed[0]
    ones = np.ones((3, N))
    # Rotation columns (3, N) and position (3, N) of the running frame.
    cols = [F0[:3, j, None] * ones for j in range(3)]
    p = F0[:3, 3, None] * ones
    zs, ps = [], []
    qa_t = qa.T  # (m, N)
    cosv = np.cos(qa_t)
    sinv = np.sin(qa_t)
    for k in range(m):
        zs.append(cols[2])
        ps.append(p)
        if c.revolute[k]:
            ck, sk = cosv[k], sinv[k]
            c0, c1 = cols[0], cols[1]
            cols = [ck * c0 + sk * c1, ck * c1 - sk * c0, cols[2]]
        else:
            p = p + qa_t[k] * cols[2]
        cols, p = _apply_fixed(cols, p, c.fixed[k + 1])
    T = np.zeros((N, 4, 4))
    T[:, :3, 0] = cols[0].T
    T[:, :3, 1] = cols[1].T
    T[:, :3, 2] = cols[2].T
    T[:, :3, 3] = p.T
    T[:, 3, 3] = 1.0
    if not want_jacobian:
        return T, None
    Z = np.stack(zs)  # (m, 3, N)
    R = p[None] - np.stack(ps)  # (m, 3, N)
    Jc = np.empty((6, m, N))
    rev = c.revolute[:, None]
    pri = c.prismatic[:, None]
    Jc[0] = (Z[:, 1] * R[:, 2] - Z[:, 2] * R[:, 1]) * rev + Z[:, 0] * pri
    Jc[1] = (Z[:, 2] * R[:, 0] - Z[:, 0] * R[:, 2]) * rev + Z[:, 1] * pri
    Jc[2] = (Z[:, 0] * R[:, 1] - Z[:, 1] * R[:, 0]) * rev + Z[:, 2] * pri
    Jc[3:] = Z.transpose(1, 0, 2) * rev
    if c.simple:
        J = Jc.transpose(2, 0, 1)
    else:
        J = np.einsum("imN,mn->Nin", Jc, c.selection)
    return T, J


def _batched(robot: Robot, q: np.ndarray, want_jacobian: bool):
    N = q.shape[0]
    T = np.empty((N, 4, 4))
    J = np.empty((N, 6, robot.dof)) if want_jacobian else None
    for s in range(0, N, _CHUNK):
        Tc, Jc = _chain_batch(robot, q[s : s + _CHUNK], want_jacobian)
        T[s : s + _CHUNK] = Tc
        if want_jacobian:
            J[s : s + _CHUNK] = Jc
    return T, J


# --------------------------------------------------------------------- public
def fk(robot: Robot, q: object) -> np.ndarray:
    """Forward kinematics: the tool pose in the base frame.

    Args:
        robot: The robot.
        q: Configuration, shape (n,) or (N, n) [rad | m].

    Returns:
        ``T_base_tool``, shape (4, 4) or (N, 4, 4).

    Example:
        A 2R planar arm with unit links, elbow at 90°: the tool is at (1, 1, 0).

        >>> r = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)] * 2)
        >>> bool(np.allclose(fk(r, [0.0, np.pi / 2])[:3, 3], [1.0, 1.0, 0.0]))
        True
    """
    q = as_configuration(robot, q)
    if q.ndim == 1:
        return _chain_single(robot, q)[1]
    return _batched(robot, q, want_jacobian=False)[0]


def joint_frames(robot: Robot, q: object) -> np.ndarray:
    """Frames of every moving axis, ``T_base_joint`` (m, 4, 4), for one configuration.

    Axis k moves about (revolute) or along (prismatic) the z axis of frame k;
    its origin lies on the axis. For a DH robot in the standard convention,
    frame k has the origin and z axis of the course's frame k-1 (z_{k-1}).
    """
    q = as_configuration(robot, q)
    if q.ndim != 1:
        raise ConfigurationError("joint_frames takes one configuration of shape (n,)")
    return _chain_single(robot, q)[0]


def link_frames(robot: Robot, q: object) -> np.ndarray:
    """Link frames ``T_base_link`` (m + 2, 4, 4): frame 0, the link frame of every axis, the tool.

    For a DH robot these are the DH frames 0 … n of its convention, then the tool frame.
    """
    q = as_configuration(robot, q)
    if q.ndim != 1:
        raise ConfigurationError("link_frames takes one configuration of shape (n,)")
    W, T = _chain_single(robot, q)
    out = np.empty((len(robot.axes) + 2, 4, 4))
    out[0] = robot.base
    for k, ax in enumerate(robot.axes):
        qa = ax.multiplier * q[ax.joint_index] + ax.offset
        M = np.eye(4)
        if ax.kind == "revolute":
            cq, sq = np.cos(qa), np.sin(qa)
            M[:2, :2] = [[cq, -sq], [sq, cq]]
        else:
            M[2, 3] = qa
        out[k + 1] = W[k] @ M @ ax.T_joint_child
    out[-1] = T
    return out


def jacobian(robot: Robot, q: object, frame: Frame = "base") -> np.ndarray:
    """Geometric Jacobian J(q), shape (6, n) or (N, 6, n).

    Rows are [v; ω]: v [m/s] is the velocity of the tool-frame origin and ω
    [rad/s] the angular velocity of the tool, per unit joint rate. Column i
    is z × (p_tool − p_i), z for a revolute joint i (Whitney's columns) and
    (z, 0) for a prismatic one.

    Args:
        robot: The robot.
        q: Configuration, shape (n,) or (N, n).
        frame: ``"base"``: components in base axes; ``"tool"``: the same twist
            in tool axes, J_tool = blockdiag(Rᵀ, Rᵀ) · J_base with R = R_base_tool.

    Example:
        A 2R planar arm with unit links at q = 0: the tool at (2, 0, 0) moves along +y.

        >>> r = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)] * 2)
        >>> bool(np.allclose(jacobian(r, [0.0, 0.0])[:2], [[0.0, 0.0], [2.0, 1.0]]))
        True
    """
    if frame not in ("base", "tool"):
        raise ValueError(f"frame must be 'base' or 'tool', got {frame!r}")
    q = as_configuration(robot, q)
    if q.ndim == 1:
        W, T = _chain_single(robot, q)
        J = _jacobian_from_frames(robot, W, T)
        if frame == "tool":
            Rt = T[:3, :3].T
            J = np.vstack([Rt @ J[:3], Rt @ J[3:]])
        return J
    T, J = _batched(robot, q, want_jacobian=True)
    if frame == "tool":
        Rt = T[:, :3, :3].transpose(0, 2, 1)
        J = np.concatenate([Rt @ J[:, :3], Rt @ J[:, 3:]], axis=1)
    return J


def jacobian_dot(robot: Robot, q: object, qd: object, frame: Frame = "base") -> np.ndarray:
    """Time derivative J̇(q, q̇) of the base-frame geometric Jacobian, shape (6, n).

    Used in the acceleration mapping  [a; α] = J q̈ + J̇ q̇  (a = acceleration of
    the tool-frame origin). Computed analytically from the joint axes:
    ż_i = ω_i × z_i, ṗ_i = v_i, with ω_i, v_i the velocities of joint frame i.

    Args:
        robot: The robot.
        q: Configuration (n,).
        qd: Joint rates (n,) [rad/s | m/s].
        frame: Only ``"base"`` is supported (the derivative of a rotated
            Jacobian mixes in Ṙ; use the base frame and rotate results).
    """
    if frame != "base":
        raise ValueError("jacobian_dot is defined for frame='base' only")
    q = as_configuration(robot, q)
    qd = as_configuration(robot, qd)
    if q.ndim != 1 or qd.ndim != 1:
        raise ConfigurationError("jacobian_dot takes one configuration q (n,) and rates qd (n,)")
    c = robot._compiled  # type: ignore[attr-defined]
    W, T = _chain_single(robot, q)
    A = _axis_jacobian(robot, W, T)  # (6, m)
    z, p = W[:, :3, 2], W[:, :3, 3]
    rate = c.multiplier * qd[c.index]  # rate of every axis
    rz = (rate * c.revolute)[:, None] * z
    # Angular velocity ω_k and origin velocity v_k of joint frame k (moved only by axes before k):
    # ω_k = Σ_{j<k} rate_j z_j,  v_k = Σ_{j<k} rate_j z_j × (p_k − p_j)  (+ rate_j z_j if prismatic).
    omega = np.cumsum(rz, axis=0) - rz
    cross_zp = np.cross(rz, p)
    slide = (rate * c.prismatic)[:, None] * z
    vel = np.cross(omega, p) - (np.cumsum(cross_zp, axis=0) - cross_zp) + (np.cumsum(slide, axis=0) - slide)
    v_tool = A[:3] @ rate
    zd = np.cross(omega, z)
    rev = c.revolute[:, None]
    Jd = np.empty((6, len(z)))
    Jd[:3] = (rev * (np.cross(zd, T[:3, 3] - p) + np.cross(z, v_tool - vel)) + c.prismatic[:, None] * zd).T
    Jd[3:] = (rev * zd).T
    return Jd if c.simple else Jd @ c.selection
