"""Work a tab asks for that takes longer than a frame (the descent to the nearest singularity, the IK
solutions of a pose), run in
a small shared thread pool so the drawing thread keeps serving every tab; the result comes back to the
tab as an action."""

from __future__ import annotations

import functools
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from kinematics import Robot
from kinematics.motion.branches import branches
from kinematics.numeric import fk
from kinematics.singularity import nearest

from ..core.actions import FollowPath, IkSolutionsFound
from ..core.motion_rules import FRAME_DT, resample

__all__ = ["background", "nearest_path", "ik_solutions", "DESCENT_SECONDS"]

DESCENT_SECONDS = 2.0
"""The descent to the nearest singularity is played back in this many seconds (at speed 1)."""


@functools.cache
def background() -> ThreadPoolExecutor:
    """The shared pool (two workers: this machine class has two cores)."""
    return ThreadPoolExecutor(max_workers=2, thread_name_prefix="jacobian-lab-work")


def nearest_path(robot: Robot, q: np.ndarray) -> FollowPath:
    """The descent from ``q`` to the nearest singularity, resampled to play for DESCENT_SECONDS,
    with what was found said in words."""
    result = nearest(robot, q)
    path = np.asarray(result.path, dtype=float)
    steady = resample(path, max(2, round(DESCENT_SECONDS / FRAME_DT)))
    path = steady if steady is not None else path
    report = result.report
    kinds = " and ".join(report.kinds) if report.kinds else "a"
    found = (
        f"found: {kinds} singularity here (σmin/σmax = {result.sigma_ratio:.1e})"
        if result.sigma_ratio < 1e-6
        else f"closest found: σmin/σmax = {result.sigma_ratio:.1e} ({kinds} singularity nearby)"
    )
    return FollowPath(tuple(tuple(float(x) for x in row) for row in path), found)


def ik_solutions(robot: Robot, name: str, q: np.ndarray) -> IkSolutionsFound:
    """The IK solutions (elbow up / down, wrist flip …) of the pose robot ``name`` reaches at ``q``."""
    T = fk(robot, q)
    found = branches(robot, T, q)
    return IkSolutionsFound(
        name,
        tuple(float(x) for x in q),
        tuple(float(x) for x in T.ravel()),
        tuple(tuple(float(x) for x in b.q) for b in found),
    )
