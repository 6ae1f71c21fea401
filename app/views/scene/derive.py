"""The Derive tab's step drawn in the 3-D view: the vectors the course's formula combines, named.

* DH frames: frames i−1 (thin) and i (thick), axes xᵢ red, yᵢ green, zᵢ blue, each named;
* Whitney: the axis zᵢ₋₁ at pᵢ₋₁, the lever pₙ − pᵢ₋₁ and the column zᵢ₋₁ × (pₙ − pᵢ₋₁) at the tool;
* differentiation: the path the tool traces when qᵢ alone moves and its tangent ∂p/∂qᵢ;
* velocity propagation: ωₖ (umber) and vₖ (black) at every link frame up to frame i;
* force propagation: the force at the tool, the lever from the axis, the axis turned by τᵢ.

Nothing is drawn when the tab walks through nothing. One arrows node, one line node and a
few labels, so a step costs a handful of messages.
"""

from __future__ import annotations

import numpy as np
import viser

from kinematics import Robot

from ...core.snapshot import Snapshot
from ...core.snapshot.derive import PATH_POINTS, Derivation, axis_names, sub, tool_name
from ...core.state import LabState
from ...viser_adapter import update_props
from ..palette import FORCE_RGB, TWIST_ANGULAR_RGB, TWIST_RGB, joint_color
from .arm import ArmGeometry
from .geometry import finite, set_if_changed
from .overlays import LINEAR_SECONDS, Arrows

__all__ = ["DeriveScene", "AXIS_RGB", "LEVER_RGB"]

AXIS_RGB = ((214, 40, 40), (30, 150, 60), (35, 80, 220))
"""Colours of drawn frame axes x, y, z."""
LEVER_RGB = (60, 64, 72)
"""The lever from a joint axis to the tool point (pₙ − pᵢ₋₁): dark, to read against the floor grid."""
_LABELS = 6
_SEGMENTS = PATH_POINTS - 1


class DeriveScene:
    """Scene nodes of the Derive tab's step for one tab and robot."""

    def __init__(self, scene: viser.SceneApi, robot: Robot, geometry: ArmGeometry, root: str) -> None:
        self.robot = robot
        self.geometry = geometry
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
                f"{root}/label_{k}", "", visible=False, anchor="bottom-left", font_screen_scale=1.1
            )
            for k in range(_LABELS)
        ]
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        d = snap.derive
        if d is None:
            self._hide()
            return
        unit = 0.2 * self.geometry.size * state.options.scale
        lin = LINEAR_SECONDS * state.options.scale
        draw = {
            "dh": self._frames,
            "whitney": self._whitney,
            "differentiation": self._differentiation,
            "propagation": self._propagation,
            "force": self._force,
        }[d.method]
        arrows, thin, lines, labels = draw(d, snap, unit, lin)
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
        for k, label in enumerate(self.labels):
            show = k < len(labels)
            set_if_changed(label, "visible", show)
            if show:
                text, where = labels[k]
                set_if_changed(label, "text", text)
                label.position = finite(where).astype(float)
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

    # Each method returns (thick arrows, thin arrows, lines, labels):
    # arrows (start, vector, rgb), lines (a, b, rgb), labels (text, position).
    def _frames(self, d: Derivation, snap: Snapshot, unit: float, lin: float) -> tuple:
        i = d.joint + 1
        thick: list = []
        thin: list = []
        labels: list = []
        for which, T in enumerate(d.frames):
            o, R = T[:3, 3], T[:3, :3]
            n = i - 1 + which
            target = thick if which else thin
            length = unit * (1.2 if which else 0.9)
            for a, name in enumerate("xyz"):
                target.append((o, R[:, a] * length, AXIS_RGB[a]))
                if a != 1:
                    labels.append((f"{name}{sub(n)}", o + R[:, a] * length))
        return thick, thin, [], labels[:_LABELS]

    def _whitney(self, d: Derivation, snap: Snapshot, unit: float, lin: float) -> tuple:
        z, p = axis_names(self.robot, d.joint)
        pn = tool_name(self.robot)
        c = d.whitney[d.axes[0]]
        rgb = joint_color(d.joint)
        tool = c.p + c.r
        thick = [(tool, c.linear * lin, rgb), (c.p, c.z * unit, rgb)]
        labels = [(z, c.p + c.z * unit)]
        thin = []
        if c.kind == "revolute":  # the lever pₙ − pᵢ₋₁ is a vector too: an arrow from the axis to the tool
            thin.append((c.p, c.r, LEVER_RGB))
            labels.append((f"{pn} − {p}", (c.p + tool) / 2))
            labels.append((f"{z} × ({pn} − {p})", tool + c.linear * lin))
        else:
            labels.append((f"{z} (slide)", tool + c.linear * lin))
        return thick, thin, [], labels

    def _differentiation(self, d: Derivation, snap: Snapshot, unit: float, lin: float) -> tuple:
        assert d.derivative is not None
        rgb = joint_color(d.joint)
        tool = snap.tool_point
        lines = [(a, b, rgb) for a, b in zip(d.path[:-1], d.path[1:], strict=True)]
        label = f"∂p/∂q{sub(d.joint + 1)}"
        return [(tool, d.derivative.dp * lin, rgb)], [], lines, [(label, tool + d.derivative.dp * lin)]

    def _propagation(self, d: Derivation, snap: Snapshot, unit: float, lin: float) -> tuple:
        """Every link's vₖ and ωₖ up to frame i, each readable: the longest of each kind drawn
        0.35 × the arm's size and none shorter than 0.08 × (a 0.5 m/s slide beside 45 m/s on the
        TRR's 24 m arm stays visible); a label at every vₖ's tip and at ωᵢ's."""
        last = d.axes[-1]
        links = d.links[: last + 1]
        size = unit / 0.2  # the arm's size × the glyph scale
        thick: list = []
        thin: list = []
        labels: list = []
        v_draw = _readable([link.v for link in links], size)
        w_draw = _readable([link.omega for link in links], size)
        for k, (link, v, w) in enumerate(zip(links, v_draw, w_draw, strict=True)):
            target = thick if k == last else thin
            if v is not None:
                target.append((link.origin, v, TWIST_RGB))
                labels.append((f"v{sub(k + 1)}", link.origin + v))
            if w is not None:
                target.append((link.origin, w, TWIST_ANGULAR_RGB))
        if w_draw[last] is not None:
            labels.append((f"ω{sub(last + 1)}", d.links[last].origin + w_draw[last]))
        return thick, thin, [], labels[-_LABELS:]

    def _force(self, d: Derivation, snap: Snapshot, unit: float, lin: float) -> tuple:
        load = next(x for x in d.loads if x.axis == d.axes[0])
        tool = snap.tool_point
        f = d.wrench[:3]
        scale = unit / max(float(np.linalg.norm(f)), 1e-9) if np.any(f) else 0.0
        thick = [(tool, f * scale, FORCE_RGB)]
        rgb = joint_color(d.joint)
        z, p = axis_names(self.robot, d.joint)
        thin = [(load.p, load.z * unit * np.sign(load.load or 1.0), rgb)]
        if load.kind == "revolute":
            thin.append((load.p, tool - load.p, LEVER_RGB))
        # Beside the axis, a quarter of the way along the lever: clear of the joint's own label.
        where = load.p + 0.25 * (tool - load.p) + 0.5 * unit * load.z
        labels = [("F", tool + f * scale), (f"τ{sub(d.joint + 1)} about {z}", where)]
        return thick, thin, [], labels

    def remove(self) -> None:
        for node in (self.arrows.node, self.thin.node, self.lines, *self.labels):
            node.remove()


def _readable(vectors: list[np.ndarray], size: float) -> list[np.ndarray | None]:
    """Drawn lengths for vectors of one kind: the longest 0.35 × ``size``, none shorter than
    0.08 × ``size`` (direction kept), a zero vector not drawn (``None``)."""
    norms = [float(np.linalg.norm(v)) for v in vectors]
    top = max(norms, default=0.0)
    if not np.isfinite(top) or top <= 1e-12:
        return [None] * len(vectors)
    out: list[np.ndarray | None] = []
    for v, n in zip(vectors, norms, strict=True):
        if n <= 1e-9 * top:
            out.append(None)
            continue
        length = max(0.35 * size * n / top, 0.08 * size)
        out.append(np.asarray(v, float) / n * length)
    return out
