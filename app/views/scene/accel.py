"""The acceleration map's two arrows at the tool: J̇ q̇ (violet) and J q̈ (magenta).

The course's ẍ = J q̈ + J̇ q̇: the linear part of each term drawn from the tool point,
:data:`ACCEL_SCALE` metres per m/s² (the change of the tool's velocity over one second, drawn at
the velocity arrows' scale), each in its own colour (:data:`app.views.palette.ACCEL_RGB`,
:data:`app.views.palette.JQDD_RGB`). J̇ q̇ is shown while joint rates are set, J q̈ while joint
accelerations are, both while the option is on; never a non-finite point (each length is capped).
"""

from __future__ import annotations

import numpy as np
import viser

from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...viser_adapter import update_props
from ..palette import ACCEL_RGB, JQDD_RGB
from .geometry import finite, set_if_changed
from .overlays import LINEAR_SECONDS

__all__ = ["AccelArrow", "ACCEL_SCALE"]

ACCEL_SCALE = LINEAR_SECONDS * 1.0
"""Drawn length [m] per [m/s²]: the velocity gained in 1 s, drawn like a velocity (0.5 m per m/s)."""
_CAP = 3.0
"""Longest arrow, in robot sizes (× scale)."""


class _Arrow:
    """One arrow node at the tool point for the linear part of one acceleration term."""

    def __init__(self, scene: viser.SceneApi, name: str, rgb: tuple[int, int, int], r: float) -> None:
        self.node = scene.add_arrows(
            name,
            points=np.zeros((1, 2, 3), np.float32),
            colors=np.array([rgb], np.uint8),
            shaft_radius=r,
            head_radius=2.4 * r,
            head_length=6 * r,
            visible=False,
        )
        self.radius = r

    def update(self, a: np.ndarray | None, on: bool, tool: np.ndarray, k: float, cap: float) -> np.ndarray:
        """Draw ``a`` (6,) from ``tool`` when ``on``; the tip drawn (1, 3), or (0, 3) when hidden."""
        vector = np.zeros(3) if a is None else np.nan_to_num(np.asarray(a[:3], float)) * ACCEL_SCALE * k
        length = float(np.linalg.norm(vector))
        if length > cap:
            vector *= cap / length
            length = cap
        show = on and length > max(1e-3, self.radius)
        if show:
            points = finite(np.array([[tool, tool + vector]], np.float32))
            update_props(
                self.node, points=points, head_length=round(float(min(6 * self.radius, 0.4 * length)), 4)
            )
        set_if_changed(self.node, "visible", bool(show))
        return (tool + vector)[None] if show else np.zeros((0, 3))

    def remove(self) -> None:
        self.node.remove()


class AccelArrow:
    """The J̇ q̇ arrow (node ``jdot_qd``) and the J q̈ arrow (node ``j_qdd``) at the tool point."""

    def __init__(self, scene: viser.SceneApi, size: float, root: str) -> None:
        self.size = size
        r = 0.012 * size
        self.jdot = _Arrow(scene, f"{root}/jdot_qd", ACCEL_RGB, r)
        self.jqdd = _Arrow(scene, f"{root}/j_qdd", JQDD_RGB, r)
        self.node = self.jdot.node  # the J̇ q̇ arrow, as before
        self.qdd_node = self.jqdd.node
        self.radius = r
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        k = state.options.scale
        cap = _CAP * self.size * k
        on = state.options.jdot_arrow
        tool = snap.tool_point
        tips = [
            self.jdot.update(snap.jdot_qd, on and bool(np.any(state.qd)), tool, k, cap),
            self.jqdd.update(snap.j_qdd, on and bool(np.any(state.qdd)), tool, k, cap),
        ]
        self.extent = np.concatenate(tips)

    def remove(self) -> None:
        self.jdot.remove()
        self.jqdd.remove()
