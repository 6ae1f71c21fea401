"""Numeric forward kinematics and geometric Jacobians (NumPy).

Every function takes an immutable :class:`~kinematics.model.Robot` and a
configuration ``q``: shape (n,) for one configuration or (N, n) for a batch.
Batches are vectorised over N (no Python loop over configurations) and are
processed in cache-sized chunks (the kernels are in :mod:`kinematics.kernel`).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from .conventions import FRAMES, FloatArray, Frame
from .errors import ConfigurationError, OptionError
from .kernel import (
    Kernel,
    axis_jacobian,
    batched_fk,
    batched_jacobian,
    chain_batch_rates,
    chain_single,
    frames_jacobian,
    jacobian_from_frames,
    kernel,
    single_fk,
    single_jacobian,
)
from .model import Robot
from .validation import MAX_ANGLE, MAX_LENGTH, show

__all__ = [
    "fk",
    "joint_frames",
    "link_frames",
    "chain_frames",
    "frames_and_jacobian",
    "jacobian",
    "jacobian_dot_alone",
    "jacobian_dot",
    "as_configuration",
    "check_frame",
    "Frame",
    "FRAMES",
]

_FAST_BOUND = min(MAX_ANGLE, MAX_LENGTH)
_MAX_ABS = np.maximum.reduce
_FLOAT = np.dtype(np.float64)
_CHUNK = 4096  # configurations per chunk of a batched J̇


def check_frame(frame: object) -> Frame:
    """``frame`` if it is one of :data:`FRAMES`, else an OptionError listing them."""
    if isinstance(frame, str) and frame in FRAMES:
        return frame
    raise OptionError(f"frame must be one of 'base', 'tool' (the frame of J's rows), got {show(frame)}")


_KINDS = {
    "b": "bools",
    "c": "complex numbers",
    "U": "strings",
    "S": "bytes",
    "O": "Python objects",
    "V": "records",
}


def as_configuration(robot: Robot, q: object, what: str = "q") -> FloatArray:
    """Return ``q`` as a float array of shape (n,) or (N, n), or raise ConfigurationError.

    Accepted: ints and floats (lists, tuples, NumPy arrays of any int or float type). Refused,
    each with a message naming the problem: strings, bytes, bools, complex numbers, object
    arrays (``None``, integers beyond float range, mixed types), ragged lists, the wrong shape,
    NaN, ±inf, and values beyond what the model accepts (|q| ≤ 1e18 rad for a revolute joint,
    where angles are only meaningful modulo 2π; |q| ≤ 1e15 m for a prismatic one).

    Args:
        robot: The robot (defines n = ``robot.dof``).
        q: Joint values [rad] for revolute, [m] for prismatic joints.
        what: Name used in messages (``"qd"`` for joint rates).
    """
    return _configuration(robot, kernel(robot), q, what)


def _configuration(robot: Robot, c: Kernel, q: object, what: str = "q") -> FloatArray:
    """:func:`as_configuration` with the robot's kernel already at hand."""
    # Hot path (one float64 configuration, an app redrawing): Σ|q| ≤ min(bound) puts every value
    # within its bound; NaN and ±inf make the sum fail the test and take the full checks below.
    if type(q) is np.ndarray and q.dtype is _FLOAT and q.shape == (robot.dof,):
        if sum(map(abs, q.tolist())) <= _FAST_BOUND:
            return q
    bound = c.bound
    try:
        a = np.asarray(q)
    except (TypeError, ValueError, OverflowError):
        raise ConfigurationError(f"{what} must be an array of numbers, got {show(q)}") from None
    if a.dtype.kind not in "iuf":
        raise ConfigurationError(
            f"{what} must hold ints or floats, got {_KINDS.get(a.dtype.kind, str(a.dtype))}: {show(q)}"
        )
    a = a.astype(float, copy=False)
    if a.ndim not in (1, 2) or a.shape[-1] != robot.dof:
        raise ConfigurationError(
            f"{what} has shape {a.shape}; robot {robot.name!r} expects ({robot.dof},) or (N, {robot.dof})"
        )
    # Fast path: max |q| ≤ min(bound) puts every value within its bound (NaN and ±inf fail it;
    # np.maximum propagates NaN). Only values beyond it are checked joint by joint.
    flat = a if a.ndim == 1 else a.ravel()
    if flat.size and not _MAX_ABS(np.abs(flat)) <= _FAST_BOUND and not (np.abs(a) <= bound).all():
        raise ConfigurationError(_bad_value(robot, a, bound, what))
    return a


def _bad_value(robot: Robot, a: FloatArray, bound: FloatArray, what: str) -> str:
    """The message for the first value of ``a`` that is not finite or is out of range."""
    bad = ~(np.abs(a) <= bound)
    i = int(np.argwhere(bad)[0][-1])
    v = float(a[..., i][bad[..., i]][0])
    joint = robot.joints[i]
    if not math.isfinite(v):
        return (
            f"{what} contains NaN or infinity (joint {joint.name!r}: {v}); every joint value must be finite"
        )
    unit = "rad" if joint.kind == "revolute" else "m"
    expected = f"expected |value| ≤ {bound[i]:g} {unit}"
    return f"{what}: joint {joint.name!r} value {v:g} {unit} is out of range; {expected}"


# --------------------------------------------------------------------- public
def fk(robot: Robot, q: npt.ArrayLike) -> FloatArray:
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
    c = kernel(robot)
    q = _configuration(robot, c, q)
    if q.ndim == 1:
        return single_fk(c, q)
    return batched_fk(c, q)


def joint_frames(robot: Robot, q: npt.ArrayLike) -> FloatArray:
    """Frames of every moving axis, ``T_base_joint`` (m, 4, 4), for one configuration.

    Axis k moves about (revolute) or along (prismatic) the z axis of frame k;
    its origin lies on the axis. For a DH robot in the standard convention,
    frame k has the origin and z axis of the course's frame k-1 (z_{k-1}).
    """
    return chain_frames(robot, q)[0]


def chain_frames(robot: Robot, q: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The joint frames ``T_base_joint`` (m, 4, 4) and the tool pose ``T_base_tool`` (4, 4) at once.

    One evaluation of the chain for one configuration (n,): what :func:`joint_frames` and
    :func:`fk` return.
    """
    c = kernel(robot)
    qc = _configuration(robot, c, q)
    if qc.ndim != 1:
        raise ConfigurationError(
            f"one configuration of shape ({robot.dof},) is expected here, got {qc.shape}"
        )
    return chain_single(c, qc)


def link_frames(robot: Robot, q: npt.ArrayLike) -> FloatArray:
    """Link frames ``T_base_link`` (m + 2, 4, 4): frame 0, the link frame of every axis, the tool.

    For a DH robot these are the DH frames 0 … n of its convention, then the tool frame.
    """
    c, qc = _one(robot, q, "link_frames")
    fast = frames_jacobian(c, qc)
    if fast is not None:
        return fast[1]
    W, T = chain_single(c, qc)
    return _link_frames(robot, qc, W, T)


def frames_and_jacobian(robot: Robot, q: npt.ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """:func:`link_frames`, :func:`joint_frames` and the base-frame :func:`jacobian` of one
    configuration (n,) from one evaluation of the chain (an app redrawing on every move needs all three).
    """
    c, qc = _one(robot, q, "frames_and_jacobian")
    fast = frames_jacobian(c, qc)
    if fast is not None:
        W, L, J = fast
        return L, W, J
    W, T = chain_single(c, qc)
    return _link_frames(robot, qc, W, T), W, jacobian_from_frames(c, W, T)


def _one(robot: Robot, q: object, who: str) -> tuple[Kernel, FloatArray]:
    """The kernel and the checked configuration (n,); ``who`` names the caller when ``q`` is a batch."""
    c = kernel(robot)
    qc = _configuration(robot, c, q)
    if qc.ndim != 1:
        raise ConfigurationError(f"{who} takes one configuration of shape ({robot.dof},), got {qc.shape}")
    return c, qc


def _link_frames(robot: Robot, q: FloatArray, W: FloatArray, T: FloatArray) -> FloatArray:
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


def jacobian(robot: Robot, q: npt.ArrayLike, frame: Frame = "base") -> FloatArray:
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
    frame = check_frame(frame)
    c = kernel(robot)
    q = _configuration(robot, c, q)
    if q.ndim == 1:
        T, J = single_jacobian(c, q)
        if frame == "tool":
            Rt = T[:3, :3].T
            J = np.vstack([Rt @ J[:3], Rt @ J[3:]])
        return J
    T, J = batched_jacobian(c, q)
    if frame == "tool":
        Rt = T[:, :3, :3].transpose(0, 2, 1)
        J = np.concatenate([Rt @ J[:, :3], Rt @ J[:, 3:]], axis=1)
    return J


def jacobian_dot(robot: Robot, q: npt.ArrayLike, qd: npt.ArrayLike, frame: Frame = "base") -> FloatArray:
    """Time derivative J̇(q, q̇) of the base-frame geometric Jacobian, shape (6, n) or (N, 6, n).

    Used in the acceleration mapping  [a; α] = J q̈ + J̇ q̇  (a = acceleration of
    the tool-frame origin). Computed analytically from the joint axes:
    ż_i = ω_i × z_i, ṗ_i = v_i, with ω_i, v_i the velocities of joint frame i.

    Args:
        robot: The robot.
        q: Configuration (n,), or a batch (N, n) (evaluated in chunks by the generated chain code).
        qd: Joint rates [rad/s | m/s]: (n,) for one configuration; (N, n), or (n,) for all, for a batch.
        frame: Only ``"base"`` is supported (the derivative of a rotated
            Jacobian mixes in Ṙ; use the base frame and rotate results).
    """
    if check_frame(frame) != "base":
        raise OptionError("jacobian_dot is defined for frame='base' only (rotate the result for tool axes)")
    c = kernel(robot)
    q = _configuration(robot, c, q)
    qd = _configuration(robot, c, qd, "qd")
    if q.ndim == 2 and (qd.ndim == 1 or qd.shape == q.shape):
        return _batched_jacobian_dot(c, q, np.broadcast_to(qd, q.shape))
    if q.ndim != 1 or qd.ndim != 1:
        raise ConfigurationError(
            f"jacobian_dot takes q (n,) and qd (n,), or a batch q (N, n) and qd (N, n) or (n,); "
            f"got q {q.shape} and qd {qd.shape}"
        )
    if c.compiled is not None:
        return c.compiled.single_rates(q, qd)[2]
    return _jacobian_dot_scan(c, q, qd)


def jacobian_dot_alone(robot: Robot, q: npt.ArrayLike, qd: npt.ArrayLike) -> FloatArray:
    """The course's per-joint J̇ᵢ (000, §7), column by column, shape (6, n) [m/s; rad/s per rad].

    Column i is what 000 derives for joint i moving alone: for a revolute joint
    J̇ᵢ = [⁰Rᵢ₋₁(ⁱ⁻¹ẑᵢ₋₁ × (ⁱ⁻¹ẑᵢ₋₁ × ⁱ⁻¹Pₙ)) q̇ᵢ; 0] = [zᵢ₋₁ × (zᵢ₋₁ × (pₙ − pᵢ₋₁)) q̇ᵢ; 0]
    in base axes, and 0 for a prismatic joint. It leaves out that zᵢ₋₁ turns and pₙ − pᵢ₋₁
    changes with the other joints, so it equals column i of :func:`jacobian_dot` when joint i is
    the only one moving, and Σᵢ J̇ᵢ q̇ᵢ = J̇ q̇ then; with several joints moving they differ.
    A joint driving several axes (coupled joints) sums the formula over its axes.

    Args:
        robot: The robot.
        q: One configuration (n,) [rad | m].
        qd: Joint rates (n,) [rad/s | m/s].
    """
    c = kernel(robot)
    q = _configuration(robot, c, q)
    qd = _configuration(robot, c, qd, "qd")
    if q.ndim != 1 or qd.ndim != 1:
        raise ConfigurationError(
            f"jacobian_dot_alone takes q (n,) and qd (n,); got q {q.shape} and qd {qd.shape}"
        )
    W, T = chain_single(c, q)
    z, p = W[:, :3, 2], W[:, :3, 3]
    rate = (c.multiplier * qd[c.index] * c.revolute)[:, None]  # rate of every revolute axis
    Jd = np.zeros((6, len(z)))
    Jd[:3] = (np.cross(z, np.cross(z, T[:3, 3] - p)) * rate).T
    out: FloatArray = Jd if c.simple else Jd @ c.selection
    return out


def _jacobian_dot_scan(c: Kernel, q: FloatArray, qd: FloatArray) -> FloatArray:
    """J̇ (6, n) of one configuration by NumPy operations over the axes (the path of chains without
    generated code; an independent derivation: ṗ_tool − ṗ_k from the joint-frame velocities)."""
    W, T = chain_single(c, q)
    A = axis_jacobian(c, W, T)  # (6, m)
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
    out: FloatArray = Jd if c.simple else Jd @ c.selection
    return out


def _batched_jacobian_dot(c: Kernel, q: FloatArray, qd: FloatArray) -> FloatArray:
    """J̇ (N, 6, n) of a batch, chunk by chunk."""
    Jd = np.empty((q.shape[0], 6, q.shape[1]))
    for s in range(0, q.shape[0], _CHUNK):
        Jd[s : s + _CHUNK] = chain_batch_rates(c, q[s : s + _CHUNK], qd[s : s + _CHUNK])[2]
    return Jd
