"""The arm: the DH picture (links as a and d segments, joint axes as cylinders), URDF meshes, frames.

For every robot the app draws the joint axes zᵢ₋₁ as coloured cylinders
(boxes for prismatic joints) in the colour of the joint's slider, and the
links as grey segments through the DH "d then a" corners, so the course's
frame picture is visible. A URDF robot whose mesh files are present shows
its meshes instead of the grey segments. All nodes are built once per
robot and then only updated.
"""

from __future__ import annotations

import dataclasses
import functools
import io
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import viser

from kinematics import Robot, joint_frames, link_frames
from kinematics.urdf import is_xacro, mesh_filename_handler, read_description

from ...core.snapshot import Snapshot
from ...core.state import Options
from ...viser_adapter import update_props
from ..palette import LINK_RGB, STATUS_RGB, joint_color
from .geometry import (
    LABEL_SCALE,
    finite,
    segment_instances,
    set_if_changed,
    unit_box,
    unit_cylinder,
    wxyz,
)
from .labels import anchor_label

__all__ = ["ArmGeometry", "ArmView"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ArmGeometry:
    """What the drawing needs to know about a robot, worked out once per robot.

    Attributes:
        size: Length of the drawn chain at home [m]: the scale of every glyph.
        axis_joint: Joint index driving each axis (m,).
        revolute: Whether each axis is revolute (m,).
        first_axis: For each joint, the first axis it drives (n,).
        moved_from_link: inv(T_joint_child) per axis (m, 4, 4): moved joint frame from link frame.
        corners: Homogeneous corner points per axis (in the moved joint frame).
    """

    size: float
    axis_joint: np.ndarray
    revolute: np.ndarray
    first_axis: np.ndarray
    moved_from_link: np.ndarray
    corners: tuple[np.ndarray, ...]

    @classmethod
    def of(cls, robot: Robot) -> ArmGeometry:
        """The geometry of ``robot`` (its size measured at home)."""
        axes = robot.axes
        corners = tuple(
            np.column_stack([np.asarray(ax.corners, float).reshape(-1, 3), np.ones(len(ax.corners))])
            for ax in axes
        )
        idx = np.array([ax.joint_index for ax in axes])
        geom = cls(
            size=1.0,
            axis_joint=idx,
            revolute=np.array([ax.kind == "revolute" for ax in axes]),
            first_axis=np.array([int(np.flatnonzero(idx == j)[0]) for j in range(robot.dof)]),
            moved_from_link=np.stack([np.linalg.inv(ax.T_joint_child) for ax in axes]),
            corners=corners,
        )
        pts = geom.polyline(link_frames(robot, robot.home), joint_frames(robot, robot.home))
        length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
        return dataclasses.replace(geom, size=max(length, 0.2))

    def polyline(self, L: np.ndarray, W: np.ndarray) -> np.ndarray:
        """Points (P, 3) of the drawn chain: frame 0; per axis its origin, corners, link frame; the tool.

        Args:
            L: Link frames (m + 2, 4, 4) as from :func:`kinematics.link_frames`.
            W: Joint frames (m, 4, 4) as from :func:`kinematics.joint_frames`.
        """
        owner, corners, order = self._gather
        m = len(W)
        parts = [L[:, :3, 3], W[:, :3, 3]]
        if len(owner):  # corner points, moved with their axis: (L[k+1] · inv(T_joint_child[k])) · corner
            moved = L[owner + 1] @ self.moved_from_link[owner]
            parts.append(np.einsum("kij,kj->ki", moved[:, :3], corners))
        points = np.concatenate(parts)
        assert len(points) == len(L) + m + len(owner)
        return points[order]

    @functools.cached_property
    def _gather(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Corner owners (C,), corner points (C, 4), and the order of the polyline's points in
        [link frames (m + 2); joint frames (m); corners (C)], worked out once per robot."""
        m = len(self.corners)
        owner = np.array([k for k in range(m) for _ in self.corners[k]], dtype=int)
        stacked = np.concatenate([*self.corners, np.zeros((0, 4))]) if m else np.zeros((0, 4))
        order, c = [0], 0
        for k in range(m):
            order.append(m + 2 + k)
            order += range(2 * m + 2 + c, 2 * m + 2 + c + len(self.corners[k]))
            c += len(self.corners[k])
            order.append(k + 1)
        order.append(m + 1)
        return owner, stacked, np.array(order, dtype=int)


class ArmView:
    """Scene nodes of the arm for one client; :meth:`update` moves them."""

    def __init__(self, client: viser.ClientHandle | viser.ViserServer, robot: Robot, root: str) -> None:
        scene = client.scene
        self.robot = robot
        self.geometry = g = ArmGeometry.of(robot)
        s = g.size
        self._status = ""
        self._meshes = _load_urdf_meshes(client, robot, f"{root}/urdf")
        L0 = link_frames(robot, robot.home)
        floor = min(0.0, float(L0[:, 2, 3].min())) - 0.02 * s
        self._nodes: list = [self._meshes] if self._meshes is not None else []
        self.grid = scene.add_grid(
            f"{root}/grid",
            width=3 * s,
            height=3 * s,
            cell_size=_nice(s / 8),
            section_size=_nice(s / 2),
            position=(0.0, 0.0, floor),
            shadow_opacity=0.1,
        )
        base = robot.base[:3, 3]
        self.pedestal = scene.add_cylinder(
            f"{root}/pedestal",
            radius=0.06 * s,
            height=max(base[2] - floor, 1e-3),
            color=(90, 94, 102),
            position=(base[0], base[1], (base[2] + floor) / 2),
        )
        m = len(robot.axes)
        self._rev = np.flatnonzero(g.revolute)
        self._pri = np.flatnonzero(~g.revolute)
        # Links are drawn as generated geometry unless every visual of the URDF was found.
        self._draw_links = self._meshes is None or not self._meshes.complete
        self._n_links = len(g.polyline(L0, joint_frames(robot, robot.home))) - 1 if self._draw_links else 0
        n_cyl = self._n_links + len(self._rev)
        self._axis_radius = 0.04 * s * (1.0 - 0.07 * np.arange(m))  # nested when axes line up
        self._axis_length = 0.17 * s * (1.0 + 0.1 * np.arange(m))
        self._radii = np.concatenate([np.full(self._n_links, 0.026 * s), self._axis_radius[self._rev]])
        # A joint's label sits just beyond the end of its first axis' cylinder.
        self._label_offset = (self._axis_length / 2 + 0.02 * s)[g.first_axis, None]
        self.label_points: np.ndarray = np.zeros((0, 3))
        """Where the joints' labels are drawn (k, 3) [m] at the last update (none when hidden)."""
        cyl_colors = np.array(
            [LINK_RGB] * self._n_links + [joint_color(int(g.axis_joint[k])) for k in self._rev],
            dtype=np.uint8,
        ).reshape(n_cyl, 3)
        v, f = unit_cylinder()
        self.cylinders = (
            scene.add_batched_meshes_simple(
                f"{root}/cylinders",
                v,
                f,
                batched_wxyzs=np.tile([1.0, 0, 0, 0], (n_cyl, 1)),
                batched_positions=np.zeros((n_cyl, 3)),
                batched_colors=cyl_colors,
                lod="off",
            )
            if n_cyl
            else None
        )
        v, f = unit_box()
        self.boxes = (
            scene.add_batched_meshes_simple(
                f"{root}/prismatic",
                v,
                f,
                batched_wxyzs=np.tile([1.0, 0, 0, 0], (len(self._pri), 1)),
                batched_positions=np.zeros((len(self._pri), 3)),
                batched_colors=np.array(
                    [joint_color(int(g.axis_joint[k])) for k in self._pri], np.uint8
                ).reshape(-1, 3),
                lod="off",
            )
            if len(self._pri)
            else None
        )
        n_frames = m + 2
        self.frames = scene.add_batched_axes(
            f"{root}/frames",
            batched_wxyzs=np.tile([1.0, 0, 0, 0], (n_frames, 1)),
            batched_positions=np.zeros((n_frames, 3)),
            axes_length=0.12 * s,
            axes_radius=0.006 * s,
            visible=False,
        )
        self.labels = [
            scene.add_label(
                f"{root}/label_{j}", _short(j, name), font_screen_scale=LABEL_SCALE, anchor="bottom-center"
            )
            for j, name in enumerate(robot.joint_names)
        ]
        self._nodes += [self.grid, self.pedestal, self.cylinders, self.boxes, self.frames, *self.labels]

    def update(self, snap: Snapshot, options: Options) -> None:
        """Move every node to ``snap`` (its joint frames and link frames)."""
        g, L, W = self.geometry, snap.link_frames, snap.joint_frames
        if self._meshes is not None:
            self._meshes.update(snap.q)
        z = W[:, :3, 2]
        o = W[:, :3, 3]
        half = self._axis_length / 2
        if self.cylinders is not None:
            r = self._rev
            ends = z[r] * half[r, None]
            p0, p1 = o[r] - ends, o[r] + ends
            if self._draw_links:  # the links first, then the revolute axes: one batch
                pts = g.polyline(L, W)
                p0, p1 = np.concatenate([pts[:-1], p0]), np.concatenate([pts[1:], p1])
            pos, quat, scale = segment_instances(p0, p1, self._radii)
            poses = {"batched_positions": finite(pos), "batched_wxyzs": finite(quat)}
            if snap.report.status != self._status and self._draw_links:
                colors = self.cylinders.batched_colors.copy()
                colors[: self._n_links] = _tint(LINK_RGB, snap.report.status)
                poses["batched_colors"] = colors
            update_props(self.cylinders, batched_scales=finite(scale), **poses)  # one message
        if self.boxes is not None:
            p = self._pri
            width = 2.2 * self._axis_radius[p]
            update_props(
                self.boxes,
                batched_positions=finite(o[p]),
                batched_wxyzs=finite(wxyz(W[p, :3, :3])),
                batched_scales=finite(np.column_stack([width, width, 2 * half[p]])),
            )
        self._status = snap.report.status
        set_if_changed(self.frames, "visible", options.frames)
        if options.frames:
            update_props(
                self.frames, batched_positions=finite(L[:, :3, 3]), batched_wxyzs=finite(wxyz(L[:, :3, :3]))
            )
        for label in self.labels:
            set_if_changed(label, "visible", options.labels)
        if options.labels:
            k = g.first_axis
            at = finite(o[k] + z[k] * self._label_offset).tolist()  # plain floats: viser's setter is cheaper
            for label, position in zip(self.labels, at, strict=True):
                anchor_label(label, position)
            self.label_points = np.asarray(at, dtype=float).reshape(-1, 3)
        else:
            self.label_points = np.zeros((0, 3))

    def remove(self) -> None:
        """Remove every node of this arm."""
        for node in self._nodes:
            if node is not None:
                node.remove()


def _short(j: int, name: str) -> str:
    """Label of joint ``j`` in the 3-D view: "q{j+1}", its one name (like the columns of J and the
    sliders), whatever symbol its own name carries (d3, A1, panda_joint4)."""
    return f"q{j + 1}"


def _nice(x: float) -> float:
    """A round grid spacing near ``x`` (1, 2 or 5 × 10ᵏ)."""
    k = np.floor(np.log10(x))
    m = x / 10**k
    return float((1 if m < 1.5 else 2 if m < 3.5 else 5) * 10**k)


def _tint(rgb: tuple[int, int, int], status: str) -> np.ndarray:
    """The link colour blended towards the status colour (unchanged when regular)."""
    if status == "regular":
        return np.array(rgb, np.uint8)
    mix = 0.65 if status == "singular" else 0.45
    return (np.array(rgb) * (1 - mix) + np.array(STATUS_RGB[status]) * mix).astype(np.uint8)


class _UrdfMeshes:
    """A URDF's visual meshes (viser's ViserUrdf), driven by the robot's joint values."""

    def __init__(self, urdf_view, names: tuple[str, ...], robot: Robot, complete: bool = True) -> None:
        self.complete = complete
        self._view = urdf_view
        index = {name: i for i, name in enumerate(robot.joint_names)}
        self._map = [index.get(name) for name in names]

    def update(self, q: np.ndarray) -> None:
        cfg = np.array([q[i] if i is not None else 0.0 for i in self._map])
        self._view.update_cfg(cfg)

    def remove(self) -> None:
        self._view.remove()


def _load_urdf_meshes(
    target: viser.ClientHandle | viser.ViserServer, robot: Robot, root: str
) -> _UrdfMeshes | None:
    """ViserUrdf of the visual geometry of a URDF robot that loads (all of it, or some: then
    ``complete`` is False and the links are drawn as generated geometry too); ``None`` when none does."""
    if not robot.urdf_path:
        return None
    try:
        import yourdfpy
        from viser.extras import ViserUrdf

        path = Path(robot.urdf_path)
        source: str | io.BytesIO = str(path)
        if is_xacro(path):  # the URDF the xacro file expanded to (its last expansion, with its arguments)
            source = io.BytesIO(read_description(path))
        urdf = yourdfpy.URDF.load(
            source,
            build_scene_graph=True,
            load_meshes=True,
            filename_handler=mesh_filename_handler(path),
        )
        wanted = sum(1 for link in urdf.robot.links for v in link.visuals if v.geometry is not None)
        found = 0 if urdf.scene is None else len(urdf.scene.geometry)
        if wanted == 0 or found == 0:
            log.info("%s: none of its %d visual meshes found; drawing generated geometry", path.name, wanted)
            return None
        if found < wanted:  # draw the ones found, and the arm's generated links so nothing is missing
            log.info(
                "%s: %d of %d visual meshes found; drawing them and the generated links",
                path.name,
                found,
                wanted,
            )
        view = ViserUrdf(target, urdf, root_node_name=root)
        return _UrdfMeshes(view, view.get_actuated_joint_names(), robot, complete=found >= wanted)
    except Exception:  # a broken mesh must not stop the app: fall back to generated geometry
        log.warning(
            "cannot load the meshes of %s; drawing generated geometry", robot.urdf_path, exc_info=True
        )
        return None
