"""What a singular (or near-singular) configuration loses, where, ready to draw and to say.

One :class:`Loss` per lost direction, each at its own point:

* a robot with a spherical wrist (:func:`kinematics.singularity.decoupling.decouple`) is decoupled as the
  course teaches: an **arm** loss is a translation of the wrist centre the arm joints cannot give
  (det J₁₁ = 0), a **wrist** loss a rotation about an axis through the wrist centre the wrist
  cannot give (det J₂₂ = 0);
* any other robot loses **tool** directions: every left singular vector of its task rows with
  σ ≈ 0, the ω rows weighed by the arm's reach L, measured at the tool point.

Translations point away from the first joint's axis (out of the workspace at a boundary
singularity), so the arrow is drawn outside the arm.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from kinematics.analysis import Ellipsoid, velocity_ellipsoid
from kinematics.singularity import NEAR_CONDITION, SingularityReport
from kinematics.singularity.decoupling import Decoupling
from kinematics.singularity.lost import lost_directions

__all__ = ["Loss", "losses", "block_ellipsoids"]

Part = Literal["arm", "wrist", "tool"]


@dataclass(frozen=True, eq=False)
class Loss:
    """One lost direction.

    Attributes:
        part: ``"arm"`` (the wrist centre's translation), ``"wrist"`` (a rotation at the wrist centre)
            or ``"tool"`` (a direction of the tool twist, no wrist to decouple).
        point: Where it is lost and drawn (3,) [m]: the wrist centre or the tool point.
        translation: Unit direction of the lost translation (3,), zero if none.
        rotation: Unit axis of the lost rotation (3,), zero if none.
        translation_share: How much of the direction is translation, in [0, 1] (ω weighed by L).
        sigma: Its singular value (0 when exactly lost) in the units of its block.
    """

    part: Part
    point: np.ndarray
    translation: np.ndarray
    rotation: np.ndarray
    translation_share: float
    sigma: float

    @property
    def rotation_share(self) -> float:
        """How much of the direction is rotation: 1 − translation_share."""
        return 1.0 - self.translation_share


def _outward(u: np.ndarray, point: np.ndarray, axis_point: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """``u`` or −u, whichever points away from the line (axis_point, axis): out of the workspace."""
    r = point - axis_point
    r = r - (r @ axis) * axis  # radial part
    if float(np.linalg.norm(r)) < 1e-9:  # on the axis: away from the base along the axis
        r = point - axis_point
    d = float(u @ r)
    if abs(d) < 1e-9:  # sideways: a fixed, readable choice
        k = int(np.argmax(np.abs(u)))
        return u if u[k] >= 0 else -u
    return u if d > 0 else -u


def _axis_sign(a: np.ndarray) -> np.ndarray:
    k = int(np.argmax(np.abs(a)))
    return a if a[k] >= 0 else -a


def _block(d: Decoupling, which: str, near: bool) -> list[tuple[np.ndarray, float]]:
    """The lost directions of one block (with σ), or for a near-singular block its weakest one."""
    lost = d.arm_lost if which == "arm" else d.wrist_lost
    if len(lost):
        return [(u, 0.0) for u in lost]
    if not near:
        return []
    block = d.J11 if which == "arm" else d.J22
    U, s, _ = np.linalg.svd(block)
    return [(U[:, 2], float(s[2]) if len(s) >= 3 else 0.0)]


def _in_range(J: np.ndarray, twist: np.ndarray) -> bool:
    """True when ``twist`` (6,) is (nearly) produced by some joint rates: not lost after all."""
    x = np.linalg.lstsq(J, twist, rcond=None)[0]
    return float(np.linalg.norm(J @ x - twist)) < 1e-6


def losses(
    report: SingularityReport,
    J: np.ndarray,
    rows: tuple[int, ...],
    length: float,
    tool: np.ndarray,
    W: np.ndarray,
    decoupling: Decoupling | None,
) -> tuple[Loss, ...]:
    """Every direction lost at this configuration (none when it is regular).

    Args:
        report: The singularity report of the task rows.
        J: Base-frame Jacobian at the tool point (6, n).
        rows: Task rows.
        length: L [m] weighing rad/s against m/s for a robot without a spherical wrist.
        tool: Tool point (3,) [m].
        W: Joint frames (m, 4, 4) (the first axis decides what "outward" means).
        decoupling: J at the wrist centre in blocks, or None.
    """
    if report.status == "regular":
        return ()
    base_point, base_axis = W[0, :3, 3], W[0, :3, 2]
    out: list[Loss] = []
    if decoupling is not None and tuple(rows) == (0, 1, 2, 3, 4, 5):
        d, c = decoupling, decoupling.centre
        near = report.status == "near singular"
        ka, kw = d.condition_arm, d.condition_wrist
        show_arm = d.arm_singular or (near and (ka >= NEAR_CONDITION or ka >= kw))
        show_wrist = d.wrist_singular or (near and (kw >= NEAR_CONDITION or kw > ka))
        if show_arm:
            for u, s in _block(d, "arm", near):
                out.append(Loss("arm", c, _outward(u, c, base_point, base_axis), np.zeros(3), 1.0, s))
        if show_wrist:
            for a, s in _block(d, "wrist", near):
                if report.status == "singular" and _in_range(d.J_centre, np.concatenate([np.zeros(3), a])):
                    continue  # a redundant arm makes up for its wrist (iiwa, q6 = 0)
                out.append(Loss("wrist", c, np.zeros(3), _axis_sign(a), 0.0, s))
        if out:
            return tuple(out)
    for lost in lost_directions(J, rows, length):
        t = (
            _outward(lost.translation, tool, base_point, base_axis)
            if lost.translation_share > 0
            else lost.translation
        )
        out.append(Loss("tool", tool, t, _axis_sign(lost.rotation), lost.translation_share, lost.sigma))
    return tuple(out)


def block_ellipsoids(d: Decoupling | None) -> tuple[Ellipsoid | None, Ellipsoid | None]:
    """The decoupled ellipsoids at the wrist centre: the wrist centre's velocity by the arm joints
    ({J₁₁ q̇ₐ : ‖q̇ₐ‖ ≤ 1}) and the tool's angular velocity by the wrist joints ({J₂₂ q̇_w})."""
    if d is None:
        return None, None
    pad = np.zeros((3, d.J11.shape[1]))
    arm = velocity_ellipsoid(np.vstack([d.J11, pad]), "linear")
    wrist = velocity_ellipsoid(np.vstack([np.zeros((3, 3)), d.J22]), "angular")
    return arm, wrist
