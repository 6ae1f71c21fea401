"""The course's Jacobian method of inverse kinematics along a path y(t), t ∈ [t₀, t_k] (004).

Newton's method finds q(t₀) with k(q(t₀)) = y(t₀); then the differential equation

    q̇ = J⁻¹ ẏ(t)                      (n = m, J regular)
    q̇ = J⁺ ẏ(t) + (I − J⁺J) ω(t)      (n > m, rank J = m)

is integrated from q(t₀) (here by the classical Runge–Kutta step, so that away from a
singularity the error ‖y(t) − k(q(t))‖ stays at the integration's error). Near a singularity
J⁻¹ grows like 1/σmin: the rates blow up and the fixed step can no longer follow, which is why
the method fails there (the error and the rates show it).

The path is of the tool point [m] in the base frame; the rows solved for are the position rows
among the robot's task rows (x, y for a planar arm).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..analysis import PART_ROWS, task_rows
from ..conventions import FloatArray
from ..errors import OptionError
from ..inverse import pinv
from ..model import Robot
from ..numeric import as_configuration, fk, jacobian
from .ik import IkResult, solve

__all__ = ["ToolPath", "line", "circle", "PathFollowing", "path_rows", "path_rates", "path_step", "follow"]

Omega = Callable[[float, FloatArray], FloatArray]
"""ω(t, q): the free joint motion projected into Ker J of a redundant arm."""


@dataclass(frozen=True)
class ToolPath:
    """y(t) of the tool point, t ∈ [0, duration] [s].

    Attributes:
        kind: "line" or "circle".
        start, end: The line's ends (3,) [m]; for a circle, its centre and a point of it.
        normal: The circle's plane normal (unit, 3,); unused for a line.
        duration: t_k − t₀ [s].
    """

    kind: str
    start: tuple[float, float, float]
    end: tuple[float, float, float]
    normal: tuple[float, float, float]
    duration: float

    def point(self, t: float) -> FloatArray:
        """y(t) [m]."""
        return self._at(t)[0]

    def velocity(self, t: float) -> FloatArray:
        """ẏ(t) [m/s]."""
        return self._at(t)[1]

    def _at(self, t: float) -> tuple[FloatArray, FloatArray]:
        a, b = np.array(self.start), np.array(self.end)
        if self.kind == "line":
            return a + (b - a) * (t / self.duration), (b - a) / self.duration
        u = b - a
        v = np.cross(np.array(self.normal), u)
        w = 2.0 * math.pi / self.duration
        c, s = math.cos(w * t), math.sin(w * t)
        return a + c * u + s * v, w * (-s * u + c * v)


def _point(p: npt.ArrayLike, what: str) -> tuple[float, float, float]:
    a = np.asarray(p, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.isfinite(a).all():
        raise OptionError(f"{what} must be a finite point (3,) [m], got {p!r}")
    return (float(a[0]), float(a[1]), float(a[2]))


def _duration(duration: float) -> float:
    if not (isinstance(duration, (int, float)) and 0.0 < duration < math.inf):
        raise OptionError(f"duration must be a positive number of seconds, got {duration!r}")
    return float(duration)


def line(start: npt.ArrayLike, end: npt.ArrayLike, duration: float = 1.0) -> ToolPath:
    """The straight line from ``start`` to ``end`` at constant speed."""
    return ToolPath("line", _point(start, "start"), _point(end, "end"), (0.0, 0.0, 1.0), _duration(duration))


def circle(
    centre: npt.ArrayLike, radius: float, normal: npt.ArrayLike = (0.0, 0.0, 1.0), duration: float = 1.0
) -> ToolPath:
    """The circle of ``radius`` [m] about ``centre`` in the plane of ``normal``, once round, counter-clockwise
    about the normal, starting on the side of the plane's first in-plane axis."""
    n = np.array(_point(normal, "normal"))
    if not (isinstance(radius, (int, float)) and 0.0 < radius < math.inf) or np.linalg.norm(n) == 0.0:
        raise OptionError(f"radius must be positive and normal non-zero, got {radius!r}, {normal!r}")
    n = n / np.linalg.norm(n)
    e = np.eye(3)[int(np.argmin(np.abs(n)))]
    u = np.cross(n, e)
    u = u / np.linalg.norm(u)
    c = np.array(_point(centre, "centre"))
    return ToolPath(
        "circle",
        _point(c, "centre"),
        _point(c + radius * u, "start"),
        _point(n, "normal"),
        _duration(duration),
    )


def path_rows(robot: Robot) -> list[int]:
    """The rows solved for: the position rows among the robot's task rows."""
    return [r for r in task_rows(robot) if r in PART_ROWS["linear"]]


def path_rates(
    robot: Robot, path: ToolPath, q: FloatArray, t: float, omega: Omega | None = None
) -> FloatArray:
    """q̇ = J⁺ ẏ(t) + (I − J⁺J) ω(t, q) (J⁻¹ ẏ for a square regular J; no ω term when ``omega`` is None)."""
    rows = path_rows(robot)
    J = jacobian(robot, q)[rows]
    Jp = pinv(J)
    qd = Jp @ path.velocity(t)[rows]
    if omega is not None:
        qd = qd + (np.eye(robot.dof) - Jp @ J) @ np.asarray(omega(t, q), dtype=float)
    return qd


def path_step(
    robot: Robot, path: ToolPath, q: FloatArray, t: float, dt: float, omega: Omega | None = None
) -> FloatArray:
    """q(t + dt) from q(t) by one classical Runge–Kutta step of :func:`path_rates` (pure)."""
    k1 = path_rates(robot, path, q, t, omega)
    k2 = path_rates(robot, path, q + 0.5 * dt * k1, t + 0.5 * dt, omega)
    k3 = path_rates(robot, path, q + 0.5 * dt * k2, t + 0.5 * dt, omega)
    k4 = path_rates(robot, path, q + dt * k3, t + dt, omega)
    return q + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


@dataclass(frozen=True, eq=False)
class PathFollowing:
    """What :func:`follow` computed.

    Attributes:
        t: Times (k + 1,) [s].
        q: q(t) (k + 1, n).
        qd: q̇(t) (k + 1, n), the rates of :func:`path_rates` at each sample.
        error: ‖y(t) − k(q(t))‖ (k + 1,) [m], the rows solved for.
        newton: The Newton solve of q(t₀).
    """

    t: FloatArray
    q: FloatArray
    qd: FloatArray
    error: FloatArray
    newton: IkResult


def follow(
    robot: Robot, path: ToolPath, q_guess: npt.ArrayLike, steps: int = 200, omega: Omega | None = None
) -> PathFollowing:
    """Newton for q(t₀) from ``q_guess``, then ``steps`` Runge–Kutta steps of q̇ = J⁺ẏ + (I − J⁺J)ω."""
    if not (isinstance(steps, int) and steps >= 1):
        raise OptionError(f"steps must be an int ≥ 1, got {steps!r}")
    rows = path_rows(robot)
    q0 = as_configuration(robot, q_guess)
    target = path.point(0.0)
    newton = solve(robot, target, q0, rows=tuple(rows), step_limit=0.5)
    times = np.linspace(0.0, path.duration, steps + 1)
    Q = np.empty((steps + 1, robot.dof))
    Q[0] = newton.q
    for i in range(steps):
        Q[i + 1] = path_step(robot, path, Q[i], float(times[i]), float(times[i + 1] - times[i]), omega)
    qd = np.array([path_rates(robot, path, Q[i], float(times[i]), omega) for i in range(steps + 1)])
    err = np.array(
        [
            np.linalg.norm((path.point(float(t)) - fk(robot, x)[:3, 3])[rows])
            for t, x in zip(times, Q, strict=True)
        ]
    )
    return PathFollowing(times, Q, qd, err, newton)
