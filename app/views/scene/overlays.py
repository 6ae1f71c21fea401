"""The Jacobian's glyphs at the tool: ellipsoids, column arrows, lost direction, twist and force.

Scales, so sizes mean something:

* linear quantities are drawn :data:`LINEAR_SECONDS` metres per m/s (per
  m/rad for a column), so the column arrows (images of unit joint rates)
  end inside the ellipsoid, which is the image of the unit ball ‖q̇‖ ≤ 1;
* unitless directions (angular columns, rotational ellipsoid, lost direction)
  scale with the robot's size;
* the force ellipsoid (semi-axes 1/σ) coincides with the velocity ellipsoid
  where σ = FORCE_SIGMA_REF × size, and is capped at ``ELLIPSOID_CAP`` sizes,
  so at a singularity it becomes a long cigar instead of infinity.

Cheap to redraw: all column arrows are one batched node, all angular
columns another, and the twist, desired twist, force and moment arrows a
third; an ellipsoid is a unit sphere whose scale and orientation change;
hidden glyphs cost nothing.
"""

from __future__ import annotations

import numpy as np
import viser

from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...viser_adapter import set_pose, update_props
from ..palette import (
    DESIRED_RGB,
    FORCE_ELLIPSOID_RGB,
    FORCE_RGB,
    LOST_RGB,
    ROTATION_ELLIPSOID_RGB,
    STATUS_RGB,
    TWIST_ANGULAR_RGB,
    TWIST_RGB,
    joint_color,
)
from .arm import ArmGeometry
from .geometry import TINY, finite, finite_tuple, set_if_changed, wxyz_one

__all__ = ["Overlays", "Arrows", "LINEAR_SECONDS", "ELLIPSOID_CAP", "SHOWN_SHARE"]

LINEAR_SECONDS = 0.5
"""Drawn length [m] per [m/s] of tool-point velocity (and per [m/rad] of a column)."""
ELLIPSOID_CAP = 1.2
"""Largest drawn ellipsoid semi-axis, in robot sizes (× scale): where a force ellipsoid goes to infinity."""
FORCE_SIGMA_REF = 0.4
SHOWN_SHARE = 0.1
"""A lost translation (rotation) is drawn when it carries at least this share of the lost direction."""
_MIN_LENGTH = 1e-3


_NO_POINTS = np.zeros((0, 3))
_EYE, _ZERO3 = np.eye(3), np.zeros(3)
_LOST_COLORS = np.array([LOST_RGB], np.uint8)
for _a in (_NO_POINTS, _EYE, _ZERO3, _LOST_COLORS):
    _a.flags.writeable = False


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
        self._drawn: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    @property
    def extent(self) -> np.ndarray:
        """The ends of the drawn semi-axes (6, 3) [m] (none when hidden)."""
        if self._drawn is None:
            return _NO_POINTS
        center, axes, r = self._drawn
        return center + np.concatenate([axes * r, -(axes * r)], axis=1).T

    def set(self, center: np.ndarray, axes: np.ndarray, radii: np.ndarray, show: bool, cap: float) -> None:
        set_if_changed(self.node, "visible", bool(show))
        if not show:
            self._drawn = None
            return
        # NaN → TINY, +inf → cap, in plain Python (three numbers: cheaper than NumPy's nan_to_num and clip)
        r = tuple(min(max(x, TINY), cap) if x == x else TINY for x in np.asarray(radii, float).tolist())
        update_props(self.node, scale=r)
        set_pose(self.node, finite_tuple(center), wxyz_one(axes))
        self._drawn = (np.asarray(center, float), np.asarray(axes, float), np.array(r))


def _ring(center: np.ndarray, axis: np.ndarray, radius: float, segments: int = 28) -> np.ndarray:
    """Line segments (segments, 2, 3) of a circle about ``axis`` through ``center``."""
    helper = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1, 0])
    e1 = np.cross(axis, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    t = np.linspace(0.0, 2 * np.pi * 0.85, segments + 1)  # an open ring: it reads as a turn
    pts = center + radius * (np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2)
    return np.stack([pts[:-1], pts[1:]], axis=1)


class Overlays:
    """The Jacobian's glyphs around the tool for one tab."""

    def __init__(
        self, scene: viser.SceneApi, geometry: ArmGeometry, dof: int, planar: bool, root: str
    ) -> None:
        self.geometry = geometry
        self.planar = planar
        s = geometry.size
        self._status = ""
        self.velocity = _Ellipsoid(scene, f"{root}/velocity_ellipsoid", STATUS_RGB["regular"], 0.28)
        self.rotational = _Ellipsoid(scene, f"{root}/rotational_ellipsoid", ROTATION_ELLIPSOID_RGB, 0.22)
        self.force = _Ellipsoid(scene, f"{root}/force_ellipsoid", FORCE_ELLIPSOID_RGB, 0.2)
        r = 0.009 * s
        self._joint_colors = np.array([joint_color(i) for i in range(dof)], np.uint8)
        self.columns = Arrows(scene, f"{root}/columns", r)
        self.angular = Arrows(scene, f"{root}/angular_columns", 0.75 * r)
        self.motion = Arrows(scene, f"{root}/twist_and_force", 1.2 * r)
        self.lost_v = Arrows(scene, f"{root}/lost_translation", 1.6 * r)
        self.lost_w = scene.add_line_segments(
            f"{root}/lost_rotation",
            points=np.zeros((1, 2, 3), np.float32),
            colors=LOST_RGB,
            thickness=4.0,
            thickness_units="screen",
            visible=False,
        )
        self.lost_labels = {
            part: scene.add_label(f"{root}/lost_{part}_label", text, visible=False, anchor="bottom-left")
            for part, text in (("v", "lost translation"), ("w", "lost rotation axis"))
        }
        self._nodes: list = [e.node for e in (self.velocity, self.rotational, self.force)]
        self._nodes += [a.node for a in (self.columns, self.angular, self.motion, self.lost_v)]
        self._nodes += [self.lost_w, *self.lost_labels.values()]
        self._links: np.ndarray = _NO_POINTS
        self._motion_colors = np.array(
            [TWIST_RGB, TWIST_ANGULAR_RGB, DESIRED_RGB, FORCE_RGB, FORCE_RGB], np.uint8
        )

    @property
    def extent(self) -> np.ndarray:
        """Points (N, 3) [m] of everything drawn at the last update: arm, ellipsoids, arrow tips
        (gathered only when asked: the camera needs them after a jump, not on every redraw)."""
        parts = [
            self._links,
            self.velocity.extent,
            self.rotational.extent,
            self.force.extent,
            self.columns.tips,
            self.angular.tips,
            self.motion.tips,
            self.lost_v.tips,
        ]
        return np.concatenate([x for x in parts if len(x)])

    def update(self, snap: Snapshot, state: LabState) -> None:
        """Redraw every glyph for ``snap``."""
        options, wrench = state.options, state.wrench
        g, s, k = self.geometry, self.geometry.size, options.scale
        p = snap.tool_point
        J = snap.J_base
        status = snap.report.status
        lin = LINEAR_SECONDS * k
        unit = 0.2 * s * k  # drawn length of a unit direction (angular columns, lost direction)
        cap = ELLIPSOID_CAP * s * k

        e = snap.velocity
        self.velocity.set(p, e.axes, e.radii * lin, options.velocity_ellipsoid, cap)
        if status != self._status:
            self.velocity.node.color = STATUS_RGB[status]
            self._status = status
        rot = snap.rotational
        if rot is not None and options.rotational_ellipsoid:
            self.rotational.set(p, rot.axes, rot.radii * 0.6 * unit, True, cap)
        else:
            self.rotational.set(p, _EYE, _ZERO3, False, 1.0)
        force = snap.force
        if force is not None and options.force_ellipsoid:
            radii = force.radii * (lin * FORCE_SIGMA_REF**2 * s * s)
            if self.planar:  # a planar arm's force ellipse lies in the plane: flatten the out-of-plane axis
                radii = np.where(np.abs(force.axes[2]) > 0.99, 0.0, radii)
            self.force.set(p, force.axes, radii, True, cap)
        else:
            self.force.set(p, _EYE, _ZERO3, False, cap)

        if options.columns:
            self.columns.set(p, J[:3].T * lin, self._joint_colors)
        else:
            self.columns.hide()
        if options.angular_columns:
            origins = snap.joint_frames[g.first_axis, :3, 3]
            self.angular.set(origins, J[3:].T * unit, self._joint_colors)
        else:
            self.angular.hide()

        rows = list(snap.rows)
        moving = state.qd.any() or state.v_desired[rows].any() or wrench.any()
        if moving:  # else every arrow is zero: nothing to work out
            desired = np.zeros(6)
            desired[rows] = state.v_desired[rows]
            vectors = np.array(
                [
                    snap.twist[:3] * lin,
                    snap.twist[3:] * unit,
                    desired[:3] * lin,
                    wrench[:3] * 0.04 * s * k,
                    wrench[3:] * 0.04 * s * k,
                ]
            )
            self.motion.set(p, vectors, self._motion_colors)
        else:
            self.motion.hide()

        self._lost(snap, p, unit)
        self._links = snap.link_frames[:, :3, 3]

    def _lost(self, snap: Snapshot, p: np.ndarray, unit: float) -> None:
        """The lost direction: an arrow for its translation, an axis with a ring for its rotation."""
        lost = snap.lost
        if lost is None:  # regular: nothing is lost
            self.lost_v.hide()
            for node in (self.lost_w, *self.lost_labels.values()):
                set_if_changed(node, "visible", False)
            return
        show_v = lost.translation_share >= SHOWN_SHARE
        show_w = lost.rotation_share >= SHOWN_SHARE and not self.planar
        length = 2.0 * unit
        vector = lost.translation * length * np.sqrt(lost.translation_share)
        self.lost_v.set(p, vector[None], _LOST_COLORS, show=show_v)
        label_v = self.lost_labels["v"]
        set_if_changed(label_v, "visible", bool(show_v))
        if show_v:
            set_pose(label_v, finite_tuple(self.lost_v.tips[0]))
        label_w = self.lost_labels["w"]
        set_if_changed(self.lost_w, "visible", bool(show_w))
        set_if_changed(label_w, "visible", bool(show_w))
        if show_w:
            a = lost.rotation
            half = length * np.sqrt(lost.rotation_share)
            axis = np.array([[p - a * half, p + a * half]])
            update_props(
                self.lost_w, points=finite(np.concatenate([axis, _ring(p + a * 0.6 * half, a, 0.25 * half)]))
            )
            set_pose(label_w, finite_tuple(p + a * half))

    def remove(self) -> None:
        for node in self._nodes:
            node.remove()
