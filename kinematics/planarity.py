"""Is a chain planar? Every revolute axis along the base z axis and every prismatic one across it.

Such an arm moves its tool only in planes parallel to the base x-y plane and turns it only about z, at
every configuration: its J has vz = ωx = ωy = 0 rows, so those rows must leave its task (a
:class:`~kinematics.model.Robot` with ``planar=True``), or the arm reads singular in every pose. The
library's planar robots say so in their files; :func:`is_planar_chain` finds it from the axes alone
(for a robot built from a DH table in the browser).

>>> from kinematics import Robot
>>> row = dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)
>>> is_planar_chain(Robot.from_dh([row, row]))
True
>>> is_planar_chain(Robot.from_dh([dict(row, alpha=1.5707963267948966), row]))
False
"""

from __future__ import annotations

import numpy as np

from .model import Robot
from .numeric import chain_frames

__all__ = ["is_planar_chain"]

_TOL = 1e-9


def is_planar_chain(robot: Robot) -> bool:
    """True when, at home and at a few other configurations (fixed seed, inside the limits), every
    revolute axis is parallel to the base z axis and every prismatic axis perpendicular to it."""
    n = robot.dof
    if n == 0 or len(robot.axes) != n:
        return False
    lo, hi = robot.qlim
    lo = np.where(np.isfinite(lo), lo, -np.pi)
    hi = np.where(np.isfinite(hi), hi, np.pi)
    rng = np.random.default_rng(5)
    for q in [np.asarray(robot.home, float)] + [rng.uniform(lo, hi) for _ in range(3)]:
        W, _ = chain_frames(robot, q)
        for ax, frame in zip(robot.axes, W, strict=True):
            z = frame[:3, 2]
            along = abs(float(z[2]))
            if ax.kind == "revolute" and abs(along - 1.0) > _TOL:
                return False
            if ax.kind != "revolute" and along > _TOL:
                return False
    return True
