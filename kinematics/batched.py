"""Everything about a batch of configurations in one pass: tool poses, J, J̇ and the measures.

:func:`batch` evaluates, chunk by chunk, the robot's generated chain code
(:mod:`kinematics.compiled`; the NumPy scan for chains over its length) once per chunk for T, J and,
given joint rates, J̇, then one batched SVD of the measured rows for σ, w, κ and the rank. The
working memory is that of one chunk, whatever N; only the results grow with N.

Frames and conventions are those of the single-configuration functions: :func:`~kinematics.numeric.fk`
(T_base_tool), :func:`~kinematics.numeric.jacobian` and :func:`~kinematics.numeric.jacobian_dot`
in the base frame (rows [v; ω], v of the tool-frame origin), and the measures of
:func:`kinematics.analysis.measures` (σ from the SVD itself, not from J Jᵀ: as exact as the single
path near singularities).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .analysis import DEFAULT_RTOL, Part, check_rtol, condition_of, part_rows, task_rows
from .conventions import FloatArray
from .errors import ConfigurationError, OptionError
from .kernel import chain_batch, chain_batch_rates, kernel
from .model import Robot
from .numeric import as_configuration
from .validation import show

__all__ = ["Batch", "batch", "CHUNK"]

CHUNK = 4096
"""Configurations per chunk (the working arrays of one chunk stay in cache)."""


@dataclass(frozen=True, eq=False)
class Batch:
    """A batch of N configurations of an n-joint robot, evaluated in one pass.

    Attributes:
        T: (N, 4, 4) tool poses T_base_tool, as :func:`~kinematics.numeric.fk`.
        J: (N, 6, n) base-frame geometric Jacobians [v; ω], as :func:`~kinematics.numeric.jacobian`.
        Jdot: (N, 6, n) J̇(q, q̇) at the given joint rates, as :func:`~kinematics.numeric.jacobian_dot`;
            None when no rates were given.
        rows: The rows of J measured (default the robot's :func:`~kinematics.analysis.task_rows`).
        sigma: (N, k) singular values of those rows, largest first, k = min(len(rows), n).
        w: (N,) manipulability Π σᵢ (0 when the rows outnumber the joints).
        kappa: (N,) condition number σmax/σmin, ``inf`` where σmin ≤ rtol · max(σmax, 1) or the rows
            outnumber the joints (as :func:`~kinematics.analysis.condition_number`).
        rank: (N,) numerical rank: the σᵢ above rtol · max(σmax, 1).
    """

    T: FloatArray
    J: FloatArray
    Jdot: FloatArray | None
    rows: tuple[int, ...]
    sigma: FloatArray
    w: FloatArray
    kappa: FloatArray
    rank: npt.NDArray[np.intp]


def batch(
    robot: Robot,
    q: npt.ArrayLike,
    qd: npt.ArrayLike | None = None,
    *,
    rows: Part | tuple[int, ...] | None = None,
    rtol: float = DEFAULT_RTOL,
    chunk: int = CHUNK,
) -> Batch:
    """fk, J, J̇ and the measures (σ, w, κ, rank) of a batch of configurations in one pass.

    Args:
        robot: The robot (n = ``robot.dof`` joints).
        q: Configurations (N, n) [rad | m], N ≥ 1, with the checks of
            :func:`~kinematics.numeric.as_configuration` (any finite value: |q| ~ 1e16 rad stays rigid).
        qd: Joint rates [rad/s | m/s]: (N, n), one row per configuration, or (n,) for all of them;
            None (default) skips J̇.
        rows: Rows of J measured: a part (``"linear"``, ``"angular"``, ``"planar"``, ``"full"``) or
            distinct row indices 0…5; default the robot's task rows.
        rtol: Relative tolerance of κ's and the rank's zero, in [0, 1).
        chunk: Configurations evaluated at a time (int ≥ 1; the results do not depend on it).

    Raises:
        ConfigurationError: ``q`` is not a non-empty batch (N, n) of acceptable values, or ``qd`` is
            neither (N, n) nor (n,), or holds unacceptable values.
        OptionError: ``rows``, ``rtol`` or ``chunk`` is invalid.

    Example:
        A 2R planar arm with unit links: w = |sin q₂| over the rows (vx, vy).

        >>> r = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)] * 2)
        >>> b = batch(r, [[0.0, 0.5], [1.0, 1.5]], [[1.0, 0.0], [0.0, 1.0]], rows=(0, 1))
        >>> b.J.shape, b.Jdot.shape, bool(np.allclose(b.w, np.sin([0.5, 1.5])))
        ((2, 6, 2), (2, 6, 2), True)
    """
    c = kernel(robot)
    Q = as_configuration(robot, q)
    n = robot.dof
    if Q.ndim != 2:
        raise ConfigurationError(
            f"q has shape {Q.shape}; batch expects configurations (N, {n}) (one configuration: q[None])"
        )
    N = len(Q)
    if N == 0:
        raise ConfigurationError(f"q is an empty batch (0, {n}); batch expects at least one configuration")
    U = None if qd is None else _rates(robot, qd, N)
    measured = part_rows(task_rows(robot) if rows is None else rows)
    tolerance = check_rtol(rtol)
    if not (isinstance(chunk, (int, np.integer)) and not isinstance(chunk, bool) and chunk >= 1):
        raise OptionError(f"chunk must be an int ≥ 1, got {show(chunk)}")
    size = int(chunk)
    k = min(len(measured), n)
    missing = len(measured) > n
    full = measured == (0, 1, 2, 3, 4, 5)
    T, J = np.empty((N, 4, 4)), np.empty((N, 6, n))
    Jdot = None if U is None else np.empty((N, 6, n))
    sigma, w, kappa, rank = np.empty((N, k)), np.zeros(N), np.empty(N), np.empty(N, dtype=np.intp)
    for s in range(0, N, size):
        part = slice(s, s + size)
        if U is None or Jdot is None:
            Tc, Jc = chain_batch(c, Q[part], want_jacobian=True)
            assert Jc is not None
        else:
            Tc, Jc, Jdot[part] = chain_batch_rates(c, Q[part], U[part])
        T[part], J[part] = Tc, Jc
        sigma[part] = np.linalg.svd(J[part] if full else J[part][:, measured], compute_uv=False)
        sc = sigma[part]
        if not missing:
            w[part] = np.prod(sc, axis=1)
        kappa[part] = condition_of(sc, tolerance, missing)
        rank[part] = np.sum(sc > tolerance * np.maximum(sc[:, :1], 1.0), axis=1)
    return Batch(T, J, Jdot, measured, sigma, w, kappa, rank)


def _rates(robot: Robot, qd: npt.ArrayLike, N: int) -> FloatArray:
    """``qd`` as (N, n) joint rates: (N, n) as given, (n,) repeated for every configuration."""
    U = as_configuration(robot, qd, "qd")
    if U.ndim == 1:
        return np.broadcast_to(U, (N, robot.dof))
    if U.shape[0] != N:
        raise ConfigurationError(
            f"qd has shape {U.shape}; expected one row of rates per configuration of q ({N}, {robot.dof}), "
            f"or ({robot.dof},) for all of them"
        )
    return U
