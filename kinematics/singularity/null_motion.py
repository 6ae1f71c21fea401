"""The null joint motion at a singularity: q̇ ∈ Ker J, the joints move and the tool stands still.

At a singular configuration the task rows of J lose rank, so some joint rates produce no tool
velocity at all. :func:`null_motion` returns one such direction with a fixed sign convention (its
largest component positive; of equal ones, the first), so that the same configuration always
gives the same words, e.g. the Puma 560's wrist at q₅ = 0: q̇₄ = −q̇₆ (axes 4 and 6 collinear).

>>> import numpy as np
>>> from kinematics import Robot
>>> arm = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)] * 2, planar=True)
>>> m = null_motion(arm, [0.0, 0.0])
>>> np.round(m.direction * np.sqrt(5), 12).tolist()
[-1.0, 2.0]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..analysis import DEFAULT_RTOL, Part, part_rows, task_rows
from ..conventions import FloatArray
from ..errors import ConfigurationError
from ..model import Robot
from ..numeric import as_configuration, jacobian

__all__ = ["NullMotion", "null_motion", "null_motion_path", "signed"]

TIE = 1e-9
"""Components within TIE of the largest magnitude count as equally large (the first is made positive)."""
ZERO = 1e-12
"""Components below ZERO are set to exactly 0 (a joint that does not take part)."""


@dataclass(frozen=True, eq=False)
class NullMotion:
    """One joint motion of Ker J at a configuration.

    Attributes:
        direction: Unit joint-rate vector (n,) with J_rows · direction = 0 (to rounding), signed by
            :func:`signed`; zeros where a joint does not take part.
        dimension: dim Ker J of the task rows (0: the configuration is regular; ``direction`` is
            then the right singular vector of σmin, the nearest thing to a null motion).
        sigma: ‖J_rows · direction‖ (0 at a singularity, σmin near one) [m/s or rad/s per unit rate].
        joints: Indices of the joints that move (non-zero components), ascending.
    """

    direction: FloatArray
    dimension: int
    sigma: float
    joints: tuple[int, ...]


def signed(v: npt.ArrayLike) -> FloatArray:
    """``v`` with components below :data:`ZERO` set to 0 and the sign chosen so that the largest
    component is positive (of components equal in magnitude within :data:`TIE`, the first)."""
    a = np.array(v, dtype=float)
    a[np.abs(a) < ZERO] = 0.0
    big = float(np.abs(a).max()) if a.size else 0.0
    if big == 0.0:
        return a
    first = int(np.flatnonzero(np.abs(a) >= big - TIE)[0])
    return a if a[first] > 0 else -a


def null_motion(
    robot: Robot, q: npt.ArrayLike, rows: Part | tuple[int, ...] | None = None, rtol: float = DEFAULT_RTOL
) -> NullMotion:
    """A null joint motion of the task rows (default the robot's) of J at ``q``.

    At a singularity, the first vector of the orthonormal basis of Ker J (σ = 0 within ``rtol``),
    signed; where Ker J has more than one dimension the other ones are in
    :func:`kinematics.null_space`. At a regular configuration, the direction of σmin.
    """
    qa = as_configuration(robot, q)
    if qa.ndim != 1:
        raise ConfigurationError(f"q must be one configuration ({robot.dof},), got shape {qa.shape}")
    chosen = tuple(task_rows(robot) if rows is None else part_rows(rows))
    J = jacobian(robot, qa)[list(chosen)]
    N = _kernel(J, rtol)
    if N.shape[1]:
        d = signed(N[:, 0])
    else:
        d = signed(np.linalg.svd(J)[2][-1])
    d = d / float(np.linalg.norm(d)) + 0.0  # + 0.0: no −0 in the words
    return NullMotion(
        d, int(N.shape[1]), float(np.linalg.norm(J @ d)), tuple(int(i) for i in np.flatnonzero(d))
    )


def _kernel(J: FloatArray, rtol: float) -> FloatArray:
    """Orthonormal basis of Ker J of already-selected rows (as :func:`kinematics.null_space`)."""
    _, s, Vt = np.linalg.svd(J)
    tol = rtol * max(float(s[0]) if s.size else 0.0, 1.0)
    r = int(np.sum(s > tol))
    return np.ascontiguousarray(Vt[r:].T)


def null_motion_path(q: npt.ArrayLike, direction: npt.ArrayLike, amplitude: float, steps: int) -> FloatArray:
    """Configurations (4·steps + 1, n) q + s · direction for s going 0 → amplitude → −amplitude → 0
    (one back-and-forth of the null motion, played in the app). The tool stands still to first
    order in s (exactly where the joints' axes coincide, as at the Puma's wrist singularity)."""
    qa = np.asarray(q, dtype=float)
    d = np.asarray(direction, dtype=float)
    if steps < 1 or not np.isfinite(amplitude):
        raise ValueError(f"steps must be ≥ 1 and amplitude finite, got {steps}, {amplitude}")
    s = amplitude * np.sin(np.linspace(0.0, 2.0 * np.pi, 4 * steps + 1))
    out: FloatArray = qa[None, :] + s[:, None] * d[None, :]
    return out
