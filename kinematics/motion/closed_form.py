"""Closed-form inverse kinematics and J⁻¹ from it: course 002's third way to J⁻¹.

002 (TRR example, item 3): "find J⁻¹(q) from the closed-form inverse kinematics equations". For an
arm whose tool point is reached by a planar two-link pair (two parallel revolute axes, standard DH,
αₖ = 0), optionally after one prismatic joint sliding along the base z axis (the TRR), the joint
values are closed-form functions q = g(x) of the tool point, and J⁻¹ = ∂g/∂x, differentiated here
by hand:

* the pair, in the plane of its first axis' frame (x′, y′, with r² = x′² + y′²):
  cos qₖ₊₁ = (r² − aₖ² − aₖ₊₁²) / (2 aₖ aₖ₊₁), qₖ = atan2(y′, x′) − atan2(aₖ₊₁ sin qₖ₊₁, aₖ + aₖ₊₁ cos qₖ₊₁)
  (each less its DH θ offset); so dqₖ₊₁ = −(x′ dx′ + y′ dy′) / (aₖ aₖ₊₁ sin qₖ₊₁) and
  dqₖ = (x′ dy′ − y′ dx′) / r² − aₖ₊₁ (aₖ₊₁ + aₖ cos qₖ₊₁) / r² · dqₖ₊₁;
* the slide: q₁ = z − d₁ − cos α₁ (dₖ + dₖ₊₁), so dq₁ = dz.

Both exist exactly where J⁻¹ does (sin qₖ₊₁ ≠ 0, the pair not folded onto its axis) and equal it
there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..analysis import task_rows
from ..conventions import FloatArray
from ..errors import ConfigurationError
from ..model import Robot
from ..numeric import as_configuration, fk

__all__ = ["ClosedForm", "closed_form", "closed_form_ik", "closed_form_inverse_jacobian"]

_TOL = 1e-12


@dataclass(frozen=True)
class ClosedForm:
    """Where a robot's closed-form IK comes from.

    Attributes:
        slide: True when joint 1 slides along the base z axis before the pair (the TRR).
        a1, a2: The pair's link lengths [m].
        theta1, theta2: The pair's DH θ offsets [rad] (added to its joint values).
        z_offset: d₁ + cos α₁ (dₖ + dₖ₊₁) for a slide [m] (q₁ = z − z_offset).
        flip: cos α₁ of the slide (+1 or −1; 1 without a slide).
    """

    slide: bool
    a1: float
    a2: float
    theta1: float
    theta2: float
    z_offset: float
    flip: float


def closed_form(robot: Robot) -> ClosedForm | None:
    """The closed-form IK of ``robot``, or ``None`` when it has none here (not a planar two-link pair,
    optionally after a slide along the base z axis; an identity base and tool; the task its position)."""
    dh = robot.dh
    if dh is None or robot.convention != "standard" or len(dh) not in (2, 3):
        return None
    if not (np.allclose(robot.base, np.eye(4)) and np.allclose(robot.tool, np.eye(4))):
        return None
    if len(robot.axes) != len(dh) or set(task_rows(robot)) - {0, 1, 2} or len(task_rows(robot)) != len(dh):
        return None
    *head, r1, r2 = dh
    if r1.joint != "revolute" or r2.joint != "revolute" or abs(math.sin(r1.alpha)) > _TOL:
        return None
    if r1.a <= 0 or r2.a <= 0:
        return None
    if not head:
        return ClosedForm(False, r1.a, r2.a, r1.theta, r2.theta, 0.0, 1.0)
    p = head[0]
    if p.joint != "prismatic" or abs(math.sin(p.alpha)) > _TOL:
        return None
    flip = math.cos(p.alpha)
    return ClosedForm(True, r1.a, r2.a, r1.theta, r2.theta, p.d + flip * (r1.d + r2.d), flip)


def _plane(robot: Robot, cf: ClosedForm, x: FloatArray, q1: float) -> FloatArray:
    """The tool point in the pair's plane (x′, y′): frame 0, or frame 1 of the slide at q₁."""
    if not cf.slide:
        return x[:2]
    row = robot.dh[0]  # type: ignore[index]
    c, s = math.cos(row.theta), math.sin(row.theta)
    u = x[:2] - row.a * np.array([c, s])  # frame 1's origin is a₁ along x₁ = Rz(θ₁) x₀
    return np.array([c * u[0] + s * u[1], cf.flip * (-s * u[0] + c * u[1])])


def closed_form_ik(robot: Robot, x: npt.ArrayLike, elbow: float = 1.0) -> FloatArray:
    """Joint values (n,) putting the tool point at ``x`` (3,) [m], base axes, by the closed form.

    Args:
        robot: A robot with a closed form (:func:`closed_form`).
        x: The tool point [m].
        elbow: The sign of sin qₖ₊₁ (the elbow's branch), +1 or −1.

    Raises:
        ConfigurationError: no closed form, or ``x`` out of reach.
    """
    cf = closed_form(robot)
    if cf is None:
        raise ConfigurationError(f"{robot.name} has no closed-form inverse kinematics here")
    x = np.asarray(x, float)
    q1 = float(x[2] - cf.z_offset) if cf.slide else 0.0
    px, py = _plane(robot, cf, x, q1)
    c2 = (px * px + py * py - cf.a1**2 - cf.a2**2) / (2 * cf.a1 * cf.a2)
    if abs(c2) > 1 + 1e-12:
        raise ConfigurationError(f"the point {x.tolist()} is out of reach of {robot.name}")
    q2 = math.copysign(math.acos(min(1.0, max(-1.0, c2))), elbow)
    qa = math.atan2(py, px) - math.atan2(cf.a2 * math.sin(q2), cf.a1 + cf.a2 * math.cos(q2))
    pair = [math.remainder(qa - cf.theta1, math.tau), math.remainder(q2 - cf.theta2, math.tau)]
    return np.array([q1, *pair] if cf.slide else pair)


def closed_form_inverse_jacobian(robot: Robot, q: npt.ArrayLike) -> FloatArray | None:
    """J⁻¹ (n, n) = ∂q/∂x of the closed-form IK at ``q``: rows joints, columns the task rows
    (ẋ, ẏ[, ż]) [rad/m | m/m]; ``None`` where it does not exist (sin qₖ₊₁ = 0: singular).

    Raises:
        ConfigurationError: no closed form (:func:`closed_form`).
    """
    cf = closed_form(robot)
    if cf is None:
        raise ConfigurationError(f"{robot.name} has no closed-form inverse kinematics here")
    q = as_configuration(robot, q)
    x = fk(robot, q)[:3, 3]
    q1 = float(q[0]) if cf.slide else 0.0
    px, py = _plane(robot, cf, x, q1)
    t2 = float(q[-1]) + cf.theta2
    s2 = math.sin(t2)
    if abs(s2) < 1e-9:
        return None
    r2 = px * px + py * py
    d2 = -np.array([px, py]) / (cf.a1 * cf.a2 * s2)  # ∂qₖ₊₁/∂(x′, y′)
    d1 = np.array([-py, px]) / r2 - cf.a2 * (cf.a2 + cf.a1 * math.cos(t2)) / r2 * d2
    plane = np.vstack([d1, d2])  # (2, 2) over (x′, y′)
    if not cf.slide:
        return plane
    th = robot.dh[0].theta  # type: ignore[index]
    c, s = math.cos(th), math.sin(th)
    P = np.array([[c, s], [-cf.flip * s, cf.flip * c]])  # (x′, y′) = P (x, y) + const
    out = np.zeros((3, 3))
    out[0, 2] = 1.0
    out[1:, :2] = plane @ P
    return out
