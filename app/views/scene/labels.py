"""A tab's 3-D labels placed in screen space (issue 28, stumble 2): no two overlap, none leaves the view.

The scene's views say where each label belongs (:func:`anchor_label`: a joint, a lost direction's tip,
a Derive step's vector) without moving it; after each redraw, and after each camera move (throttled by
the tab, :mod:`app.tab.labels`), :meth:`ScreenLabels.place` projects the shown labels' anchors
through the browser's camera (:class:`Layout`), sizes each label as viser lays it out (12 CSS px ×
``font_screen_scale`` per em, :mod:`.placement`), finds each a box inside the part of the canvas the
panel leaves visible, out of what the page draws over it (the motion's readout, :attr:`Layout.avoid`),
apart from the boxes placed before it (in the order given: joints first, so they stay at their joints),
and puts the label at the 3-D point of its anchor's depth that projects there.
A label whose box is free stays at its anchor. Without a camera (a recorded scene) every label is at
its anchor.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...viser_adapter import set_pose, update_props
from ..camera import View, project
from .geometry import finite, set_if_changed
from .placement import EM_PX, label_size, lift, place, wrap

__all__ = ["Layout", "ScreenLabels", "anchor_label", "label_anchor", "label_box"]


@dataclass(frozen=True)
class Layout:
    """Where the labels are seen: the browser's camera, its canvas [CSS px] and the canvas's visible part.

    Attributes:
        view: The camera (its ``aspect``: the canvas's).
        width, height: The canvas [CSS px].
        rect: (x0, y0, x1, y1) [px] of the canvas not under the panel.
        avoid: Boxes (x0, y0, x1, y1) [px] the page draws over the canvas (the motion's readout): no
            label goes under them.
    """

    view: View
    width: float
    height: float
    rect: tuple[float, float, float, float]
    avoid: tuple[tuple[float, float, float, float], ...] = ()


def anchor_label(handle: Any, position: Sequence[float] | np.ndarray) -> None:
    """Say where ``handle`` (a label) belongs; :meth:`ScreenLabels.place` moves it."""
    handle.__dict__["_jl_anchor"] = tuple(float(x) for x in position)


def label_anchor(handle: Any) -> np.ndarray:
    """Where ``handle`` belongs (3,) [m]: the last :func:`anchor_label`, else where it is."""
    at = handle.__dict__.get("_jl_anchor")
    return np.asarray(at if at is not None else handle.position, float)


def label_box(handle: Any, spot: np.ndarray) -> np.ndarray:
    """The box (x0, y0, x1, y1) [px] viser draws ``handle`` in when its position projects to ``spot``
    (labelLayout.ts: the background's bottom edge on the point; its left edge there for a "…-left"
    anchor, centred for "…-center")."""
    w, h = label_size(str(handle.text), EM_PX * float(handle.font_screen_scale))
    x0 = spot[0] - (w / 2 if str(handle.anchor).endswith("center") else 0.0)
    return np.array([x0, spot[1] - h, x0 + w, spot[1]])


def _words(handle: Any, most: float) -> str:
    """The words the view gave ``handle``, broken at spaces where wider than ``most`` [px] (a phone's
    view, or a window whose panel leaves a narrow view); set on the label when that changed them."""
    d = handle.__dict__
    text = str(handle.text)
    if text != d.get("_jl_wrapped"):  # the view set new words
        d["_jl_words"] = text
    words = d.get("_jl_words", text)
    font = EM_PX * float(handle.font_screen_scale)
    wanted = wrap(words, font, most) if label_size(words, font)[0] > most else words
    if wanted != text:
        handle.text = wanted
    d["_jl_wrapped"] = wanted
    return wanted


def _shown(handle: Any) -> bool:
    cache = handle.__dict__.get("_jl_last", {})
    return bool(cache.get("visible", handle.visible))


LEADER_PX = 12.0
"""A label whose box ends farther than this [px] from its anchor gets a leader line to it."""
LEADER_RGB = (120, 120, 120)


class ScreenLabels:
    """The labels of one scene, in the order they take their places (the first keep their spots).

    ``scene``: where to draw the leader lines (a thin grey line from a label moved away from its
    anchor to the anchor), under ``root``; none without it."""

    def __init__(self, handles: Sequence[Any], scene: Any = None, root: str = "/lab/labels") -> None:
        self.handles = list(handles)
        self.leaders = (
            None
            if scene is None
            else scene.add_line_segments(
                f"{root}/leaders",
                points=np.zeros(
                    (len(self.handles), 2, 3), np.float32
                ),  # always this many: the page keeps the count
                colors=LEADER_RGB,
                thickness=1.5,
                thickness_units="screen",
                visible=False,
            )
        )
        self.leader_count = 0
        """How many leader lines the last placement drew."""
        self.boxes: np.ndarray = np.zeros((0, 4))
        """The shown labels' boxes [px] at the last placement with a camera."""
        self.placed: list[Any] = []
        """The labels those boxes are of."""
        self.layout: Layout | None = None
        """The layout of the last placement (None: every label at its anchor)."""

    def place(self, layout: Layout | None) -> None:
        """Move every shown label to its place in ``layout`` (at its anchor when None)."""
        shown = [h for h in self.handles if _shown(h)]
        anchors = np.array([label_anchor(h) for h in shown]).reshape(-1, 3)
        spots, boxes, leaders = anchors, np.zeros((0, 4)), list[Any]()
        if layout is not None and shown:
            for h in shown:
                _words(h, layout.rect[2] - layout.rect[0])
            key = _placement_key(layout, shown, anchors)
            made = _PLACED.get(key)
            if made is None:
                made = _placed(layout, shown, anchors)
                _PLACED.put(key, made)
            spots, boxes, leaders = made
            self._lead(leaders)
        for handle, spot in zip(shown, spots, strict=True):
            if np.isfinite(spot).all():
                set_pose(handle, [float(x) for x in spot])
        if layout is None or not shown:
            self._lead([])
        self.placed, self.boxes, self.layout = shown, boxes, layout  # the layout last: what it is placed for

    def _lead(self, leaders: list) -> None:
        """Draw ``leaders`` ((start, end) in 3-D [m]); the unused segments at zero length."""
        self.leader_count = len(leaders)
        if self.leaders is None:
            return
        set_if_changed(self.leaders, "visible", bool(leaders))
        if leaders:
            pts = np.zeros((len(self.handles), 2, 3))
            pts[: len(leaders)] = np.array(leaders)
            pts[len(leaders) :] = pts[0, 0]
            update_props(self.leaders, points=finite(pts).astype(np.float32))


def _placed(layout: Layout, shown: list[Any], anchors: np.ndarray) -> tuple[np.ndarray, np.ndarray, list]:
    """Where ``shown`` (anchored at ``anchors``) go in ``layout``: their 3-D spots, their boxes [px] and
    the leader lines (start, end) [m] of those moved away from their anchors."""
    px = project(layout.view, anchors, layout.width, layout.height)
    natural = np.array([label_box(h, p) for h, p in zip(shown, px, strict=True)])
    sizes = natural[:, 2:] - natural[:, :2]
    boxes = place(natural[:, [0, 3]], sizes, layout.rect, occupied=layout.avoid)  # bottom-left corners
    offsets = px - natural[:, [0, 3]]  # from a box's bottom-left corner to its label's point
    spots = anchors.copy()
    leaders = []
    for k, anchor in enumerate(anchors):
        if np.isfinite(px[k]).all():
            at = boxes[k, [0, 3]] + offsets[k]
            spots[k] = lift(layout.view, at, anchor, layout.width, layout.height)
            near = np.clip(px[k], boxes[k, :2], boxes[k, 2:])  # the box's point nearest its anchor
            if np.hypot(*(near - px[k])) > LEADER_PX:
                start = lift(layout.view, near, anchor, layout.width, layout.height)
                leaders.append((start, anchor))
    spots.setflags(write=False)  # shared by every tab that places the same labels alike
    boxes.setflags(write=False)
    return spots, boxes, leaders


def _placement_key(layout: Layout, shown: list[Any], anchors: np.ndarray) -> tuple:
    """Everything a placement depends on, as values: the camera, the canvas, and each label's words, size,
    anchoring and 3-D anchor."""
    v = layout.view
    labels = tuple((str(h.text), float(h.font_screen_scale), str(h.anchor)) for h in shown)
    camera = (v.position.tobytes(), v.look_at.tobytes(), v.up.tobytes(), float(v.fov), float(v.aspect))
    return (camera, layout.width, layout.height, layout.rect, layout.avoid, labels, anchors.tobytes())


class _Recent:
    """The last few placements made in this process: the followers of a room that show the same labels
    through the same camera in the same canvas (each placing its own scene's labels when the presenter
    turns the camera) work them out once. Values are never changed after they are put."""

    def __init__(self, size: int) -> None:
        self._size, self._lock = size, threading.Lock()
        self._items: OrderedDict[tuple, tuple[np.ndarray, np.ndarray, list]] = OrderedDict()

    def get(self, key: tuple) -> tuple[np.ndarray, np.ndarray, list] | None:
        with self._lock:
            made = self._items.get(key)
            if made is not None:
                self._items.move_to_end(key)
            return made

    def put(self, key: tuple, made: tuple[np.ndarray, np.ndarray, list]) -> None:
        with self._lock:
            self._items[key] = made
            while len(self._items) > self._size:
                self._items.popitem(last=False)


_PLACED = _Recent(32)
