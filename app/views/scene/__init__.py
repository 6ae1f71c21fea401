"""The 3-D view of one tab: the arm and the Jacobian's glyphs, built once per robot.

:class:`SceneView` owns every scene node of a tab. It is created for a
robot (nodes built once), updated for every snapshot (nodes moved, inside
the session's ``atomic`` batch), and removed when the tab switches robot
or leaves. After each update :attr:`SceneView.extent` holds the points the
camera must keep in view.

The arm is always drawn; everything drawn on it is a glyph: one module here and one entry in
:data:`GLYPHS` (a :class:`Glyph`: a name and how to build its :class:`GlyphView` from a
:class:`SceneContext`). Whether a glyph shows is an option of :mod:`app.core.options` it reads
from the state in ``update``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import viser

from kinematics import Robot

from ...core.i18n import Translator, translations
from ...core.poll import Seen
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ..camera import View
from ..panel.common import Dispatch
from .accel import AccelArrow
from .arm import ArmGeometry, ArmView
from .derive import DeriveScene
from .drive import DriveView
from .labels import Layout, ScreenLabels
from .overlays import Overlays
from .path import PlannedPath, ToolPath
from .question import QuestionScene, hide_lost

__all__ = ["SceneView", "ArmGeometry", "Glyph", "GlyphView", "SceneContext", "GLYPHS"]


@dataclass(frozen=True)
class SceneContext:
    """What a glyph is built from, once per robot.

    Attributes:
        scene: The tab's scene (or a whole server's, for ``jacobian-lab record``).
        robot: The robot drawn; geometry: the arm's drawn geometry (``geometry.size``: its length [m]).
        dispatch: Where a glyph that takes input (the drag handle) sends actions.
        root: The scene path under which the glyph puts its nodes.
        joint_labels: Where the arm's joint labels are at the last update (k, 3) [m]: a glyph's own
            labels keep clear of them.
        tr: The tab's language (the words a glyph writes in the 3-D view).
        open_tab: The name of the panel tab the page has open at the update ("derive" …; "" when not
            known): a tab's own glyphs (the Derive tab's step) are drawn only while it is open.
        question: The room's question as the tab shows it (:mod:`app.core.poll`), or None.
        view: The tab's camera as the browser last reported it, or None (a recording has none).
    """

    scene: viser.SceneApi
    robot: Robot
    geometry: ArmGeometry
    dispatch: Dispatch
    root: str
    joint_labels: Callable[[], np.ndarray] = lambda: np.zeros((0, 3))
    tr: Translator = field(default_factory=translations)
    open_tab: Callable[[], str] = lambda: ""
    question: Callable[[], Seen | None] = lambda: None
    view: Callable[[], View | None] = lambda: None


class GlyphView(Protocol):
    """One glyph's nodes for one robot: moved on every snapshot, removed on a robot switch."""

    @property
    def extent(self) -> np.ndarray:
        """The points (N, 3) [m] it drew at the last update (the camera keeps them in view)."""
        ...

    def update(self, snap: Snapshot, state: LabState) -> None: ...

    def remove(self) -> None: ...


@dataclass(frozen=True)
class Glyph:
    """One entry of :data:`GLYPHS`: ``scene.<name>`` is the view ``build`` makes."""

    name: str
    build: Callable[[SceneContext], GlyphView]


GLYPHS: tuple[Glyph, ...] = (
    Glyph(
        "overlays",
        lambda c: Overlays(
            c.scene, c.geometry, c.robot.dof, c.robot.planar, f"{c.root}/jacobian", c.joint_labels, c.tr
        ),
    ),
    Glyph("accel", lambda c: AccelArrow(c.scene, c.geometry.size, f"{c.root}/jacobian")),
    Glyph(
        "drive", lambda c: DriveView(c.scene, c.dispatch, c.geometry.size, c.robot.planar, f"{c.root}/drive")
    ),
    Glyph("planned", lambda c: PlannedPath(c.scene, f"{c.root}/motion")),
    Glyph("path", lambda c: ToolPath(c.scene, f"{c.root}/motion")),
    Glyph(
        "derive",
        lambda c: DeriveScene(
            c.scene, c.robot, c.geometry, f"{c.root}/derive", c.joint_labels, c.tr, c.open_tab
        ),
    ),
    Glyph(
        "candidates",
        lambda c: QuestionScene(
            c.scene, c.geometry.size, f"{c.root}/question", c.tr, c.question, c.view, c.joint_labels
        ),
    ),
)
"""What is drawn on the arm, in update order: J's columns, ellipsoids, twist, force and lost direction;
J̇ q̇; the drag handle and motion traces; the chosen path y(t); the tool's path while a motion plays; the
Derive tab's step; the room's candidate lost directions."""
HIDDEN_UNTIL_REVEALED = ("kind", "lost")
"""While the room answers one of these questions the arm's lost-direction glyph (its words name the
kind, its arrow the direction) is not drawn: the reveal draws it."""
_GLYPH_NAMES = frozenset(g.name for g in GLYPHS)


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
        tr: Translator | None = None,
        view: Callable[[], View | None] | None = None,
    ) -> None:
        self.arm = ArmView(client, robot, f"{root}/arm")
        self.open_tab = ""
        """The name of the panel tab the page has open ("" when not known: every glyph is drawn)."""
        self.question: Seen | None = None
        """The room's question as the tab shows it (set by the tab before each update)."""
        ignore: Dispatch = lambda action: None  # noqa: E731  (a recorded scene takes no input)
        arm = self.arm
        context = SceneContext(
            client.scene,
            robot,
            arm.geometry,
            dispatch or ignore,
            root,
            lambda: arm.label_points,
            tr or translations(),
            lambda: self.open_tab,
            lambda: self.question,
            lambda: view() if view is not None else None,
        )
        self.glyphs: dict[str, GlyphView] = {g.name: g.build(context) for g in GLYPHS}
        overlays, derive, question = self.glyphs["overlays"], self.glyphs["derive"], self.glyphs["candidates"]
        self.labels = ScreenLabels(
            [
                *arm.labels,
                *getattr(overlays, "lost_labels", []),
                *getattr(question, "labels", []),
                *getattr(derive, "labels", []),
            ],
            client.scene,
            f"{root}/labels",
        )
        """The 3-D labels, placed on the screen after each update (joints first: they keep their spots)."""
        self.layout: Callable[[], Layout | None] = lambda: None
        """Where the tab's labels are seen (its camera and canvas; None: at their anchors)."""

    def __getattr__(self, name: str) -> Any:
        """``scene.overlays``, ``scene.derive`` …: the view of glyph ``name``."""
        if name in _GLYPH_NAMES and "glyphs" in self.__dict__:
            return self.__dict__["glyphs"][name]
        raise AttributeError(name)

    @property
    def size(self) -> float:
        """Length of the drawn chain at home [m]."""
        return self.arm.geometry.size

    @property
    def extent(self) -> np.ndarray:
        """Points (N, 3) [m] of everything drawn at the last update: arm, ellipsoids, arrow tips."""
        parts = [g.extent for g in self.glyphs.values()]
        return np.concatenate([x for x in parts if len(x)]) if any(len(x) for x in parts[1:]) else parts[0]

    def update(self, snap: Snapshot, state: LabState) -> None:
        """Move every node to ``snap`` (call inside ``client.atomic()``)."""
        self.arm.update(snap, state.options)
        for glyph in self.glyphs.values():
            glyph.update(snap, state)
        if self.question is not None and self.question.masks in HIDDEN_UNTIL_REVEALED:
            hide_lost(self.glyphs["overlays"])  # the room is answering: its answer is not drawn
        self.labels.place(self.layout())

    def place_labels(self) -> None:
        """Place the labels again (the camera or the canvas changed; call inside ``client.atomic()``)."""
        self.labels.place(self.layout())

    def remove(self) -> None:
        """Remove every node (on robot switch or disconnect)."""
        for glyph in reversed(self.glyphs.values()):
            glyph.remove()
        if self.labels.leaders is not None:
            self.labels.leaders.remove()
        self.arm.remove()
