"""The explorer's scene nodes: the drag handle at the tool, the ghost of the held tool, the IK target
and the workspace cloud.

* **Drive the tool**: a transform gizmo at the tool pose. Dragging it dispatches
  :class:`~app.core.actions.DriveTool` with the handle's pose; the reducer solves IK and the arm follows.
  While the user drags, the server never moves the handle (that would fight the hand); on release it
  goes back onto the tool, so a target the arm could not reach is seen to snap back.
* **Ghost**: where the tool is held during self-motion and the manipulability climb (a translucent
  ball and a small triad): the student sees the tool stay put while the elbow moves.
* **Target**: a thin line from the tool to the dragged target when the solution departs from it
  (near a singularity the damped solution stops short).
* **Workspace cloud**: tool points of random configurations coloured by w (built once per robot).
"""

from __future__ import annotations

import numpy as np
import viser

from ...core.actions import DriveTool
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ..palette import DESIRED_RGB, LOST_RGB
from ..panel.common import Dispatch
from .geometry import finite, set_if_changed, wxyz

__all__ = ["DriveView"]

_DEPARTURE_SHOWN = 1e-3
"""A target farther than this from the tool [m] is drawn with a line to it."""


class DriveView:
    """Scene nodes of the explorer for one tab and robot.

    Args:
        scene: The tab's scene.
        dispatch: Where a drag goes.
        size: Length of the arm [m] (sizes of the handle and ghost).
        planar: A planar arm: the handle moves in the base x-y plane only.
        root: Scene path.
    """

    def __init__(
        self, scene: viser.SceneApi, dispatch: Dispatch, size: float, planar: bool, root: str
    ) -> None:
        self.scene = scene
        self.size = size
        self.root = root
        self.dragging = False
        self.gizmo = scene.add_transform_controls(
            f"{root}/handle",
            scale=0.3 * size,
            active_axes=(True, True, not planar),
            disable_rotations=True,
            depth_test=False,
            visible=False,
        )

        async def moved(event: viser.TransformControlsEvent) -> None:
            # async: runs on the event loop in order (start, updates, end); dispatch only queues.
            self.dragging = event.phase != "end"
            T = np.eye(4)
            T[:3, :3] = _matrix(np.asarray(event.target.wxyz, dtype=float))
            T[:3, 3] = np.asarray(event.target.position, dtype=float)
            if np.isfinite(T).all():
                dispatch(DriveTool(tuple(float(x) for x in T.ravel())))

        self.gizmo.on_update(moved)
        self.ghost = scene.add_icosphere(
            f"{root}/ghost", radius=0.045 * size, color=DESIRED_RGB, opacity=0.45, visible=False
        )
        self.ghost_frame = scene.add_frame(
            f"{root}/ghost_frame", axes_length=0.12 * size, axes_radius=0.006 * size, visible=False
        )
        self.target = scene.add_line_segments(
            f"{root}/target",
            points=np.zeros((1, 2, 3), dtype=np.float32),
            colors=np.array(LOST_RGB, dtype=np.uint8),
            thickness=3.0,
            thickness_units="screen",
            visible=False,
        )
        self.cloud: viser.PointCloudHandle | None = None
        self._cloud_of: object = None
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        """Place the handle, ghost, target line and cloud for ``snap``."""
        o = state.options
        T = snap.T_tool
        set_if_changed(self.gizmo, "visible", o.gizmo)
        set_if_changed(self.gizmo, "disable_rotations", o.ik_mode != "pose")
        if o.gizmo and not self.dragging:
            self.gizmo.position = finite(T[:3, 3])
            self.gizmo.wxyz = wxyz(T[:3, :3])
        anchor = state.motion.anchor
        held = anchor is not None
        set_if_changed(self.ghost, "visible", held)
        set_if_changed(self.ghost_frame, "visible", held)
        if anchor is not None:
            self.ghost.position = finite(anchor[:3, 3])
            self.ghost_frame.position = finite(anchor[:3, 3])
            self.ghost_frame.wxyz = wxyz(anchor[:3, :3])
        ik = state.motion.ik
        far = o.gizmo and ik is not None and ik.departure > _DEPARTURE_SHOWN
        set_if_changed(self.target, "visible", far)
        if far and ik is not None:
            self.target.points = finite(np.array([[T[:3, 3], ik.target]]))
        self._cloud(snap)
        self.extent = np.array([anchor[:3, 3]]) if anchor is not None else np.zeros((0, 3))

    def _cloud(self, snap: Snapshot) -> None:
        cloud = snap.cloud
        if cloud is None:
            if self.cloud is not None:
                set_if_changed(self.cloud, "visible", False)
            return
        if self.cloud is None or self._cloud_of is not cloud:
            if self.cloud is not None:
                self.cloud.remove()
            self.cloud = self.scene.add_point_cloud(
                f"{self.root}/cloud",
                points=finite(cloud.points),
                colors=cloud.colors,
                point_size=0.0025 * self.size,  # smaller dots: the arm stays visible among 20 000
                point_shape="circle",
            )
            self._cloud_of = cloud
        set_if_changed(self.cloud, "visible", True)

    def remove(self) -> None:
        for node in (self.gizmo, self.ghost, self.ghost_frame, self.target, self.cloud):
            if node is not None:
                node.remove()


def _matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of the unit quaternion (w, x, y, z) (normalised first)."""
    n = float(np.linalg.norm(q))
    w, x, y, z = q / n if n > 0 else (1.0, 0.0, 0.0, 0.0)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
