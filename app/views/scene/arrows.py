"""A batched arrows node of the scene (J's columns, lost translations, a Derive step's vectors)."""

from __future__ import annotations

import numpy as np
import viser

from ...viser_adapter import update_props
from .geometry import finite, set_if_changed

__all__ = ["Arrows"]

_MIN_LENGTH = 1e-3
"""Shortest arrow drawn [m]."""
_NO_POINTS = np.zeros((0, 3))
_NO_POINTS.flags.writeable = False


class Arrows:
    """One batched arrows node: only the arrows long enough to see are sent."""

    def __init__(self, scene: viser.SceneApi, name: str, radius: float) -> None:
        self.radius = radius
        self.node = scene.add_arrows(
            name,
            points=np.zeros((1, 2, 3), np.float32),
            colors=np.zeros((1, 3), np.uint8),
            shaft_radius=radius,
            head_radius=2.4 * radius,
            head_length=6 * radius,
            visible=False,
        )
        self._mask = b""
        self._colors: np.ndarray = np.zeros((0, 3), np.uint8)
        self.tips: np.ndarray = _NO_POINTS

    def hide(self) -> None:
        self.tips = _NO_POINTS
        set_if_changed(self.node, "visible", False)

    def set(self, starts: np.ndarray, vectors: np.ndarray, colors: np.ndarray, show: bool = True) -> None:
        """Arrows from ``starts`` (N, 3), or one start (3,) shared by all, along ``vectors`` (N, 3)."""
        if not show or not len(vectors):  # hidden: nothing to work out
            return self.hide()
        lengths = np.sqrt(np.einsum("ij,ij->i", vectors, vectors))  # NaN stays NaN, so it is not kept
        keep = (lengths > max(_MIN_LENGTH, self.radius)) & (lengths < np.inf)
        if not keep.any():
            return self.hide()
        ends = starts + vectors
        points = np.empty((len(vectors), 2, 3))
        points[:, 0] = starts
        points[:, 1] = ends
        mask = keep.tobytes()
        if not keep.all():
            points, ends, lengths = points[keep], ends[keep], lengths[keep]
        self.tips = ends
        head = round(min(6 * self.radius, 0.4 * float(lengths.min())), 4)
        change: dict = {"points": finite(points), "head_length": head}
        kept = np.asarray(colors[keep], np.uint8)
        if mask != self._mask or not np.array_equal(kept, self._colors):  # colours sent only when they change
            change["colors"] = kept
            self._mask, self._colors = mask, kept
        update_props(self.node, **change)  # points, colours and head together: one message
        set_if_changed(self.node, "visible", True)
