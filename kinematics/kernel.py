"""The numeric kernels behind :mod:`kinematics.numeric`: per-robot precomputed arrays and the
single and batched chain evaluations.

:func:`kernel` returns a robot's :class:`Kernel` (built on first use, cached while the robot
lives: the robot is immutable, so it never goes stale, and the cache holds the robot weakly).
The functions here take already-checked input (``q`` from
:func:`kinematics.numeric.as_configuration`); use the public functions of
:mod:`kinematics.numeric` instead.
"""

from __future__ import annotations

import functools
import weakref
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .compiled import MAX_AXES, Chain, Compiled
from .conventions import FloatArray
from .errors import RobotDefinitionError
from .model import Robot
from .validation import MAX_ANGLE, MAX_LENGTH, show

__all__ = [
    "Kernel",
    "kernel",
    "chain_single",
    "chain_scan",
    "single_jacobian",
    "frames_jacobian",
    "single_fk",
    "axis_jacobian",
    "jacobian_from_frames",
    "batched_fk",
    "chain_batch",
    "batch_scan",
    "batch_scan_rates",
    "chain_batch_rates",
    "batched_jacobian",
]

_CHUNK = 4096  # configurations per chunk in batched kernels (keeps working arrays in cache)


@dataclass(frozen=True, eq=False)
class Kernel:
    """Arrays precomputed once per robot for the numeric kernels (see :func:`kernel`).

    ``fixed`` is :meth:`Robot.fixed_transforms`: T_base_tool = fixed[0] · M_1 · fixed[1] ⋯ M_m · fixed[m].
    """

    fixed: FloatArray  # (m+1, 4, 4)
    index: NDArray[np.intp]  # (m,) joint index of each axis
    multiplier: FloatArray  # (m,)
    offset: FloatArray  # (m,)
    revolute: FloatArray  # (m,) float 1.0/0.0
    prismatic: FloatArray  # (m,) float
    simple: bool  # one axis per joint, in order, multiplier 1
    selection: FloatArray  # (m, n): column k of J = Σ_axes selection[axis, k] · contribution
    all_revolute: bool
    prismatic_index: NDArray[np.intp]  # (p,) indices of prismatic axes
    rz_cos: FloatArray  # (m, 4, 4): Rz(θ) F_k = cos θ · rz_cos + sin θ · rz_sin + rz_const
    rz_sin: FloatArray
    rz_const: FloatArray
    tz_lin: FloatArray  # (m, 4, 4): Tz(d) F_k = F_k + d · tz_lin
    bound: FloatArray  # (n,) largest accepted |q| per joint: MAX_ANGLE [rad] or MAX_LENGTH [m]
    compiled: Compiled | None  # generated straight-line code (None: a chain over MAX_AXES axes)

    def __post_init__(self) -> None:
        for value in vars(self).values():
            if isinstance(value, np.ndarray):
                value.flags.writeable = False

    @staticmethod
    def build(robot: Robot) -> Kernel:
        m, n = len(robot.axes), robot.dof
        fixed = robot.fixed_transforms()
        index = np.array([ax.joint_index for ax in robot.axes], dtype=int)
        mult = np.array([ax.multiplier for ax in robot.axes])
        rev = np.array([1.0 if ax.kind == "revolute" else 0.0 for ax in robot.axes])
        sel = np.zeros((m, n))
        sel[np.arange(m), index] = mult
        simple = m == n and bool(np.all(index == np.arange(n))) and bool(np.all(mult == 1.0))
        offset = np.array([ax.offset for ax in robot.axes])
        pri_idx = np.flatnonzero(rev == 0.0)
        F = fixed[1:]
        Dc, Ds, E, Dz = np.diag([1.0, 1, 0, 0]), np.zeros((4, 4)), np.diag([0.0, 0, 1, 1]), np.zeros((4, 4))
        Ds[0, 1], Ds[1, 0], Dz[2, 3] = -1.0, 1.0, 1.0
        bound = np.array([MAX_ANGLE if j.kind == "revolute" else MAX_LENGTH for j in robot.joints])
        return Kernel(
            fixed=fixed,
            index=index,
            multiplier=mult,
            offset=offset,
            revolute=rev,
            prismatic=1.0 - rev,
            simple=simple,
            selection=sel,
            all_revolute=len(pri_idx) == 0,
            prismatic_index=pri_idx,
            rz_cos=Dc @ F,
            rz_sin=Ds @ F,
            rz_const=E @ F,
            tz_lin=Dz @ F,
            bound=bound,
            compiled=None
            if m > MAX_AXES
            else Compiled(
                Chain(
                    fixed=fixed.copy(),
                    base=np.array(robot.base, dtype=float),
                    child=np.array([ax.T_joint_child for ax in robot.axes], dtype=float).reshape(m, 4, 4),
                    index=tuple(int(i) for i in index),
                    multiplier=tuple(float(x) for x in mult),
                    offset=tuple(float(x) for x in offset),
                    revolute=tuple(ax.kind == "revolute" for ax in robot.axes),
                    dof=n,
                )
            ),
        )


# id(robot) -> (weak reference to the robot, its kernel). Faster to query than a
# WeakKeyDictionary (this sits on every call); the reference's callback drops the entry when the
# robot is collected, before its id can be reused, and the identity check guards the rest.
_KERNELS: dict[int, tuple[weakref.ref[Robot], Kernel]] = {}


def kernel(robot: Robot) -> Kernel:
    """The precomputed arrays of ``robot``, built on first use and kept while the robot lives.

    The robot is immutable, so they never go stale; the cache holds the robot weakly.

    Raises:
        RobotDefinitionError: ``robot`` is not a :class:`~kinematics.model.Robot`.
    """
    entry = _KERNELS.get(id(robot))
    if entry is not None and entry[0]() is robot:
        return entry[1]
    if not isinstance(robot, Robot):
        raise RobotDefinitionError(f"expected a kinematics.Robot, got {show(robot)}")
    built = Kernel.build(robot)
    key = id(robot)
    _KERNELS[key] = (weakref.ref(robot, functools.partial(_forget, key)), built)
    return built


def _forget(key: int, ref: weakref.ref[Robot]) -> None:
    """Drop the kernel of a collected robot (unless the entry was replaced meanwhile)."""
    entry = _KERNELS.get(key)
    if entry is not None and entry[0] is ref:
        del _KERNELS[key]


def chain_single(c: Kernel, q: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Joint frames T_base_joint (m, 4, 4) (before each axis moves) and T_base_tool."""
    if c.compiled is None:
        return chain_scan(c, q)
    T, W = c.compiled.single(q, "TW")
    return W, T


def single_fk(c: Kernel, q: FloatArray) -> FloatArray:
    """T_base_tool (4, 4) of one configuration."""
    if c.compiled is None:
        return chain_scan(c, q)[1]
    return c.compiled.single(q, "T")[0]


def single_jacobian(c: Kernel, q: FloatArray) -> tuple[FloatArray, FloatArray]:
    """T_base_tool (4, 4) and the base-frame J (6, n) of one configuration."""
    if c.compiled is None:
        W, T = chain_scan(c, q)
        return T, jacobian_from_frames(c, W, T)
    T, J = c.compiled.single(q, "TJ")
    return T, J


def frames_jacobian(c: Kernel, q: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray] | None:
    """Joint frames (m, 4, 4), link frames (m + 2, 4, 4) and the base-frame J (6, n) of one
    configuration by the generated code (None for a chain without it)."""
    if c.compiled is None:
        return None
    _, W, L, J = c.compiled.single(q, "TWLJ")
    return W, L, J


def chain_scan(c: Kernel, q: FloatArray) -> tuple[FloatArray, FloatArray]:
    """:func:`chain_single` by NumPy stack operations (the path of chains over MAX_AXES axes, and
    the reference the generated code is tested against)."""
    qa = q if c.simple else q[c.index] * c.multiplier
    qa = qa + c.offset
    # Rz(θ) · F = cos θ · (Dc F) + sin θ · (Ds F) + (E F), precomputed per axis, so that the
    # moved-and-fixed transform of every axis comes from a few whole-stack operations. Sine and
    # cosine come from the same argument, which NumPy reduces modulo 2π accurately (tested against
    # an exact reduction), so the rotation stays orthonormal for any |θ|; forming sin θ as
    # cos(θ − π/2) would not, once θ − π/2 rounds (‖RᵀR − I‖ reached 1.5 at |θ| ~ 1e16).
    th = qa if c.all_revolute else qa * c.revolute
    P = np.cos(th)[:, None, None] * c.rz_cos + np.sin(th)[:, None, None] * c.rz_sin + c.rz_const
    if not c.all_revolute:
        P += (qa * c.prismatic)[:, None, None] * c.tz_lin
    # Prefix products A_0 · A_1 ⋯ A_k by a parallel scan: log2(m + 1) stacked matmuls.
    A = np.concatenate((c.fixed[:1], P))
    step = 1
    while step < len(A):
        A[step:] = np.matmul(A[:-step], A[step:])
        step *= 2
    return A[:-1], A[-1]


def _levi_civita_map() -> FloatArray:
    """The Levi-Civita tensor as a (3, 9) map: (z @ map).reshape(3, 3) is the cross-product matrix [z]×."""
    eps = np.zeros((3, 3, 3))
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        eps[k, i, j] = -1.0
        eps[k, j, i] = 1.0
    return eps.reshape(3, 9)


_SKEW = _levi_civita_map()


def axis_jacobian(c: Kernel, W: FloatArray, T: FloatArray) -> FloatArray:
    """Per-axis Jacobian columns (6, m) from the joint frames W and the tool pose T."""
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


def jacobian_from_frames(c: Kernel, W: FloatArray, T: FloatArray) -> FloatArray:
    """The geometric Jacobian (6, n) from the joint frames W and the tool pose T (mimic axes summed)."""
    J = axis_jacobian(c, W, T)
    return J if c.simple else J @ c.selection


def _lin(terms: list[tuple[float, FloatArray]]) -> FloatArray:
    """Σ coefficient · array, skipping zero coefficients and multiplications by ±1.

    Returns the input array itself (no copy) for a single unit term: arrays
    are never modified in place, so sharing is safe. Zeros if every coefficient is zero.
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
    return np.zeros_like(terms[0][1]) if out is None else out


def _apply_fixed(cols: list[FloatArray], p: FloatArray, F: FloatArray) -> tuple[list[FloatArray], FloatArray]:
    """(R, p) · F for a constant 4×4 F, with R given as its three columns (3, N) and p (3, N)."""
    new_cols = [_lin([(F[k, j], cols[k]) for k in range(3)]) for j in range(3)]
    new_p = _lin([(1.0, p)] + [(F[k, 3], cols[k]) for k in range(3)])
    return new_cols, new_p


def chain_batch(c: Kernel, q: FloatArray, want_jacobian: bool) -> tuple[FloatArray, FloatArray | None]:
    """T (N, 4, 4) and, if asked, J (N, 6, n) of one chunk q (N, n), by the generated code."""
    if c.compiled is None:
        return batch_scan(c, q, want_jacobian)
    return c.compiled.batch(q, want_jacobian)


def chain_batch_rates(c: Kernel, q: FloatArray, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """T (N, 4, 4), J (N, 6, n) and J̇ (N, 6, n) of one chunk q (N, n) at joint rates u (N, n), by the
    generated code (the NumPy scan for a chain without it)."""
    if c.compiled is None:
        return batch_scan_rates(c, q, u)
    return c.compiled.batch_rates(q, u)


def batch_scan(c: Kernel, q: FloatArray, want_jacobian: bool) -> tuple[FloatArray, FloatArray | None]:
    """Component-wise chain over a chunk (the path of chains over MAX_AXES axes, and the reference
    the generated code is tested against). Returns T (N,4,4) and, if asked, J (N,6,n)."""
    T, Z, P, p = _scan_axes(c, q)
    if not want_jacobian:
        return T, None
    return T, _per_joint(c, _columns(c, Z, p[None] - P))


def batch_scan_rates(c: Kernel, q: FloatArray, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """T (N,4,4), J (N,6,n) and J̇ (N,6,n) of a chunk q (N, n) at joint rates u (N, n) by NumPy
    operations over all axes at once (the path of chains over MAX_AXES axes, and the reference the
    generated J̇ is tested against); the derivation is that of ``compiled._axis_columns_dot``."""
    T, Z, P, p = _scan_axes(c, q)
    R = p[None] - P  # (m, 3, N)
    A = _columns(c, Z, R)  # (6, m, N)
    rate = (u if c.simple else u[:, c.index] * c.multiplier).T  # (m, N)
    rz = (rate * c.revolute[:, None])[:, None] * Z  # (m, 3, N)
    omega = np.cumsum(rz, axis=0) - rz
    moved = (rate[None] * A[:3]).transpose(1, 0, 2)  # (m, 3, N): ṙ_j v_j
    after = np.cumsum(moved[::-1], axis=0)[::-1]  # Σ_{j≥k}
    zd = np.cross(omega, Z, axis=1)
    rel = np.cross(omega, R, axis=1) + after
    dv = np.cross(zd, R, axis=1) + np.cross(Z, rel, axis=1)
    rev, pri = c.revolute[:, None, None], c.prismatic[:, None, None]
    D = np.empty_like(A)
    D[:3] = (dv * rev + zd * pri).transpose(1, 0, 2)
    D[3:] = (zd * rev).transpose(1, 0, 2)
    return T, _per_joint(c, A), _per_joint(c, D)


def _scan_axes(c: Kernel, q: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """T (N,4,4), the axes z_k (m,3,N), the joint-frame origins p_k (m,3,N) and the tool's p (3,N)."""
    N = q.shape[0]
    m = len(c.offset)
    qa = (q if c.simple else q[:, c.index] * c.multiplier) + c.offset  # (N, m)
    F0 = c.fixed[0]
    ones = np.ones((3, N))
    # Rotation columns (3, N) and position (3, N) of the running frame.
    cols = [F0[:3, j, None] * ones for j in range(3)]
    p = F0[:3, 3, None] * ones
    zs: list[FloatArray] = []
    ps: list[FloatArray] = []
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
    empty = np.empty((0, 3, N))
    return T, np.stack(zs) if zs else empty, np.stack(ps) if ps else empty, p


def _columns(c: Kernel, Z: FloatArray, R: FloatArray) -> FloatArray:
    """Whitney's columns (6, m, N) of every axis from the axes Z and r = p_tool − p_k, (m, 3, N)."""
    Jc: FloatArray = np.empty((6, Z.shape[0], Z.shape[2]))
    rev = c.revolute[:, None]
    pri = c.prismatic[:, None]
    Jc[0] = (Z[:, 1] * R[:, 2] - Z[:, 2] * R[:, 1]) * rev + Z[:, 0] * pri
    Jc[1] = (Z[:, 2] * R[:, 0] - Z[:, 0] * R[:, 2]) * rev + Z[:, 1] * pri
    Jc[2] = (Z[:, 0] * R[:, 1] - Z[:, 1] * R[:, 0]) * rev + Z[:, 2] * pri
    Jc[3:] = Z.transpose(1, 0, 2) * rev
    return Jc


def _per_joint(c: Kernel, Jc: FloatArray) -> FloatArray:
    """(N, 6, n) from axis columns (6, m, N): mimic axes summed per joint, times their multipliers."""
    out: FloatArray = Jc.transpose(2, 0, 1) if c.simple else np.einsum("imN,mn->Nin", Jc, c.selection)
    return out


def batched_fk(c: Kernel, q: FloatArray) -> FloatArray:
    """T_base_tool (N, 4, 4) for a batch q (N, n), chunk by chunk."""
    T = np.empty((q.shape[0], 4, 4))
    for s in range(0, q.shape[0], _CHUNK):
        T[s : s + _CHUNK] = chain_batch(c, q[s : s + _CHUNK], want_jacobian=False)[0]
    return T


def batched_jacobian(c: Kernel, q: FloatArray) -> tuple[FloatArray, FloatArray]:
    """T_base_tool (N, 4, 4) and the base-frame J (N, 6, n) for a batch q (N, n), chunk by chunk."""
    N = q.shape[0]
    T = np.empty((N, 4, 4))
    J = np.empty((N, 6, c.selection.shape[1]))
    for s in range(0, N, _CHUNK):
        Tc, Jc = chain_batch(c, q[s : s + _CHUNK], want_jacobian=True)
        T[s : s + _CHUNK] = Tc
        if Jc is not None:
            J[s : s + _CHUNK] = Jc
    return T, J
