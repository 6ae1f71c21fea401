"""Maps of manipulability over the workspace and over pairs of joints.

Both measures come from the eigenvalues λ₁ ≥ … ≥ λₖ of the task rows' Gram matrix J Jᵀ (k×k),
batched, which costs a fraction of a batched SVD of J:

* ``w`` = √det(J Jᵀ) = √(Πλᵢ) = Π σᵢ, Yoshikawa's manipulability [units of the rows' product];
* ``inverse_kappa`` = √(λₖ/λ₁) = σmin/σmax ∈ [0, 1] (0 singular, 1 isotropic). Squaring J
  costs precision: values below about 1e-7 are noise around 0 (fine for a colour map).

Sampling follows the limits; a joint without limits is sampled over ±π (revolute) or ±1 m
(prismatic, :data:`UNLIMITED_PRISMATIC`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .analysis import Part, part_rows, task_rows
from .conventions import FloatArray
from .errors import ConfigurationError, OptionError
from .kernel import batched_jacobian, kernel
from .model import Robot
from .numeric import as_configuration
from .validation import show

__all__ = ["Workspace", "JointMap", "workspace", "joint_map", "sampling_range", "gram_measures"]

UNLIMITED_PRISMATIC = 1.0
"""Half-range [m] sampled for a prismatic joint without limits."""
CHUNK = 2048
"""Configurations per chunk (keeps the working arrays in cache)."""


@dataclass(frozen=True, eq=False)
class Workspace:
    """Random configurations and their tool points.

    Attributes:
        q: (N, n) configurations [rad | m], uniform within :func:`sampling_range`.
        points: (N, 3) tool positions p_base_tool [m].
        w: (N,) manipulability √det(J Jᵀ) of the task rows.
        inverse_kappa: (N,) σmin/σmax of the task rows, in [0, 1].
    """

    q: FloatArray
    points: FloatArray
    w: FloatArray
    inverse_kappa: FloatArray


@dataclass(frozen=True, eq=False)
class JointMap:
    """Manipulability over joints i and j, the others held.

    Attributes:
        i, j: The joint indices (0-based).
        values_i: (resolution,) values of joint i [rad | m]; values_j likewise.
        w: (resolution, resolution); ``w[a, b]`` at q_i = values_i[a], q_j = values_j[b].
        inverse_kappa: (resolution, resolution), same layout.
    """

    i: int
    j: int
    values_i: FloatArray
    values_j: FloatArray
    w: FloatArray
    inverse_kappa: FloatArray


def sampling_range(robot: Robot) -> FloatArray:
    """(2, n) lower and upper values sampled per joint: its limits, or ±π / ±1 m without."""
    lim: FloatArray = robot.qlim.copy()
    for k, joint in enumerate(robot.joints):
        if joint.qlim is None:
            span = np.pi if joint.kind == "revolute" else UNLIMITED_PRISMATIC
            lim[:, k] = (-span, span)
    return lim


def gram_measures(J: FloatArray) -> tuple[FloatArray, FloatArray]:
    """w and σmin/σmax of a batch of task Jacobians (N, k, n) through eigvalsh of J Jᵀ."""
    N, k, n = J.shape
    if k > n:  # more rows than joints: always rank-deficient
        return np.zeros(N), np.zeros(N)
    lam = np.linalg.eigvalsh(J @ J.transpose(0, 2, 1))  # ascending
    lam = np.maximum(lam, 0.0)
    w = np.sqrt(np.prod(lam, axis=1))
    top = lam[:, -1]
    inverse = np.sqrt(np.divide(lam[:, 0], top, out=np.zeros(N), where=top > 0))
    return w, inverse


def _evaluate(robot: Robot, Q: FloatArray, rows: list[int]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Tool points, w and σmin/σmax for Q (N, n), chunk by chunk."""
    c = kernel(robot)
    N = len(Q)
    points, w, inverse = np.empty((N, 3)), np.empty(N), np.empty(N)
    full = rows == [0, 1, 2, 3, 4, 5]
    for s in range(0, N, CHUNK):
        T, J = batched_jacobian(c, Q[s : s + CHUNK])
        points[s : s + CHUNK] = T[:, :3, 3]
        w[s : s + CHUNK], inverse[s : s + CHUNK] = gram_measures(J if full else J[:, rows])
    return points, w, inverse


def _rows(robot: Robot, rows: Part | tuple[int, ...] | None) -> list[int]:
    return list(task_rows(robot) if rows is None else part_rows(rows))


def _int(x: object, what: str, low: int) -> int:
    if not (isinstance(x, (int, np.integer)) and not isinstance(x, bool) and x >= low):
        raise OptionError(f"{what} must be an int ≥ {low}, got {show(x)}")
    return int(x)


def workspace(
    robot: Robot, n: int, *, seed: int | None, rows: Part | tuple[int, ...] | None = None
) -> Workspace:
    """``n`` configurations drawn uniformly within :func:`sampling_range`, with their tool
    points and manipulability (of ``rows``, default the robot's task rows).

    Args:
        robot: The robot.
        n: Number of samples (int ≥ 0).
        seed: Seed of ``numpy.random.default_rng`` (None: fresh entropy).
        rows: Rows of J measured.
    """
    count = _int(n, "n", 0)
    chosen = _rows(robot, rows)
    try:
        rng = np.random.default_rng(seed)
    except (TypeError, ValueError):
        raise OptionError(f"seed must be an int ≥ 0 or None, got {show(seed)}") from None
    lim = sampling_range(robot)
    Q = rng.uniform(lim[0], lim[1], size=(count, robot.dof))
    points, w, inverse = _evaluate(robot, Q, chosen)
    return Workspace(Q, points, w, inverse)


def joint_map(
    robot: Robot,
    q: npt.ArrayLike,
    i: int,
    j: int,
    *,
    resolution: int = 64,
    rows: Part | tuple[int, ...] | None = None,
) -> JointMap:
    """Manipulability of ``rows`` (default the task rows) over a grid of joints i and j (each
    over :func:`sampling_range`, ``resolution`` values ends included), the others held at ``q``."""
    qa = as_configuration(robot, q)
    if qa.ndim != 1:
        raise ConfigurationError(f"q must be one configuration ({robot.dof},), got shape {qa.shape}")
    for value, what in ((i, "i"), (j, "j")):
        if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool)):
            raise OptionError(f"{what} must be a joint index 0…{robot.dof - 1}, got {show(value)}")
        if not 0 <= value < robot.dof:
            raise OptionError(f"{what} must be a joint index 0…{robot.dof - 1}, got {show(value)}")
    if i == j:
        raise OptionError(f"i and j must be two different joints, got i = j = {i}")
    res = _int(resolution, "resolution", 2)
    chosen = _rows(robot, rows)
    lim = sampling_range(robot)
    vi = np.linspace(lim[0, i], lim[1, i], res)
    vj = np.linspace(lim[0, j], lim[1, j], res)
    Q = np.repeat(qa[None], res * res, axis=0)
    Q[:, i] = np.repeat(vi, res)
    Q[:, j] = np.tile(vj, res)
    _, w, inverse = _evaluate(robot, Q, chosen)
    return JointMap(int(i), int(j), vi, vj, w.reshape(res, res), inverse.reshape(res, res))
