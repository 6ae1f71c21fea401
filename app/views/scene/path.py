"""The tool's path in the 3-D view: the points the tool went through during the running motion, and the
path y(t) chosen in the Motion tab (:class:`PlannedPath`), drawn before it is followed.

A resolved-rate preset holds a constant v, so the path is the straight line the course promises (until
the singularity stops it); the self-motion's ghost and the path descent show their own. Drawn as one
line strip (at most :data:`MAX_POINTS` points, the latest always included) and hidden when no motion
has traced anything.
"""

from __future__ import annotations

import numpy as np
import viser

from ...core.snapshot import Snapshot
from ...core.state import LabState
from ..palette import PATH_RGB, PLANNED_RGB
from .geometry import finite, set_if_changed

__all__ = ["ToolPath", "PlannedPath", "MAX_POINTS", "path_points"]

MAX_POINTS = 300
"""Points sent for one path (the trace keeps up to 900): every k-th, and the last."""


def path_points(tool: np.ndarray) -> np.ndarray:
    """The points drawn for the traced tool points ``tool`` (k, 3): at most :data:`MAX_POINTS`, in order,
    the first and last included."""
    k = len(tool)
    if k <= MAX_POINTS:
        return np.asarray(tool, dtype=float)
    index = np.unique(np.r_[np.linspace(0, k - 1, MAX_POINTS).round().astype(int), k - 1])
    return np.asarray(tool, dtype=float)[index]


class ToolPath:
    """The line of the tool's path for one tab."""

    def __init__(self, scene: viser.SceneApi, root: str) -> None:
        self.line = scene.add_line_segments(
            f"{root}/tool_path",
            points=np.zeros((1, 2, 3), dtype=np.float32),
            colors=np.array(PATH_RGB, dtype=np.uint8),
            thickness=4.0,
            thickness_units="screen",
            visible=False,
        )
        self._of: object = None
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        trace = state.motion.trace
        shown = trace is not None and len(trace.tool) >= 2 and len(trace.tool) == len(trace)
        set_if_changed(self.line, "visible", shown)
        if not shown or trace is None:
            self.extent = np.zeros((0, 3))
            return
        if trace is not self._of:
            self._of = trace
            p = path_points(trace.tool)
            self.line.points = finite(np.stack([p[:-1], p[1:]], axis=1))
            self.extent = p

    def remove(self) -> None:
        self.line.remove()


class PlannedPath:
    """The chosen path y(t) for one tab (``snap.planned``): a wide sea-green polyline the tool's dark
    trace runs inside while it is followed; hidden when no path is chosen."""

    def __init__(self, scene: viser.SceneApi, root: str) -> None:
        self.line = scene.add_line_segments(
            f"{root}/planned_path",
            points=np.zeros((1, 2, 3), dtype=np.float32),
            colors=np.array(PLANNED_RGB, dtype=np.uint8),
            thickness=8.0,
            thickness_units="screen",
            visible=False,
        )
        self.points: np.ndarray | None = None
        """The polyline's points (k, 3) [m] as last drawn (``None``: hidden)."""
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        p = snap.planned
        set_if_changed(self.line, "visible", p is not None)
        if p is None:
            self.points, self.extent = None, np.zeros((0, 3))
            return
        if self.points is None or not np.array_equal(self.points, p):
            self.points = np.array(p, dtype=float)
            self.line.points = finite(np.stack([p[:-1], p[1:]], axis=1))
            self.extent = self.points

    def remove(self) -> None:
        self.line.remove()
