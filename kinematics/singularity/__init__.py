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

from ..analysis import DEFAULT_RTOL, PART_ROWS, as_jacobian, check_rtol, task_rows
from ..errors import ArrayError, ConfigurationError, OptionError
from ..model import Robot
from ..numeric import as_configuration, chain_frames, jacobian
from ..validation import is_number, show
from .descent import descend_to_singularity

__all__ = ["SingularityReport", "assess", "NEAR_CONDITION", "NearestSingularity", "nearest"]

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
    if q.ndim != 1:
        raise ConfigurationError(f"assess takes one configuration ({robot.dof},), got {q.shape}")
    rtol = check_rtol(rtol)
    if not (is_number(near_condition) and near_condition > 1):
        raise OptionError(f"near_condition must be a number > 1, got {show(near_condition)}")
    if J is None:
        J = jacobian(robot, q)
    else:
        J = as_jacobian(J)
        if J.shape != (6, robot.dof):
            raise ArrayError(f"J should have shape (6, {robot.dof}) for robot {robot.name!r}, got {J.shape}")
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
        kinds = _kinds(robot, q, rows, KIND_TOL if singular else NEAR_KIND_TOL)
    return SingularityReport(status, kinds, smin, cond, lost, null_motion.copy())


KIND_TOL = 1e-7
"""A normalised geometric measure below this names the kind of an exact singularity."""
NEAR_KIND_TOL = 0.1
"""... and below this, the kind a near-singular configuration is close to."""


def _kinds(robot: Robot, q: np.ndarray, rows: list[int], tol: float) -> tuple[str, ...]:
    """Kinds of singularity from normalised geometric measures (each in [0, 1], 0 = degenerate).

    * wrist: σmin of the three wrist axis directions [z₋₃ z₋₂ z₋₁];
    * the arm (axes before the wrist, or all axes without a wrist) moves the
      wrist point (where the last wrist axes meet; the tool point without a
      wrist) through the columns zᵢ × (p − pᵢ): elbow when the last two arm
      columns alone lose rank (stretched or folded), shoulder when the arm
      columns lose rank although those two do not (the first axis only adds
      motion the others already give: the wrist point is in the plane of
      axes 1 and 2).
    """
    W, T = chain_frames(robot, q)
    is_revolute = [ax.kind == "revolute" for ax in robot.axes]
    revolute = [k for k in range(len(W)) if is_revolute[k]]
    z, p = W[:, :3, 2], W[:, :3, 3]
    kinds = []
    orientation_task = any(r in PART_ROWS["angular"] for r in rows)
    if robot.planar and orientation_task and len(revolute) >= 3:
        # A planar arm that also orients its tool: the last axis is its "wrist".
        elbow_point = shoulder_point = p[revolute[-1]]
        arm = shoulder_arm = list(range(revolute[-1]))
    elif not robot.planar and orientation_task and len(revolute) >= 3:
        wrist_axes = revolute[-3:]
        if float(np.linalg.svd(z[wrist_axes].T, compute_uv=False)[-1]) <= tol:
            kinds.append("wrist")
        centre = _common_point(z[wrist_axes], p[wrist_axes])
        arm = list(range(wrist_axes[0]))
        if centre is not None:  # spherical wrist: the arm positions the wrist centre
            elbow_point = shoulder_point = centre
            shoulder_arm = arm
        else:  # offset wrist (UR type): the first wrist axis still moves where the last two meet
            elbow_point, shoulder_point = p[wrist_axes[0]], p[wrist_axes[-1]]
            shoulder_arm = list(range(wrist_axes[1]))
    else:
        elbow_point = shoulder_point = T[:3, 3]
        arm = shoulder_arm = list(range(len(W)))
    if not arm:
        return tuple(kinds)

    def columns(axes: list[int], point: np.ndarray) -> np.ndarray:
        Jp = np.empty((3, len(axes)))
        for j, k in enumerate(axes):
            Jp[:, j] = np.cross(z[k], point - p[k]) if is_revolute[k] else z[k]
        return Jp[:2] if robot.planar else Jp

    def rank(A: np.ndarray) -> int:
        s = np.linalg.svd(A, compute_uv=False) if A.size else np.zeros(0)
        return int(np.sum(s > tol * s[0])) if s.size and s[0] > 0 else 0

    Je, Js = columns(arm, elbow_point), columns(shoulder_arm, shoulder_point)
    full = Je.shape[0]
    if rank(Je) < min(full, Je.shape[1]) and rank(Je[:, -2:]) < min(2, Je.shape[1]):
        kinds.append("elbow")  # the last two arm joints move the point along one line only
    if "elbow" not in kinds and Js.shape[1] > 2 and rank(Js) < full and rank(Js[:, 1:]) == rank(Js):
        kinds.append("shoulder")  # joint 1 adds no motion the others do not already give
    return tuple(kinds)


def _common_point(z: np.ndarray, p: np.ndarray) -> np.ndarray | None:
    """The point where the lines (pᵢ, zᵢ) meet, or None if they do not (within 1e-9 m)."""
    P = [np.eye(3) - np.outer(zi, zi) for zi in z]
    A, b = sum(P), sum(Pi @ pi for Pi, pi in zip(P, p, strict=True))
    if np.linalg.svd(A, compute_uv=False)[-1] < 1e-9:
        return None
    x = np.linalg.solve(A, b)
    if max(np.linalg.norm(Pi @ (x - pi)) for Pi, pi in zip(P, p, strict=True)) > 1e-9:
        return None
    return x


@dataclass(frozen=True, eq=False)
class NearestSingularity:
    """What :func:`nearest` found.

    Attributes:
        q: (n,) the end of the descent [rad | m].
        path: (k+1, n) every iterate from q0 to q (to animate the descent).
        sigma_ratio: σmin/σmax of the task rows at ``q`` (< tol when converged).
        converged: True when sigma_ratio < tol.
        report: :func:`assess` at ``q`` (its ``kinds``: wrist, elbow, shoulder ...).
    """

    q: np.ndarray
    path: np.ndarray
    sigma_ratio: float
    converged: bool
    report: SingularityReport


def nearest(robot: Robot, q0: object, *, max_iterations: int = 100, tol: float = 1e-6) -> NearestSingularity:
    """A singular configuration near ``q0``: descend σmin of the task rows of J from ``q0``.

    Minimum-norm Newton steps on w = Π σᵢ = 0 (see :mod:`kinematics.singularity.descent`), so the path
    heads for a nearby piece of the singular set (e.g. q2 → 0 for a planar 2R arm from
    q2 = 20°), until σmin/σmax < ``tol`` (then a few more steps, so that :func:`assess` calls
    the end singular). Joint limits are not enforced (they bound sliders, not maths). For a
    redundant arm the descent is slower and may end with ``converged=False``.

    Raises:
        ConfigurationError: ``q0`` is not one configuration.
        OptionError: ``max_iterations`` is not an int ≥ 0 or ``tol`` not in (0, 1).
    """
    q = as_configuration(robot, q0, "q0")
    if q.ndim != 1:
        raise ConfigurationError(f"q0 must be one configuration ({robot.dof},), got shape {q.shape}")
    if not (isinstance(max_iterations, (int, np.integer)) and not isinstance(max_iterations, bool)):
        raise OptionError(f"max_iterations must be an int ≥ 0, got {show(max_iterations)}")
    if max_iterations < 0:
        raise OptionError(f"max_iterations must be an int ≥ 0, got {show(max_iterations)}")
    if not (is_number(tol) and 0.0 < tol < 1.0):
        raise OptionError(f"tol must be a number in (0, 1) (a ratio σmin/σmax), got {show(tol)}")
    path, ratio = descend_to_singularity(robot, q, list(task_rows(robot)), int(max_iterations), float(tol))
    end = path[-1]
    return NearestSingularity(end, path, ratio, ratio < tol, assess(robot, end))
