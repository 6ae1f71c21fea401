"""The J̇ q̇ arrow at the tool: the tool's acceleration when the joints turn at constant rates.

The course's ẍ = J q̈ + J̇ q̇ with q̈ = 0: the linear part of J̇ q̇ drawn from the
tool point, :data:`ACCEL_SCALE` metres per m/s² (the change of the tool's
velocity over one second, drawn at the velocity arrows' scale), in its own
colour (:data:`app.views.palette.ACCEL_RGB`). Shown while joint rates are set and the
option is on; never a non-finite point (the arrow's length is capped).
"""

from __future__ import annotations

import numpy as np
import viser

from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...viser_adapter import update_props
from ..palette import ACCEL_RGB
from .geometry import finite, set_if_changed
from .overlays import LINEAR_SECONDS

__all__ = ["AccelArrow", "ACCEL_SCALE"]

ACCEL_SCALE = LINEAR_SECONDS * 1.0
"""Drawn length [m] per [m/s²]: the velocity gained in 1 s, drawn like a velocity (0.5 m per m/s)."""
_CAP = 3.0
"""Longest arrow, in robot sizes (× scale)."""


class AccelArrow:
    """One arrow node for J̇ q̇ (its linear part) at the tool point."""

    def __init__(self, scene: viser.SceneApi, size: float, root: str) -> None:
        self.size = size
        r = 0.012 * size
        self.node = scene.add_arrows(
            f"{root}/jdot_qd",
            points=np.zeros((1, 2, 3), np.float32),
            colors=np.array([ACCEL_RGB], np.uint8),
            shaft_radius=r,
            head_radius=2.4 * r,
            head_length=6 * r,
            visible=False,
        )
        self.radius = r
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        a = snap.jdot_qd
        k = state.options.scale
        vector = np.zeros(3) if a is None else np.nan_to_num(np.asarray(a[:3], float)) * ACCEL_SCALE * k
        length = float(np.linalg.norm(vector))
        cap = _CAP * self.size * k
        if length > cap:
            vector *= cap / length
            length = cap
        show = state.options.jdot_arrow and bool(np.any(state.qd)) and length > max(1e-3, self.radius)
        self.extent = np.zeros((0, 3))
        if show:
            p = snap.tool_point
            points = finite(np.array([[p, p + vector]], np.float32))
            update_props(
                self.node, points=points, head_length=round(float(min(6 * self.radius, 0.4 * length)), 4)
            )
            self.extent = (p + vector)[None]
        set_if_changed(self.node, "visible", bool(show))

    def remove(self) -> None:
        self.node.remove()
