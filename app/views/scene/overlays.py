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

from collections.abc import Callable

import numpy as np
import viser

from ...core.i18n import N_, Translator, translations
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
from .arrows import Arrows
from .geometry import (
    LABEL_CLEARANCE,
    LOST_LABEL_SCALE,
    TINY,
    clear_of,
    clear_start,
    finite,
    finite_tuple,
    ring,
    set_if_changed,
    wxyz_one,
)
from .labels import anchor_label

__all__ = ["Overlays", "Arrows", "LINEAR_SECONDS", "ELLIPSOID_CAP", "SHOWN_SHARE", "MAX_LOSSES", "GAP"]

LINEAR_SECONDS = 0.5
"""Drawn length [m] per [m/s] of tool-point velocity (and per [m/rad] of a column)."""
ELLIPSOID_CAP = 1.2
"""Largest drawn ellipsoid semi-axis, in robot sizes (× scale): where a force ellipsoid goes to infinity."""
FORCE_SIGMA_REF = 0.4
SHOWN_SHARE = 0.1
"""A lost translation (rotation) is drawn when it carries at least this share of the lost direction."""
MAX_LOSSES = 3
"""Lost directions drawn at most (a rank-3 loss: the iiwa's candle)."""
GAP = 0.3
"""A lost translation's arrow starts this many unit lengths beyond its point: clear of the links."""
FLAT_FLOOR = 0.03
"""At a singularity a flat ellipsoid axis is drawn this many robot sizes thick, so it can be seen."""
_LABELS = {
    ("arm", "v"): N_("arm: lost translation (wrist centre)"),
    ("wrist", "w"): N_("wrist: lost rotation axis"),
    ("tool", "v"): N_("lost translation"),
    ("tool", "w"): N_("lost rotation axis"),
    ("arm", "w"): N_("lost rotation axis"),
    ("wrist", "v"): N_("lost translation"),
}
"""The words at a lost direction (English msgids: shown in the tab's language); ``_SECOND``: at a second
of the same kind (the iiwa's candle loses z and y of its wrist centre)."""
_SECOND = {_LABELS["arm", "v"]: N_("arm: second lost translation (wrist centre)")}

_NO_POINTS = np.zeros((0, 3))
_EYE, _ZERO3 = np.eye(3), np.zeros(3)
_LOST_COLORS = np.array([LOST_RGB], np.uint8)
for _a in (_NO_POINTS, _EYE, _ZERO3, _LOST_COLORS):
    _a.flags.writeable = False


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

    def set(
        self,
        center: np.ndarray,
        axes: np.ndarray,
        radii: np.ndarray,
        show: bool,
        cap: float,
        floor: float = TINY,
    ) -> None:
        """Draw (or hide) the ellipsoid; a flat axis is drawn ``floor`` thick so a collapsed
        ellipsoid stays visible as a thin disc or needle around what lies inside it."""
        set_if_changed(self.node, "visible", bool(show))
        if not show:
            self._drawn = None
            return
        # NaN → floor, +inf → cap, in plain Python (three numbers: cheaper than NumPy's nan_to_num and clip)
        r = tuple(min(max(x, floor), cap) if x == x else floor for x in np.asarray(radii, float).tolist())
        update_props(self.node, scale=r)
        set_pose(self.node, finite_tuple(center), wxyz_one(axes))
        self._drawn = (np.asarray(center, float), np.asarray(axes, float), np.array(r))


class Overlays:
    """The Jacobian's glyphs around the tool for one tab."""

    def __init__(
        self,
        scene: viser.SceneApi,
        geometry: ArmGeometry,
        dof: int,
        planar: bool,
        root: str,
        joint_labels: Callable[[], np.ndarray] | None = None,
        tr: Translator | None = None,
    ) -> None:
        self.tr = tr or translations()
        self.geometry = geometry
        self._joint_labels = joint_labels or (lambda: np.zeros((0, 3)))
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
        self.arm_ellipsoid = _Ellipsoid(scene, f"{root}/arm_ellipsoid", STATUS_RGB["singular"], 0.3)
        self.wrist_ellipsoid = _Ellipsoid(scene, f"{root}/wrist_ellipsoid", ROTATION_ELLIPSOID_RGB, 0.3)
        self.lost_w = scene.add_line_segments(
            f"{root}/lost_rotation",
            points=np.zeros((1, 2, 3), np.float32),
            colors=LOST_RGB,
            thickness=4.0,
            thickness_units="screen",
            visible=False,
        )
        self.lost_labels = [
            scene.add_label(
                f"{root}/lost_label_{i}",
                "lost",
                visible=False,
                anchor="bottom-left",
                font_screen_scale=LOST_LABEL_SCALE,
            )
            for i in range(MAX_LOSSES)
        ]
        self._label_texts = [""] * MAX_LOSSES
        self.lost_tips: np.ndarray = _NO_POINTS
        ellipsoids = (self.velocity, self.rotational, self.force, self.arm_ellipsoid, self.wrist_ellipsoid)
        self._nodes: list = [e.node for e in ellipsoids]
        self._nodes += [a.node for a in (self.columns, self.angular, self.motion, self.lost_v)]
        self._nodes += [self.lost_w, *self.lost_labels]
        self._links: np.ndarray = _NO_POINTS
        self._show_velocity = True
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
            self.arm_ellipsoid.extent,
            self.wrist_ellipsoid.extent,
            self.lost_tips,
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
        # Decoupled at the wrist centre, the ellipsoids that flatten are the blocks' (drawn there instead).
        decoupled = any(loss.part != "tool" for loss in snap.losses)
        floor = FLAT_FLOOR * s * k if status != "regular" else TINY  # a collapsed ellipsoid stays visible
        self.velocity.set(p, e.axes, e.radii * lin, options.velocity_ellipsoid and not decoupled, cap, floor)
        if status != self._status:
            self.velocity.node.color = STATUS_RGB[status]
            self._status = status
        rot = snap.rotational
        if rot is not None and options.rotational_ellipsoid and not decoupled:
            self.rotational.set(p, rot.axes, rot.radii * 0.6 * unit, True, cap, floor)
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

        self._show_velocity = options.velocity_ellipsoid
        self._blocks(snap, lin, unit, cap, FLAT_FLOOR * s * k)
        self._lost(snap, unit)
        self._links = snap.link_frames[:, :3, 3]

    def _blocks(self, snap: Snapshot, lin: float, unit: float, cap: float, floor: float) -> None:
        """The decoupled block that flattens, drawn at the wrist centre: the wrist centre's velocity
        ellipsoid by the arm joints (arm loss), the wrist joints' angular one (wrist loss)."""
        parts = {loss.part for loss in snap.losses}
        d = snap.decoupling
        for part, node, e, scale in (
            ("arm", self.arm_ellipsoid, snap.arm_ellipsoid, lin),
            ("wrist", self.wrist_ellipsoid, snap.wrist_ellipsoid, 0.6 * unit),
        ):
            if d is None or e is None or part not in parts or not self._show_velocity:
                node.set(_ZERO3, _EYE, _ZERO3, False, cap)
            else:
                node.set(d.centre, e.axes, e.radii * scale, True, cap, floor)

    def _words(self, label: str) -> str:
        """A lost direction's words in the tab's language; longer than the English (which the camera
        keeps in view), they break after their colon: "muñeca:\neje de giro perdido" (viser's labels
        keep line breaks), so they do not run under the panel at 1280×720."""
        text = self.tr.gettext(label)
        return text.replace(": ", ":\n", 1) if len(text) > len(label) else text

    def _lost(self, snap: Snapshot, unit: float) -> None:
        """Every lost direction at its own point: an arrow for a translation (starting a little beyond
        the point, away from the arm), an axis with a ring for a rotation, each with its label."""
        starts, vectors, segments, tips, texts = [], [], [], [], []
        length = 2.0 * unit
        for loss in snap.losses[:MAX_LOSSES]:
            a, point = loss.rotation, loss.point
            show_v = loss.translation_share >= SHOWN_SHARE or (self.planar and loss.translation_share > 0)
            show_w = loss.rotation_share >= SHOWN_SHARE and not self.planar
            if show_v:
                u = loss.translation
                size = length * (np.sqrt(loss.translation_share) if loss.part == "tool" else 1.0)
                start = clear_start(
                    point, u, snap.link_frames[:, :3, 3], GAP * unit, 0.06 * self.geometry.size
                )
                starts.append(start)
                vectors.append(u * size)
                tips.append(start + u * (size + 0.1 * unit))
                words = _LABELS[loss.part, "v"]
                texts.append(self._words(_SECOND.get(words, words) if self._words(words) in texts else words))
            if show_w:
                half = length * (np.sqrt(loss.rotation_share) if loss.part == "tool" else 0.75)
                segments.append(np.array([[point - a * half, point + a * half]]))
                segments.append(ring(point + a * 0.6 * half, a, 0.25 * half))
                tips.append(point + a * (half + 0.1 * unit))
                texts.append(self._words(_LABELS[loss.part, "w"]))
        if starts:
            self.lost_v.set(np.array(starts), np.array(vectors), np.repeat(_LOST_COLORS, len(starts), axis=0))
        else:
            self.lost_v.hide()
        set_if_changed(self.lost_w, "visible", bool(segments))
        if segments:
            update_props(self.lost_w, points=finite(np.concatenate(segments)))
        taken = self._joint_labels()
        gap = LABEL_CLEARANCE * self.geometry.size
        for i, label in enumerate(self.lost_labels):
            shown = i < len(texts) and texts[i] not in texts[:i]  # never the same words twice
            set_if_changed(label, "visible", shown)
            if shown:
                if texts[i] != self._label_texts[i]:
                    label.text = texts[i]
                    self._label_texts[i] = texts[i]
                tips[i] = clear_of(tips[i], taken, gap, self.planar)  # not on a joint's label (q6's)
                taken = np.vstack([taken, tips[i]])
                anchor_label(label, finite_tuple(tips[i]))
        self.lost_tips = np.array(tips) if tips else _NO_POINTS

    def remove(self) -> None:
        for node in self._nodes:
            node.remove()
