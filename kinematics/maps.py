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
from typing import Any

import numpy as np
import numpy.typing as npt

from .analysis import Part, part_rows, task_rows
from .conventions import FloatArray
from .errors import ConfigurationError, OptionError
from .kernel import chain_batch, kernel
from .model import Robot
from .numeric import as_configuration
from .validation import show

__all__ = [
    "Workspace",
    "JointMap",
    "Measures",
    "workspace",
    "joint_map",
    "measures",
    "measures_dask",
    "sampling_range",
    "gram_measures",
    "gram_sigma",
]

UNLIMITED_PRISMATIC = 1.0
"""Half-range [m] sampled for a prismatic joint without limits."""
CHUNK = 4096
"""Configurations per chunk: the working arrays of a batch are those of one chunk (in cache), so
the memory a map needs beyond its results is bounded by the chunk, whatever the batch's size."""


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


@dataclass(frozen=True, eq=False)
class Measures:
    """Tool points and the measures of the Jacobian's rows for a batch of configurations.

    Attributes:
        points: (N, 3) tool positions p_base_tool [m].
        sigma: (N, k) singular values of the k rows measured, largest first (from the Gram
            matrix: values below about 1e-7 of the largest are noise around 0).
        w: (N,) manipulability Π σᵢ.
        inverse_kappa: (N,) σmin/σmax in [0, 1] (κ = 1 / inverse_kappa; 0: singular).
    """

    points: FloatArray
    sigma: FloatArray
    w: FloatArray
    inverse_kappa: FloatArray


def gram_sigma(J: FloatArray) -> FloatArray:
    """Singular values (N, k), largest first, of a batch of task Jacobians (N, k, n), through
    eigvalsh of J Jᵀ (zeros beyond rank n when k > n)."""
    lam = np.linalg.eigvalsh(J @ J.transpose(0, 2, 1))  # ascending
    sigma: FloatArray = np.sqrt(np.maximum(lam[:, ::-1], 0.0))
    return sigma


def _from_sigma(sigma: FloatArray, n: int) -> tuple[FloatArray, FloatArray]:
    N, k = sigma.shape
    if k > n:  # more rows than joints: always rank-deficient
        return np.zeros(N), np.zeros(N)
    top = sigma[:, 0]
    inverse = np.divide(sigma[:, -1], top, out=np.zeros(N), where=top > 0)
    return np.prod(sigma, axis=1), inverse


def gram_measures(J: FloatArray) -> tuple[FloatArray, FloatArray]:
    """w and σmin/σmax of a batch of task Jacobians (N, k, n) through eigvalsh of J Jᵀ."""
    return _from_sigma(gram_sigma(J), J.shape[2])


def _evaluate(
    robot: Robot, Q: FloatArray, rows: list[int], chunk: int = CHUNK, keep_sigma: bool = True
) -> Measures:
    """Tool points and measures for Q (N, n), ``chunk`` configurations at a time: one pass of the
    generated chain code (T and J) and one eigvalsh per chunk, written into the results."""
    c = kernel(robot)
    N = len(Q)
    points, sigma = np.empty((N, 3)), np.empty((N if keep_sigma else 0, len(rows)))
    w, inverse = np.empty(N), np.empty(N)
    full = rows == [0, 1, 2, 3, 4, 5]
    for s in range(0, N, chunk):
        T, J = chain_batch(c, Q[s : s + chunk], want_jacobian=True)
        assert J is not None
        points[s : s + chunk] = T[:, :3, 3]
        part = gram_sigma(J if full else J[:, rows])
        if keep_sigma:
            sigma[s : s + chunk] = part
        w[s : s + chunk], inverse[s : s + chunk] = _from_sigma(part, robot.dof)
    return Measures(points, sigma, w, inverse)


def measures(
    robot: Robot, q: npt.ArrayLike, *, rows: Part | tuple[int, ...] | None = None, chunk: int = CHUNK
) -> Measures:
    """Tool points, singular values σ, manipulability w and σmin/σmax of ``rows`` (default the
    robot's task rows) for a batch q (N, n), in one pass per chunk of ``chunk`` configurations
    (the working memory is that of one chunk)."""
    Q = as_configuration(robot, q)
    if Q.ndim != 2:
        raise ConfigurationError(f"q must be a batch of configurations (N, {robot.dof}), got shape {Q.shape}")
    return _evaluate(robot, Q, _rows(robot, rows), _int(chunk, "chunk", 1))


def measures_dask(
    robot: Robot, q: Any, *, rows: Part | tuple[int, ...] | None = None, chunk: int = CHUNK
) -> Any:
    """:func:`measures` mapped over a Dask array of configurations (N, n), one task per block of
    ``chunk`` rows (the optional extra ``dask``: for sweeps larger than one machine's memory or
    cores). Returns a lazy Dask array (N, 3 + k + 2): the tool point, the k singular values, w and
    σmin/σmax of each configuration, the columns of :class:`Measures` side by side.

    Raises:
        OptionError: Dask is not installed.
    """
    try:
        import dask.array as da
    except ImportError:
        raise OptionError("measures_dask needs Dask: pip install 'dask[array]'") from None
    chosen = _rows(robot, rows)
    size = _int(chunk, "chunk", 1)
    blocks = da.asarray(q).rechunk((size, -1))
    if blocks.ndim != 2 or blocks.shape[1] != robot.dof:
        raise ConfigurationError(
            f"q must be a batch of configurations (N, {robot.dof}), got shape {blocks.shape}"
        )

    def block(part: FloatArray) -> FloatArray:
        found = _evaluate(robot, as_configuration(robot, part), chosen, size)
        return np.column_stack((found.points, found.sigma, found.w, found.inverse_kappa))

    width = 3 + len(chosen) + 2
    return blocks.map_blocks(block, chunks=(blocks.chunks[0], (width,)), dtype=float)


def _rows(robot: Robot, rows: Part | tuple[int, ...] | None) -> list[int]:
    return list(task_rows(robot) if rows is None else part_rows(rows))


def _int(x: object, what: str, low: int) -> int:
    if not (isinstance(x, (int, np.integer)) and not isinstance(x, bool) and x >= low):
        raise OptionError(f"{what} must be an int ≥ {low}, got {show(x)}")
    return int(x)


def workspace(
    robot: Robot,
    n: int,
    *,
    seed: int | None,
    rows: Part | tuple[int, ...] | None = None,
    chunk: int = CHUNK,
) -> Workspace:
    """``n`` configurations drawn uniformly within :func:`sampling_range`, with their tool
    points and manipulability (of ``rows``, default the robot's task rows).

    Args:
        robot: The robot.
        n: Number of samples (int ≥ 0).
        seed: Seed of ``numpy.random.default_rng`` (None: fresh entropy).
        rows: Rows of J measured.
        chunk: Configurations evaluated at a time (the working memory is that of one chunk; the
            results do not depend on it).
    """
    count = _int(n, "n", 0)
    size = _int(chunk, "chunk", 1)
    chosen = _rows(robot, rows)
    try:
        rng = np.random.default_rng(seed)
    except (TypeError, ValueError):
        raise OptionError(f"seed must be an int ≥ 0 or None, got {show(seed)}") from None
    lim = sampling_range(robot)
    Q = np.empty((count, robot.dof))
    for s in range(0, count, size):  # drawn chunk by chunk: the same numbers as in one draw
        Q[s : s + size] = rng.uniform(lim[0], lim[1], size=(min(size, count - s), robot.dof))
    found = _evaluate(robot, Q, chosen, size, keep_sigma=False)
    return Workspace(Q, found.points, found.w, found.inverse_kappa)


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
    found = _evaluate(robot, Q, chosen, keep_sigma=False)
    return JointMap(int(i), int(j), vi, vj, found.w.reshape(res, res), found.inverse_kappa.reshape(res, res))
