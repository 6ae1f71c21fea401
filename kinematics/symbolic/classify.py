"""Names and solutions of singular sets: which joints a factor of det J involves, and where it vanishes."""

from __future__ import annotations

import sympy as sp

from ..analysis import PART_ROWS
from ..model import Robot

__all__ = ["kind_context", "kind", "solve_single"]


def kind_context(robot: Robot, rows: tuple[int, ...]) -> tuple[set[int], set[int], set[int]]:
    """(wrist joints, arm joints, elbow joints) by index.

    The wrist is the last three joints of a 6+ joint arm (every joint of a robot whose task is
    orientation only); an elbow joint is a revolute arm joint after the first that is parallel to
    the joint before it, or the last arm joint.
    """
    n = robot.dof
    if rows == PART_ROWS["angular"]:
        return set(range(n)), set(), set()
    wrist = set(range(n - 3, n)) if n >= 6 else set()
    arm = set(range(n)) - wrist
    simple = len(robot.axes) == n and all(ax.joint_index == i for i, ax in enumerate(robot.axes))
    elbows = set()
    for j in sorted(arm)[1:]:
        if robot.joint_types[j] != "revolute":
            continue
        parallel = False
        if simple:
            F = robot.axes[j - 1].T_joint_child @ robot.axes[j].T_parent_joint
            parallel = abs(abs(F[2, 2]) - 1.0) < 1e-9
        if parallel or j == max(arm):
            elbows.add(j)
    return wrist, arm, elbows


def kind(idx: set[int], robot: Robot, ctx: tuple[set[int], set[int], set[int]]) -> str:
    wrist, arm, elbows = ctx
    if idx <= wrist:
        return "wrist"
    if len(idx) == 1 and idx <= elbows:
        return "elbow"
    if all(robot.joint_types[i] == "prismatic" for i in idx):
        return ""
    return "shoulder" if idx & arm else ""


def solve_single(f: sp.Expr, qj: sp.Symbol, revolute: bool) -> tuple[sp.Expr, ...] | None:
    domain = sp.Interval(-sp.pi, sp.pi, left_open=True) if revolute else sp.S.Reals
    try:
        sol = sp.solveset(f, qj, domain)
    except (NotImplementedError, ValueError, TypeError):
        return None
    return tuple(sorted(sol, key=lambda v: float(v))) if isinstance(sol, sp.FiniteSet) else None
