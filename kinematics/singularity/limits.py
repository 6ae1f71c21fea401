"""Joint-limit points as critical points (002).

The course's critical points of the workspace are the singular points and the points on the
joint-limit boundary: where joint i stands at a limit it can move one way only, so the tool
velocities along J's column i (q̇ᵢ · Jᵢ) are possible in one sense only. :func:`limit_contacts` names
the joints at a limit with the sense they can still move in and the column it signs;
:func:`at_limit` marks a batch of configurations (for the maps).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..conventions import FloatArray
from ..errors import ConfigurationError
from ..model import Robot
from ..numeric import as_configuration, jacobian

__all__ = ["LimitContact", "limit_contacts", "at_limit", "LIMIT_TOL"]

LIMIT_TOL = 1e-6
"""A joint within this of a limit is at it [rad | m]."""


@dataclass(frozen=True, eq=False)
class LimitContact:
    """A joint at one of its limits.

    Attributes:
        joint: Its index (0-based).
        side: "lower" or "upper".
        sense: The sign q̇ᵢ can still take: +1 at the lower limit, −1 at the upper.
        column: sense · Jᵢ (6,): the tool twist [v; ω] per unit rate that remains possible; its
            opposite is not.
    """

    joint: int
    side: str
    sense: int
    column: FloatArray


def limit_contacts(robot: Robot, q: npt.ArrayLike, tol: float = LIMIT_TOL) -> tuple[LimitContact, ...]:
    """The joints of ``q`` at a limit (within ``tol``), in joint order; empty: not a limit point."""
    qa = as_configuration(robot, q)
    if qa.ndim != 1:
        raise ConfigurationError(f"q must be one configuration ({robot.dof},), got shape {qa.shape}")
    lo, hi = robot.qlim
    out = []
    J: FloatArray | None = None
    for i in range(robot.dof):
        side = "lower" if qa[i] <= lo[i] + tol else "upper" if qa[i] >= hi[i] - tol else ""
        if not side:
            continue
        J = jacobian(robot, qa) if J is None else J
        sense = 1 if side == "lower" else -1
        out.append(LimitContact(i, side, sense, sense * J[:, i]))
    return tuple(out)


def at_limit(robot: Robot, Q: npt.ArrayLike, tol: float = LIMIT_TOL) -> np.ndarray:
    """(N,) bool: which configurations of ``Q`` (N, n) have a joint within ``tol`` of a limit."""
    Qa = np.asarray(Q, dtype=float).reshape(-1, robot.dof)
    lo, hi = robot.qlim
    return np.asarray(((Qa <= lo + tol) | (Qa >= hi - tol)).any(axis=1))
