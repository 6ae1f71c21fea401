"""The 3-D view of one client: the arm and the Jacobian's glyphs, built once per robot.

:class:`SceneView` owns every scene node of a client. It is created for a
robot (nodes built once), updated for every snapshot (nodes moved, inside
the session's ``atomic`` batch), and removed when the client switches robot
or leaves.
"""

from __future__ import annotations

import numpy as np
import viser

from kinematics import Robot

from ..snapshot import Snapshot
from ..state import LabState
from .arm import ArmGeometry, ArmView
from .overlays import Overlays

__all__ = ["SceneView", "ArmGeometry"]


class SceneView:
    """Scene nodes of one client for one robot."""

    def __init__(self, client: viser.ClientHandle, robot: Robot, root: str = "/lab") -> None:
        self.client = client
        self.arm = ArmView(client.scene, client, robot, f"{root}/arm")
        self.overlays = Overlays(client.scene, self.arm.geometry, robot.dof, robot.planar, f"{root}/jacobian")
        self._framing: tuple | None = None

    @property
    def size(self) -> float:
        """Length of the drawn chain at home [m]."""
        return self.arm.geometry.size

    def update(self, snap: Snapshot, state: LabState) -> None:
        """Move every node to ``snap`` (call inside ``client.atomic()``)."""
        self.arm.update(snap, state.options)
        self.overlays.update(snap, state.options, state.wrench)

    def frame_camera(self, snap: Snapshot, planar: bool) -> None:
        """Point the client's camera at the arm from a three-quarter view (from above for a planar arm).

        The distance fits the arm and its ellipsoid in the narrower of the two fields of view.
        """
        pts = snap.link_frames[:, :3, 3]
        center = (pts.min(axis=0) + pts.max(axis=0)) / 2
        radius = float(np.linalg.norm(pts - center, axis=1).max()) + 0.25 * self.size
        cam = self.client.camera
        fov = float(cam.fov) if np.isfinite(cam.fov) and cam.fov > 0.1 else 1.0
        aspect = float(cam.aspect) if cam.image_height > 0 else 1.0
        half = min(fov, 2 * np.arctan(np.tan(fov / 2) * aspect)) / 2
        direction = np.array([0.25, -0.35, 1.6]) if planar else np.array([1.25, -1.45, 0.8])
        position = center + direction / np.linalg.norm(direction) * radius / np.sin(half)
        cam.up_direction = (0.0, 0.0, 1.0)
        cam.position = tuple(float(x) for x in position)
        cam.look_at = tuple(float(x) for x in center)  # after position: setting position moves look_at along
        self._framing = (position, aspect, snap, planar)

    def follow_canvas(self) -> None:
        """Frame again when the canvas changed shape (panels docking, window resized), unless the user
        has moved the camera since the app placed it."""
        if self._framing is None:
            return
        position, aspect, snap, planar = self._framing
        cam = self.client.camera
        if cam.image_height <= 0 or abs(cam.aspect - aspect) < 0.05 * aspect:
            return
        if np.linalg.norm(cam.position - position) > 1e-3 * (1.0 + np.linalg.norm(position)):
            self._framing = None  # the user took the camera: leave it alone
            return
        self.frame_camera(snap, planar)

    def remove(self) -> None:
        """Remove every node (on robot switch or disconnect)."""
        self.overlays.remove()
        self.arm.remove()
