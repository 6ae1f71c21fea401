"""The several inverse-kinematics solutions of one pose (004: the inverse problem is not unique).

A 6-axis arm such as the Puma 560 reaches a pose in up to eight ways (shoulder left / right, elbow
up / down, wrist flipped or not); the planar 2R reaches a point elbow up or elbow down. As the pose
approaches a singularity two of these branches approach each other and merge there (the 2R
stretched out: q₂ = ±arccos(…) → 0). :func:`branches` finds them by the course's Newton iteration
from spread starting points and keeps the distinct ones within the joint limits; :func:`gap` is
the smallest distance between two of them (→ 0 as they merge).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..conventions import FloatArray
from ..errors import ConfigurationError, OptionError
from ..model import Robot
from ..numeric import as_configuration
from .ik import solve

__all__ = ["Branch", "branches", "gap", "SAME"]

SAME = 1e-6
"""Two solutions closer than this in every joint (revolute ones modulo 2π) are one [rad | m]."""


@dataclass(frozen=True, eq=False)
class Branch:
    """One IK solution: ``q`` (n,) and its distance from the configuration asked about [rad | m]."""

    q: FloatArray
    distance: float


def _wrap(robot: Robot, q: FloatArray) -> FloatArray | None:
    """``q`` with each revolute joint moved by whole turns into its limits (None: no turn fits)."""
    out: FloatArray = np.array(q, dtype=float)
    lo, hi = robot.qlim
    for i, kind in enumerate(robot.joint_types):
        if kind == "revolute":
            x = (out[i] + math.pi) % (2.0 * math.pi) - math.pi
            for cand in (x, x + 2.0 * math.pi, x - 2.0 * math.pi):
                if lo[i] - 1e-9 <= cand <= hi[i] + 1e-9:
                    out[i] = cand
                    break
            else:
                return None
        elif not lo[i] - 1e-9 <= out[i] <= hi[i] + 1e-9:
            return None
    return out


def _difference(robot: Robot, a: FloatArray, b: FloatArray) -> FloatArray:
    d = a - b
    rev = np.array([k == "revolute" for k in robot.joint_types])
    d[rev] = (d[rev] + math.pi) % (2.0 * math.pi) - math.pi
    return d


def branches(
    robot: Robot,
    target: npt.ArrayLike,
    q: npt.ArrayLike,
    *,
    starts: int = 64,
    seed: int = 0,
    tol: float = 1e-10,
) -> tuple[Branch, ...]:
    """The distinct IK solutions of ``target`` (a point (3,) or a pose (4, 4)) within the limits,
    nearest to ``q`` first. Newton from ``q`` and from ``starts`` configurations drawn uniformly
    within the limits (±π where a revolute joint has none; a fixed ``seed``: the same answer every
    time). Only converged solutions are kept."""
    qa = as_configuration(robot, q)
    if qa.ndim != 1:
        raise ConfigurationError(f"q must be one configuration ({robot.dof},), got shape {qa.shape}")
    if not (isinstance(starts, int) and starts >= 0):
        raise OptionError(f"starts must be an int ≥ 0, got {starts!r}")
    lo, hi = robot.qlim
    lo = np.where(np.isfinite(lo), lo, -math.pi)
    hi = np.where(np.isfinite(hi), hi, math.pi)
    rng = np.random.default_rng(seed)
    seeds = np.vstack([qa[None], rng.uniform(lo, hi, size=(starts, robot.dof))])
    found: list[FloatArray] = []
    for s in seeds:
        r = solve(robot, target, s, tol=tol, step_limit=0.5, max_iterations=80)
        if not r.converged:
            continue
        w = _wrap(robot, r.q)
        if w is None or any(np.abs(_difference(robot, w, f)).max() < SAME for f in found):
            continue
        found.append(w)
    out = [Branch(f, float(np.linalg.norm(_difference(robot, f, qa)))) for f in found]
    return tuple(sorted(out, key=lambda b: b.distance))


def gap(robot: Robot, found: tuple[Branch, ...]) -> float:
    """The smallest joint-space distance between two of ``found`` (inf for fewer than two) [rad | m]."""
    best = math.inf
    for i in range(len(found)):
        for j in range(i + 1, len(found)):
            best = min(best, float(np.linalg.norm(_difference(robot, found[i].q, found[j].q))))
    return best
