"""What a tab's motion is doing: which motion Play runs, where it started and what it has traced.

Part of the frozen :class:`~app.core.state.LabState` (``state.motion``), changed only by the reducer.
Four motions run on the tab's ticker, one :class:`~app.core.actions.Step` per frame:

* ``"joints"``: the joints move at the rates q̇ of the v = J q̇ view;
* ``"resolved_rate"``: the course's q_{k+1} = q_k + Δt J⁺ v, the desired tool twist held;
* ``"climb"``: q̇ = (I − J⁺J) ∇w, Yoshikawa's w climbing with the tool held;
* ``"path"``: a path computed beforehand (the descent to the nearest singularity) played back.

Everything traced is finite (κ is capped at :data:`KAPPA_CAP` for the charts), so no NaN and no
infinity ever reaches a chart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from kinematics import Robot

from .ranges import joint_ranges

__all__ = [
    "MotionState",
    "Trace",
    "IkInfo",
    "MOTIONS",
    "TRACE_LENGTH",
    "KAPPA_CAP",
    "readonly",
    "MotionRefused",
    "slider_bounds",
]

MOTIONS = ("joints", "resolved_rate", "climb", "path")
TRACE_LENGTH = 900
"""Samples kept for the charts (30 s at 30 frames per second); older ones are dropped."""
KAPPA_CAP = 1e8
"""κ beyond this is charted as this (κ = ∞ at a singularity)."""


def readonly(a: object, dtype: type = float) -> np.ndarray:
    """A read-only copy of ``a``."""
    out: np.ndarray = np.array(a, dtype=dtype)
    out.flags.writeable = False
    return out


@dataclass(frozen=True, eq=False)
class Trace:
    """Measures along a motion, one sample per frame (all finite).

    Attributes:
        t: Time or motion parameter of each sample (k,) [s, or rad / m of self-motion].
        sigma_min: Smallest singular value of the task rows (k,).
        kappa: Condition number of the task rows, capped at :data:`KAPPA_CAP` (k,).
        w: Yoshikawa's manipulability of the task rows (k,).
        qd: Joint rates (k, n) [rad/s | m/s].
        tool: The tool point at each sample (k, 3) [m] (base frame): the path drawn in the 3-D view.
    """

    t: np.ndarray
    sigma_min: np.ndarray
    kappa: np.ndarray
    w: np.ndarray
    qd: np.ndarray
    tool: np.ndarray = field(default_factory=lambda: readonly(np.zeros((0, 3))))

    @classmethod
    def empty(cls, n: int) -> Trace:
        z = readonly(np.zeros(0))
        return cls(z, z, z, z, readonly(np.zeros((0, n))), readonly(np.zeros((0, 3))))

    def __len__(self) -> int:
        return int(self.t.shape[0])

    def append(
        self, t: float, sigma_min: float, kappa: float, w: float, qd: np.ndarray, tool: object = None
    ) -> Trace:
        """This trace with one more sample (the oldest dropped beyond :data:`TRACE_LENGTH`); ``tool``: the
        tool point [m] (the last one again when not given)."""
        keep = slice(-TRACE_LENGTH + 1, None) if len(self) >= TRACE_LENGTH else slice(None)
        kappa = float(kappa) if np.isfinite(kappa) else KAPPA_CAP
        qd = np.where(np.isfinite(qd), qd, 0.0)
        last = self.tool[-1] if len(self.tool) else np.zeros(3)
        point = np.asarray(tool if tool is not None else last, dtype=float).reshape(3)
        point = np.where(np.isfinite(point), point, last)
        tools = self.tool if len(self.tool) == len(self) else np.zeros((len(self), 3))
        return Trace(
            readonly(np.append(self.t[keep], t)),
            readonly(np.append(self.sigma_min[keep], _finite(sigma_min))),
            readonly(np.append(self.kappa[keep], min(kappa, KAPPA_CAP))),
            readonly(np.append(self.w[keep], _finite(w))),
            readonly(np.vstack([self.qd[keep], qd[None, :]])),
            readonly(np.vstack([tools[keep], point[None, :]])),
        )


def _finite(x: float) -> float:
    return float(x) if np.isfinite(x) else 0.0


@dataclass(frozen=True)
class IkInfo:
    """The last solve of "drive the tool".

    Attributes:
        method: "dls" or "newton".
        iterations: Iterations taken.
        converged: Whether the error fell below the tolerance.
        residual: Norm of the final task error [m, rad].
        departure: Distance from the target point to the tool point reached [m].
        target: The target point (3,) [m] (base frame).
    """

    method: str
    iterations: int
    converged: bool
    residual: float
    departure: float
    target: tuple[float, float, float]


@dataclass(frozen=True, eq=False)
class MotionState:
    """A tab's motion.

    Attributes:
        kind: What Play runs (one of :data:`MOTIONS`).
        start: q where the motion started (Reset goes back there), or ``None``.
        preset: Name of the preset it came from ("" when none).
        path: Configurations (k, n) played back by the ``"path"`` motion, or ``None``.
        index: Where the playback is on ``path``.
        found: What the path leads to, said when it ends.
        trace: Measures along the motion (for the charts).
        s: Self-motion parameter [rad | m along the null space].
        anchor: T_base_tool (4, 4) held by self-motion and the climb (drawn as a ghost), or ``None``.
        self_trace: (s, w) samples of the self-motion, shape (k, 2).
        direction: The null-space direction of increasing s (n,) (kept so s keeps its sense).
        ik: The last "drive the tool" solve, or ``None``.
        pace: The motion's time per second of the clock and unit speed at the last step (1: as fast as
            the speed option says; less near a singularity, see :mod:`app.core.pacing`).
        solutions: The IK solutions (k, n) of ``pose`` found on request (elbow up / down, wrist flip …),
            nearest to where the arm stood first, or ``None``.
        pose: T_base_tool (4, 4) whose solutions they are.
    """

    kind: str = "joints"
    start: np.ndarray | None = None
    preset: str = ""
    path: np.ndarray | None = None
    index: int = 0
    found: str = ""
    trace: Trace | None = None
    s: float = 0.0
    anchor: np.ndarray | None = None
    self_trace: np.ndarray = field(default_factory=lambda: readonly(np.zeros((0, 2))))
    direction: np.ndarray | None = None
    ik: IkInfo | None = None
    pace: float = 1.0
    solutions: np.ndarray | None = None
    pose: np.ndarray | None = None

    def replace(self, **changes: object) -> MotionState:
        return replace(self, **changes)  # type: ignore[arg-type]


class MotionRefused(ValueError):
    """A motion that cannot start here (the message says why, in words: a catalogs' sentence made with
    :func:`kinematics.text.words`, so a tab says it in its language)."""


def slider_bounds(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """The joints' slider ends [rad | m] (lower, upper): where a motion stops."""
    ranges = joint_ranges(robot)
    lo = np.array([r.clamp_si(-math.inf) for r in ranges])
    hi = np.array([r.clamp_si(math.inf) for r in ranges])
    return lo, hi
