"""The Derive tab's step drawn in the 3-D view: the vectors the course's formula combines, named.

What each method draws is its record's ``draw`` (:data:`app.views.methods.METHODS`): the DH frames
i−1 and i; Whitney's axis, lever and column; the tool's path and its tangent; ω and v of the
link frames; the force, the lever and the axis turned by τᵢ.

Nothing is drawn when the tab walks through nothing, nor while another panel tab is open (the
option keeps the walk for when the Derive tab is opened again). One arrows node, one line node and a
few labels, so a step costs a handful of messages.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import viser

from kinematics import Robot

from ...core.i18n import Translator, translations
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import PATH_POINTS
from ...core.state import LabState
from ...viser_adapter import update_props
from ..methods import METHODS
from ..methods.common import AXIS_RGB, LEVER_RGB
from .arm import ArmGeometry
from .geometry import LABEL_CLEARANCE, LABEL_SCALE, clear_of, finite, set_if_changed
from .labels import anchor_label
from .overlays import LINEAR_SECONDS, Arrows

__all__ = ["DeriveScene", "AXIS_RGB", "LEVER_RGB"]

_LABELS = 6
_SEGMENTS = PATH_POINTS - 1


class DeriveScene:
    """Scene nodes of the Derive tab's step for one tab and robot."""

    def __init__(
        self,
        scene: viser.SceneApi,
        robot: Robot,
        geometry: ArmGeometry,
        root: str,
        joint_labels: Callable[[], np.ndarray] | None = None,
        tr: Translator | None = None,
        open_tab: Callable[[], str] | None = None,
    ) -> None:
        self.robot = robot
        self._open_tab = open_tab or (lambda: "")
        self.tr = tr or translations()
        self.geometry = geometry
        self._joint_labels = joint_labels or (lambda: np.zeros((0, 3)))
        s = geometry.size
        self.arrows = Arrows(scene, f"{root}/arrows", 0.008 * s)
        self.thin = Arrows(scene, f"{root}/thin_arrows", 0.004 * s)
        self.lines = scene.add_line_segments(
            f"{root}/lines",
            points=np.zeros((_SEGMENTS, 2, 3), np.float32),  # always this many: the page keeps the count
            colors=LEVER_RGB,
            thickness=4.0,
            thickness_units="screen",
            visible=False,
        )
        self.labels = [
            scene.add_label(
                f"{root}/label_{k}", "", visible=False, anchor="bottom-left", font_screen_scale=LABEL_SCALE
            )
            for k in range(_LABELS)
        ]
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        d = snap.derive
        if d is None or self._open_tab() not in ("", "derive"):  # the step is drawn on its own tab only
            self._hide()
            return
        unit = 0.2 * self.geometry.size * state.options.scale
        lin = LINEAR_SECONDS * state.options.scale
        arrows, thin, lines, labels = METHODS[d.method].draw(self.robot, d, snap, unit, lin, self.tr)
        labels = labels[:_LABELS]
        self._set(self.arrows, arrows)
        self._set(self.thin, thin)
        if lines:
            pts = np.array([[a, b] for a, b, _ in lines])
            if self.robot.planar:  # lifted off the floor grid the planar arm lies on (no depth fight)
                pts[..., 2] += 0.004 * self.geometry.size
            pad = _SEGMENTS - len(pts)  # unused segments: zero length at the first point
            pts = np.concatenate([pts, np.repeat(pts[:1, :1], pad, axis=0).repeat(2, axis=1)])
            rgb = np.array([c for _, _, c in lines] + [lines[0][2]] * pad, np.uint8)
            update_props(self.lines, points=finite(pts), colors=np.repeat(rgb[:, None], 2, axis=1))
        set_if_changed(self.lines, "visible", bool(lines))
        taken = self._joint_labels()
        for k, label in enumerate(self.labels):
            show = k < len(labels)
            set_if_changed(label, "visible", show)
            if show:
                text, where = labels[k]
                gap = LABEL_CLEARANCE * self.geometry.size
                where = clear_of(np.asarray(where, float), taken, gap, self.robot.planar)
                taken = np.vstack([taken, where])
                set_if_changed(label, "text", text)
                anchor_label(label, finite(where))
        tips = [self.arrows.tips, self.thin.tips] + [np.array([a, b]) for a, b, _ in lines]
        self.extent = (
            np.concatenate([t for t in tips if len(t)]) if any(len(t) for t in tips) else np.zeros((0, 3))
        )

    @staticmethod
    def _set(node: Arrows, items: list) -> None:
        if not items:
            node.set(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3), np.uint8), show=False)
            return
        starts = np.array([a for a, _, _ in items], float)
        vectors = np.array([v for _, v, _ in items], float)
        node.set(starts, vectors, np.array([c for _, _, c in items], np.uint8))

    def _hide(self) -> None:
        self._set(self.arrows, [])
        self._set(self.thin, [])
        set_if_changed(self.lines, "visible", False)
        for label in self.labels:
            set_if_changed(label, "visible", False)
        self.extent = np.zeros((0, 3))

    def remove(self) -> None:
        for node in (self.arrows.node, self.thin.node, self.lines, *self.labels):
            node.remove()
