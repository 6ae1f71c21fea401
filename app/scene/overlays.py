"""What the Jacobian says, drawn at the tool: ellipsoids, column arrows, the lost direction, v = J q̇, F.

Scales (all multiplied by the client's scale option):

* linear quantities (J's linear columns, the velocity ellipsoid, the twist
  v = J q̇) are drawn at ``LINEAR_SECONDS`` × their value: a column of
  0.8 m/rad becomes a 0.4 m arrow, and since the columns are the images of
  the unit joint rates they end inside the ellipsoid, which is the image of
  the unit ball ‖q̇‖ ≤ 1;
* unitless directions (angular columns, rotational ellipsoid, lost direction)
  scale with the robot's size;
* the force ellipsoid (semi-axes 1/σ) is drawn at a scale that makes it equal
  to the velocity ellipsoid for σ = 0.4 × robot size, and capped at
  ``ELLIPSOID_CAP`` robot sizes, so at a singularity it becomes a long cigar
  instead of infinity.
"""

from __future__ import annotations

import numpy as np
import viser

from ..palette import (
    FORCE_ELLIPSOID_RGB,
    FORCE_RGB,
    LOST_ANGULAR_RGB,
    LOST_RGB,
    ROTATION_RGB,
    STATUS_RGB,
    TWIST_RGB,
    joint_color,
)
from ..snapshot import Snapshot
from ..state import Options
from .arm import ArmGeometry
from .geometry import TINY, finite, wxyz

__all__ = ["Overlays", "LINEAR_SECONDS", "ELLIPSOID_CAP"]

LINEAR_SECONDS = 0.5
"""Drawn length [m] per [m/s] of tool-point velocity (and per [m/rad] of a column)."""
ELLIPSOID_CAP = 1.2
"""Largest drawn ellipsoid semi-axis, in robot sizes (× scale): where a force ellipsoid goes to infinity."""
FORCE_SIGMA_REF = 0.4
"""The force ellipsoid (radii 1/σ) is drawn as LINEAR_SECONDS · σ_ref² / σ with σ_ref = this × robot size:
it coincides with the velocity ellipsoid where σ = σ_ref, and is long where that one is short."""
_MIN_LENGTH = 1e-3


class _Arrow:
    """One arrow node whose head stays in proportion to its length; hidden when too short to see."""

    def __init__(self, scene: viser.SceneApi, name: str, rgb: tuple[int, int, int], radius: float) -> None:
        self.radius = radius
        self.node = scene.add_arrows(
            name,
            points=np.zeros((1, 2, 3), np.float32),
            colors=np.array([rgb], np.uint8),
            shaft_radius=radius,
            head_radius=2.4 * radius,
            head_length=6 * radius,
            visible=False,
        )

    def set(self, start: np.ndarray, vector: np.ndarray, show: bool = True) -> None:
        length = float(np.linalg.norm(vector)) if np.isfinite(vector).all() else 0.0
        visible = bool(show and length > max(_MIN_LENGTH, self.radius))
        self.node.visible = visible
        if visible:
            self.node.head_length = float(min(6 * self.radius, 0.4 * length))
            self.node.points = finite(np.stack([start, start + vector])[None])


class _Ellipsoid:
    """An icosphere scaled to an ellipsoid; never thinner than :data:`TINY`, never infinite."""

    def __init__(self, scene: viser.SceneApi, name: str, rgb: tuple[int, int, int], opacity: float) -> None:
        self.node = scene.add_icosphere(
            name,
            radius=1.0,
            color=rgb,
            subdivisions=3,
            opacity=opacity,
            visible=False,
            cast_shadow=False,
            receive_shadow=False,
        )

    def set(self, center: np.ndarray, axes: np.ndarray, radii: np.ndarray, show: bool, cap: float) -> None:
        self.node.visible = show
        if show:
            r = np.clip(np.nan_to_num(radii, nan=0.0, posinf=cap), TINY, cap)
            self.node.scale = tuple(float(x) for x in r)
            self.node.wxyz = tuple(finite(wxyz(axes)))
            self.node.position = tuple(finite(center))


class Overlays:
    """The Jacobian's glyphs around the tool for one client."""

    def __init__(
        self, scene: viser.SceneApi, geometry: ArmGeometry, dof: int, planar: bool, root: str
    ) -> None:
        self.geometry = geometry
        self.planar = planar
        s = geometry.size
        self._status = ""
        self.velocity = _Ellipsoid(scene, f"{root}/velocity_ellipsoid", STATUS_RGB["regular"], 0.28)
        self.rotational = _Ellipsoid(scene, f"{root}/rotational_ellipsoid", ROTATION_RGB, 0.22)
        self.force = _Ellipsoid(scene, f"{root}/force_ellipsoid", FORCE_ELLIPSOID_RGB, 0.2)
        r = 0.009 * s
        self.columns = [_Arrow(scene, f"{root}/column_{i}", joint_color(i), r) for i in range(dof)]
        self.angular = [_Arrow(scene, f"{root}/angular_{i}", joint_color(i), 0.75 * r) for i in range(dof)]
        self.lost_v = _Arrow(scene, f"{root}/lost_linear", LOST_RGB, 1.6 * r)
        self.lost_w = _Arrow(scene, f"{root}/lost_angular", LOST_ANGULAR_RGB, 1.2 * r)
        self.lost_labels = [
            scene.add_label(f"{root}/lost_{part}_label", f"lost {part}", visible=False, anchor="bottom-left")
            for part in ("v", "ω")
        ]
        self.twist_v = _Arrow(scene, f"{root}/twist_linear", TWIST_RGB, 1.3 * r)
        self.twist_w = _Arrow(scene, f"{root}/twist_angular", ROTATION_RGB, 1.0 * r)
        self.force_arrow = _Arrow(scene, f"{root}/force", FORCE_RGB, 1.3 * r)
        self.moment_arrow = _Arrow(scene, f"{root}/moment", FORCE_RGB, 0.9 * r)
        self._nodes = [e.node for e in (self.velocity, self.rotational, self.force)]
        self._nodes += [
            a.node
            for a in (
                *self.columns,
                *self.angular,
                self.lost_v,
                self.lost_w,
                self.twist_v,
                self.twist_w,
                self.force_arrow,
                self.moment_arrow,
            )
        ]
        self._nodes += self.lost_labels

    def update(self, snap: Snapshot, options: Options, wrench: np.ndarray) -> None:
        """Redraw every glyph for ``snap``."""
        g, s, k = self.geometry, self.geometry.size, options.scale
        p = snap.tool_point
        J = snap.J_base
        status = snap.report.status
        lin = LINEAR_SECONDS * k
        unit = 0.2 * s * k  # drawn length of a unit direction (angular columns, lost direction)

        e = snap.velocity
        self.velocity.set(p, e.axes, e.radii * lin, options.velocity_ellipsoid, ELLIPSOID_CAP * s * k)
        if status != self._status:
            self.velocity.node.color = STATUS_RGB[status]
            self._status = status
        if snap.rotational is not None:
            e = snap.rotational
            self.rotational.set(
                p, e.axes, e.radii * 0.6 * unit, options.rotational_ellipsoid, ELLIPSOID_CAP * s * k
            )
        else:
            self.rotational.set(p, np.eye(3), np.zeros(3), False, 1.0)
        e = snap.force
        radii = e.radii * (lin * FORCE_SIGMA_REF**2 * s * s)
        if self.planar:  # a planar arm's force ellipse lies in the plane: flatten the out-of-plane axis
            radii = np.where(np.abs(e.axes[2]) > 0.99, 0.0, radii)
        self.force.set(p, e.axes, radii, options.force_ellipsoid, ELLIPSOID_CAP * s * k)

        for i, arrow in enumerate(self.columns):
            arrow.set(p, J[:3, i] * lin, options.columns)
        W = snap.joint_frames
        for i, arrow in enumerate(self.angular):
            arrow.set(W[g.first_axis[i], :3, 3], J[3:, i] * unit, options.angular_columns)

        singular = status != "regular"
        lost = snap.report.lost_twist  # unit [v; ω] direction of σmin (its parts drawn separately)
        for arrow, label, part in zip(
            (self.lost_v, self.lost_w), self.lost_labels, (lost[:3], lost[3:]), strict=True
        ):
            arrow.set(p, part * 2 * unit, singular)
            label.visible = arrow.node.visible
            if label.visible:
                label.position = tuple(finite(p + part * 2 * unit))

        self.twist_v.set(p, snap.twist[:3] * lin)
        self.twist_w.set(p, snap.twist[3:] * unit)
        self.force_arrow.set(p, wrench[:3] * 0.04 * s * k)
        self.moment_arrow.set(p, wrench[3:] * 0.04 * s * k)

    def remove(self) -> None:
        for node in self._nodes:
            node.remove()
