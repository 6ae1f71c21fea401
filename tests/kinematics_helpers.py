"""Helpers shared by the kinematics tests."""

from __future__ import annotations

import numpy as np


def random_q(robot, rng: np.random.Generator, size: int | None = None) -> np.ndarray:
    """Configurations sampled inside the joint limits (±π / ±1 m where a joint has none)."""
    lim = robot.qlim.copy()
    for i, kind in enumerate(robot.joint_types):
        span = np.pi if kind == "revolute" else 1.0
        lim[0, i] = max(lim[0, i], -span)
        lim[1, i] = min(lim[1, i], span)
    shape = (robot.dof,) if size is None else (size, robot.dof)
    return rng.uniform(lim[0], lim[1], size=shape)
