"""The 3-D view of one tab: the arm and the Jacobian's glyphs, built once per robot.

:class:`SceneView` owns every scene node of a tab. It is created for a
robot (nodes built once), updated for every snapshot (nodes moved, inside
the session's ``atomic`` batch), and removed when the tab switches robot
or leaves. After each update :attr:`SceneView.extent` holds the points the
camera must keep in view.
"""

from __future__ import annotations

import numpy as np
import viser

from kinematics import Robot

from ...core.snapshot import Snapshot
from ...core.state import LabState
from ..panel.common import Dispatch
from .accel import AccelArrow
from .arm import ArmGeometry, ArmView
from .derive import DeriveScene
from .drive import DriveView
from .overlays import Overlays
from .path import ToolPath

__all__ = ["SceneView", "ArmGeometry"]


class SceneView:
    """Scene nodes of one tab for one robot.

    ``client``: the tab's client handle, or a whole server (its shared scene: what ``jacobian-lab
    record`` draws and records).
    """

    def __init__(
        self,
        client: viser.ClientHandle | viser.ViserServer,
        robot: Robot,
        dispatch: Dispatch | None = None,
        root: str = "/lab",
    ) -> None:
        self.arm = ArmView(client, robot, f"{root}/arm")
        self.overlays = Overlays(client.scene, self.arm.geometry, robot.dof, robot.planar, f"{root}/jacobian")
        self.derive = DeriveScene(client.scene, robot, self.arm.geometry, f"{root}/derive")
        self.accel = AccelArrow(client.scene, self.size, f"{root}/jacobian")
        self.path = ToolPath(client.scene, f"{root}/motion")
        self.drive = DriveView(
            client.scene, dispatch or (lambda action: None), self.size, robot.planar, f"{root}/drive"
        )

    @property
    def size(self) -> float:
        """Length of the drawn chain at home [m]."""
        return self.arm.geometry.size

    @property
    def extent(self) -> np.ndarray:
        """Points (N, 3) [m] of everything drawn at the last update: arm, ellipsoids, arrow tips."""
        parts = [
            self.overlays.extent,
            self.drive.extent,
            self.accel.extent,
            self.derive.extent,
            self.path.extent,
        ]
        return np.concatenate([x for x in parts if len(x)]) if any(len(x) for x in parts[1:]) else parts[0]

    def update(self, snap: Snapshot, state: LabState) -> None:
        """Move every node to ``snap`` (call inside ``client.atomic()``)."""
        self.arm.update(snap, state.options)
        self.overlays.update(snap, state)
        self.accel.update(snap, state)
        self.drive.update(snap, state)
        self.path.update(state)
        self.derive.update(snap, state)

    def remove(self) -> None:
        """Remove every node (on robot switch or disconnect)."""
        self.drive.remove()
        self.path.remove()
        self.derive.remove()
        self.accel.remove()
        self.overlays.remove()
        self.arm.remove()
