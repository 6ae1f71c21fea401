"""What each input may hold, per robot: slider ranges, steps, and the values sliders snap to.

One source for the views (slider min, max, step) and the reducer (clamping a
typed value, snapping to a named configuration), so the number in a box is
always the number in the maths. Pure functions of the robot.

Joint limits bound the sliders, never the maths: a named configuration that
lies outside the limits widens the slider so it can be shown; a value typed
beyond the range is clamped, in the box and in the state alike.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from kinematics import Robot
from kinematics.singularity.lost import characteristic_length

__all__ = [
    "Range",
    "joint_ranges",
    "rate_ranges",
    "accel_ranges",
    "twist_ranges",
    "wrench_ranges",
    "snap_joint",
    "to_display",
    "from_display",
    "unit_of",
    "SNAP_DEGREES",
    "reach",
]

SNAP_DEGREES = 0.75
"""A revolute slider within this many degrees of a named configuration's value lands on it exactly."""
SNAP_METRES = 0.002
"""... and a prismatic slider within this many metres."""


@dataclass(frozen=True)
class Range:
    """An input's range in display units (degrees for revolute joints and their rates).

    Attributes:
        lo, hi: Ends of the slider [display units].
        step: Slider step [display units].
        unit: Display unit ("°", "m", "°/s", "m/s", "N", "N·m").
        degrees: True when display = degrees of a radian quantity.
    """

    lo: float
    hi: float
    step: float
    unit: str
    degrees: bool

    def clamp_si(self, value: float) -> float:
        """``value`` [SI] clamped to the range."""
        lo, hi = from_display(self, self.lo), from_display(self, self.hi)
        return float(min(max(value, lo), hi))


def unit_of(kind: str) -> str:
    """Slider unit of a joint kind: "°" or "m"."""
    return "°" if kind == "revolute" else "m"


def to_display(r: Range, value: float) -> float:
    """SI value in the range's display units."""
    return math.degrees(value) if r.degrees else float(value)


def from_display(r: Range, value: float) -> float:
    """Display value in SI units."""
    return math.radians(value) if r.degrees else float(value)


@functools.lru_cache(maxsize=64)  # bounded: every edit of a DH table makes a new robot
def reach(robot: Robot) -> float:
    """The robot's characteristic length [m], cached
    (:func:`~kinematics.singularity.lost.characteristic_length`)."""
    return characteristic_length(robot)


def _outward(lo: float, hi: float, step: float) -> tuple[float, float]:
    """Ends rounded outwards to whole steps (no float noise in the box)."""
    return math.floor(lo / step + 1e-9) * step, math.ceil(hi / step - 1e-9) * step


@functools.lru_cache(maxsize=64)  # bounded: every edit of a DH table makes a new robot
def joint_ranges(robot: Robot) -> tuple[Range, ...]:
    """Slider range of every joint: its limits, widened to hold home and every named configuration.

    Joints without limits get ±180° or ±(reach) metres.
    """
    reach_m = reach(robot)
    values = np.array([robot.home, *(c.q for c in robot.configurations)])
    out = []
    for i, joint in enumerate(robot.joints):
        revolute = joint.kind == "revolute"
        step = 0.1 if revolute else _prismatic_step(reach_m)
        if joint.qlim is not None:
            lo, hi = joint.qlim
        else:
            lo, hi = (-math.pi, math.pi) if revolute else (-reach_m, reach_m)
        lo, hi = min(lo, values[:, i].min()), max(hi, values[:, i].max())
        if revolute:
            lo, hi = math.degrees(lo), math.degrees(hi)
        lo, hi = _outward(lo, hi, step)
        out.append(Range(round(lo, 6), round(hi, 6), step, unit_of(joint.kind), revolute))
    return tuple(out)


def _prismatic_step(reach: float) -> float:
    """A prismatic slider step: 1 mm on a 1 m arm, 1 cm on a 10 m one."""
    return float(10 ** math.floor(math.log10(max(reach, 1e-3)) - 3 + 0.5))


@functools.lru_cache(maxsize=64)  # bounded: every edit of a DH table makes a new robot
def rate_ranges(robot: Robot) -> tuple[Range, ...]:
    """Joint-rate sliders: ±180 °/s for revolute joints, ±(slider span) per second for prismatic ones."""
    out = []
    for joint, r in zip(robot.joints, joint_ranges(robot), strict=True):
        if joint.kind == "revolute":
            out.append(Range(-180.0, 180.0, 1.0, "°/s", True))
        else:
            span = max(abs(r.lo), abs(r.hi), 1.0)
            out.append(Range(-span, span, r.step, "m/s", False))
    return tuple(out)


@functools.lru_cache(maxsize=64)  # bounded: every edit of a DH table makes a new robot
def accel_ranges(robot: Robot) -> tuple[Range, ...]:
    """Joint-acceleration sliders q̈: ±360 °/s² for revolute joints, ±(rate span) per second for
    prismatic ones (a rate slider's whole span gained in one second)."""
    out = []
    for r in rate_ranges(robot):
        if r.degrees:
            out.append(Range(-360.0, 360.0, 1.0, "°/s²", True))
        else:
            out.append(Range(r.lo, r.hi, r.step, "m/s²", False))
    return tuple(out)


@functools.lru_cache(maxsize=64)  # bounded: every edit of a DH table makes a new robot
def twist_ranges(robot: Robot) -> tuple[Range, ...]:
    """Desired-twist sliders [vx vy vz ωx ωy ωz]: ±2 reach per second (at least 1 m/s) and ±180 °/s."""
    span = float(max(1.0, math.ceil(2.0 * reach(robot))))
    step = 0.01 if span <= 5 else 0.1 if span <= 50 else 1.0
    linear = Range(-span, span, step, "m/s", False)
    angular = Range(-180.0, 180.0, 1.0, "°/s", True)
    return (linear,) * 3 + (angular,) * 3


@functools.lru_cache(maxsize=64)  # bounded: every edit of a DH table makes a new robot
def wrench_ranges(robot: Robot) -> tuple[Range, ...]:
    """Wrench sliders [Fx Fy Fz Mx My Mz]: ±20 N and ±10 N·m (scaled up for large arms)."""
    scale = float(max(1.0, 10 ** math.floor(math.log10(max(reach(robot), 1.0)))))
    return (Range(-20.0 * scale, 20.0 * scale, 0.5, "N", False),) * 3 + (
        Range(-10.0 * scale, 10.0 * scale, 0.25, "N·m", False),
    ) * 3


def snap_joint(robot: Robot, i: int, value: float, previous: float) -> float:
    """``value`` [rad | m] of joint ``i`` moved onto a named configuration's value when it arrives near one.

    Coming from farther than :data:`SNAP_DEGREES` (revolute) or :data:`SNAP_METRES` (prismatic) away
    from home's or a named configuration's value, and landing within it, the joint lands exactly on it,
    so a student can put the arm exactly on a singularity. Leaving it (``previous`` already near it) is
    never held back: fine steps away from a named value are kept.
    """
    tol = math.radians(SNAP_DEGREES) if robot.joints[i].kind == "revolute" else SNAP_METRES
    candidates = [float(robot.home[i]), *(float(c.q[i]) for c in robot.configurations)]
    best = min(candidates, key=lambda c: abs(c - value))
    if abs(best - value) <= tol and abs(best - previous) > tol:
        return best
    return float(value)
