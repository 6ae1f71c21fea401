"""Is this configuration singular, and of which kind?

:func:`assess` measures the task rows of the base-frame Jacobian (see
:func:`kinematics.analysis.task_rows`) and names the kind of singularity the
course talks about where the geometry tells it:

* **wrist**: the last three revolute axes lose rank as a set of directions
  (two wrist axes line up, e.g. q5 = 0 on a Puma 560 or UR5): the tool cannot
  rotate about one direction whatever the wrist does;
* **shoulder**: the wrist point (for arms without a wrist, the tool point)
  lies on the first revolute axis: turning joint 1 does not move it;
* **elbow**: the arm joints lose rank at the wrist point otherwise (the arm
  stretched out or folded back, e.g. q2 = 0 on a planar 2R arm).

The kinds are tests of geometry, not of a particular robot's joint values,
so they hold for any robot the user defines; where no test applies the report
says "singular" without a kind.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from .analysis import DEFAULT_RTOL, PART_ROWS, task_rows
from .model import Robot
from .numeric import _chain_single, as_configuration, jacobian

__all__ = ["SingularityReport", "assess", "NEAR_CONDITION"]

NEAR_CONDITION = 50.0
"""Task condition number above which a configuration is called "near singular"."""

Status = Literal["regular", "near singular", "singular"]


@dataclass(frozen=True, eq=False)
class SingularityReport:
    """What :func:`assess` found.

    Attributes:
        status: ``"regular"``, ``"near singular"`` or ``"singular"``.
        kinds: Kinds of singularity found (``"wrist"``, ``"elbow"``, ``"shoulder"``);
            for a near-singular configuration, the kinds it is close to.
        sigma_min: Smallest singular value of the task rows (units of those rows).
        condition: Task condition number σmax/σmin, ``inf`` when singular.
        lost_twist: (6,) unit [v; ω] direction (base axes) of σmin: the task
            direction the tool can (almost) not move in. Zero in rows outside the task.
        null_motion: (n,) unit joint motion belonging to σmin: the joint rates that
            (almost) do not move the tool.
    """

    status: Status
    kinds: tuple[str, ...]
    sigma_min: float
    condition: float
    lost_twist: np.ndarray
    null_motion: np.ndarray

    def text(self) -> str:
        """Plain words for a status line: "regular", "near singular: wrist", "singular: elbow"."""
        if self.status == "regular" or not self.kinds:
            return self.status
        return f"{self.status}: {' + '.join(self.kinds)}"


def _smallest(A: np.ndarray) -> float:
    """Smallest singular value of A, or 0 when A has more rows than columns."""
    if A.shape[0] > A.shape[1] or A.size == 0:
        return 0.0
    return float(np.linalg.svd(A, compute_uv=False)[-1])


def assess(
    robot: Robot,
    q: object,
    J: np.ndarray | None = None,
    near_condition: float = NEAR_CONDITION,
    rtol: float = DEFAULT_RTOL,
) -> SingularityReport:
    """Classify the configuration ``q`` of ``robot``.

    Args:
        robot: The robot.
        q: One configuration (n,) [rad | m].
        J: Its base-frame Jacobian if already computed (saves one evaluation).
        near_condition: Task condition number above which the status is "near singular".
        rtol: Relative tolerance for a zero singular value.
    """
    q = as_configuration(robot, q)
    if J is None:
        J = jacobian(robot, q)
    rows = list(task_rows(robot))
    Js = J[rows]
    U, s, Vt = np.linalg.svd(Js)
    n = robot.dof
    k = min(len(rows), n)
    smin = float(s[k - 1]) if len(rows) <= n else 0.0
    scale = max(float(s[0]), 1.0)
    singular = smin <= rtol * scale
    cond = np.inf if singular else float(s[0]) / smin
    u_lost = U[:, len(rows) - 1] if len(rows) > n else U[:, k - 1]
    lost = np.zeros(6)
    lost[rows] = u_lost
    null_motion = Vt[min(k, Vt.shape[0]) - 1] if len(rows) <= n else Vt[-1]
    status: Status = "singular" if singular else "near singular" if cond > near_condition else "regular"
    kinds: tuple[str, ...] = ()
    if status != "regular":
        # Compare each geometric test with the task's smallest singular value: a kind is
        # named when its own measure is about as small (relative to the task's).
        kinds = _kinds(robot, q, rows, tol=max(smin, rtol * scale) * 10.0 + 1e-12)
    return SingularityReport(status, kinds, smin, cond, lost, null_motion.copy())


def _kinds(robot: Robot, q: np.ndarray, rows: list[int], tol: float) -> tuple[str, ...]:
    W, T = _chain_single(robot, q)
    c = robot._compiled  # type: ignore[attr-defined]
    revolute = [k for k in range(len(W)) if c.revolute[k]]
    z = W[:, :3, 2]
    kinds = []
    wants_orientation = any(r in PART_ROWS["angular"] for r in rows)
    has_wrist = wants_orientation and len(revolute) >= 3
    if has_wrist:
        wrist_axes = revolute[-3:]
        if _smallest(z[wrist_axes].T) <= tol:
            kinds.append("wrist")
        # Wrist point: origin of the middle wrist axis' frame (on the axes' intersection for a
        # spherical wrist); the arm is every axis before the wrist.
        point = W[wrist_axes[1], :3, 3]
        arm = list(range(wrist_axes[0]))
    else:
        point = T[:3, 3]
        arm = list(range(len(W)))
    if not arm:
        return tuple(kinds)
    first_rev = next((k for k in arm if c.revolute[k]), None)
    on_axis = False
    if first_rev is not None:
        r = point - W[first_rev, :3, 3]
        dist = np.linalg.norm(np.cross(z[first_rev], r))
        on_axis = dist <= tol
        if on_axis:
            kinds.append("shoulder")
    # Linear velocity of the wrist point produced by the arm axes.
    Jp = np.empty((3, len(arm)))
    for j, k in enumerate(arm):
        Jp[:, j] = np.cross(z[k], point - W[k, :3, 3]) if c.revolute[k] else z[k]
    if robot.planar:
        Jp = Jp[:2]
    if not on_axis and _smallest(Jp) <= tol:
        kinds.append("elbow")
    return tuple(kinds)
