"""One tab's labels kept in place on its screen: after each redraw (the scene places them) and, at most
every :data:`PLACE_EVERY` seconds, while its camera moves (an orbit, the app's glide) — the last
position always placed.

The layout (:class:`app.views.scene.labels.Layout`) is the browser's camera and its canvas [CSS px]:
the part of the window the panel leaves (:func:`app.views.panel.viewport.visible_view_rect`, from the
window size the page reported), or before that report the camera's canvas in its device pixels over a
guessed pixel ratio (:func:`guessed_pixel_ratio`; 720 px high if it has not said). Labels are placed
inside the whole canvas, out of what the page draws over it: the motion's readout while a motion is on
screen and the first hint until the tab's first change (their boxes estimated for the window:
:func:`app.views.panel.live_box.live_box`, :func:`app.views.panel.hint_box.hint_box`).

A tab whose scene others replay (the presenter, or the follower that drew a relayed state for the
followers of its look) hands each placement's messages on (:class:`Placement`, to ``placed``: the
classroom), and a follower showing that very drawing replays them (:meth:`TabLabels.replay`): when the
presenter orbits, the labels of every follower of its look move with its own.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..services.later import Call, later
from ..views.panel.hint_box import hint_box
from ..views.panel.layout import COLUMN
from ..views.panel.live_box import live_box
from ..views.panel.viewport import visible_view_rect
from ..views.scene.labels import Layout
from ..viser_adapter import capture_scene, replay_scene

__all__ = [
    "TabLabels",
    "Placement",
    "PLACE_EVERY",
    "ASSUMED_HEIGHT",
    "PHONE_PIXEL_RATIO",
    "guessed_pixel_ratio",
]

PLACE_EVERY = 0.1
"""Labels are placed again at most this often [s] while the camera moves."""
ASSUMED_HEIGHT = 720.0
"""The canvas's height [CSS px] until the page has reported its window."""


@dataclass(frozen=True)
class Placement:
    """The scene messages of one placement of the labels of ``state``'s drawing for ``look``
    (:meth:`app.tab.screen.Screen.look`)."""

    state: Any
    look: str
    messages: tuple


PHONE_PIXEL_RATIO = 2.0
"""Device pixels per CSS pixel taken for a phone (2 to 3 on today's phones: 2 errs towards labels larger
than they are, so they are set further apart, not over each other)."""


def guessed_pixel_ratio(user_agent: str) -> float:
    """Device pixels per CSS pixel of a browser whose page has not reported its window yet: a phone's
    (``Mobi`` in its ``User-Agent``, as MDN advises telling phones) :data:`PHONE_PIXEL_RATIO`, else 1.
    The camera reports its canvas in device pixels; the labels' sizes are CSS pixels. On a 390×844 phone
    at scale 2 the labels were placed for a 780×1688 canvas for the 2 s a 4× throttled page takes to
    build its panel and report its window."""
    return PHONE_PIXEL_RATIO if "Mobi" in user_agent else 1.0


class TabLabels:
    """Places a tab's scene labels for its camera and window.

    Args:
        client: The tab's viser client (``atomic``).
        camera: The tab's :class:`~app.tab.camera.TabCamera` (``view()``).
        window: The window the page reported: (width, height, touch), or None.
        lock: The session's lock (the scene's handles are the renderer's).
        screen: The tab's :class:`~app.tab.screen.Screen`: its ``own_scene`` (None while it shows another
            tab's nodes: a follower), ``live`` and ``hint``, the motion's readout and the first hint it
            drew over the 3-D view.
        closed: Whether the tab has gone.
        placed: Told each placement of a drawing other tabs replay (``screen.leads``).
        user_agent: The browser's ``User-Agent`` (:func:`guessed_pixel_ratio`).
    """

    def __init__(
        self,
        client: Any,
        camera: Any,
        window: Callable[[], tuple[float, float, bool] | None],
        lock: Any,
        screen: Callable[[], Any],
        closed: Callable[[], bool],
        placed: Callable[[Placement], None] | None = None,
        user_agent: str = "",
    ) -> None:
        self.client, self.camera, self._window, self._lock = client, camera, window, lock
        self._screen, self._closed, self.placed = screen, closed, placed
        self._timer: Call | None = None
        self.pixel_ratio = guessed_pixel_ratio(user_agent)  # until the page reports its window
        self._last = 0.0
        self._tlock = threading.Lock()

    def canvas(self) -> tuple[float, float, tuple] | None:
        """The canvas the labels are seen in [CSS px] and the page's window, or None before the camera is
        known: what :meth:`layout` needs besides the view (the look of a drawing, without working out
        the view)."""
        try:
            aspect = float(self.camera.client.camera.aspect)
        except Exception:
            return None
        if not (math.isfinite(aspect) and aspect > 0.05):
            return None
        window = self._window()
        if window is None:  # the camera's canvas, its pixel ratio guessed (1: a bare websocket client)
            cam = self.camera.client.camera
            height = float(getattr(cam, "image_height", 0) or ASSUMED_HEIGHT * self.pixel_ratio)
            height /= self.pixel_ratio  # its device pixels, in CSS px as the labels' sizes are
            width = height * aspect
            return width, height, (width + COLUMN, height, False)  # beside the docked panel
        r = visible_view_rect(*window)
        return r.width, r.height, window

    def layout(self) -> Layout | None:
        """The camera and canvas the labels are seen in, or None before the camera is known."""
        view = self.camera.view()
        canvas = self.canvas() if view is not None else None
        if view is None or canvas is None:
            return None
        width, height, window = canvas
        screen = self._screen()
        over = (
            live_box(str(getattr(screen, "live", "") or ""), window),
            hint_box(str(getattr(screen, "hint", "") or ""), window),
        )
        avoid = tuple((b.x, b.y, b.x + b.width, b.y + b.height) for b in over if b is not None)
        return Layout(
            view, width, height, (0.0, 0.0, width, height), avoid
        )  # the canvas at the window's corner

    def moved(self) -> None:
        """The camera moved: place the labels now, or once :data:`PLACE_EVERY` has passed."""
        with self._tlock:
            if self._timer is not None:
                return
            wait = self._last + PLACE_EVERY - time.monotonic()
            if wait > 0:
                self._timer = later(wait, self._trailing)
                return
            self._last = time.monotonic()
        self.place()

    def _trailing(self) -> None:
        with self._tlock:
            self._timer = None
            self._last = time.monotonic()
        self.place()

    def place(self) -> None:
        """Place the scene's labels for the camera as it is now (and hand the placement on when other
        tabs replay our drawing)."""
        with self._lock:
            screen = self._screen()
            scene = getattr(screen, "own_scene", None)
            if scene is None or self._closed():
                return
            try:
                with self.client.atomic(), capture_scene(self.client) as messages:
                    scene.place_labels()
            except RuntimeError:  # a node removed meanwhile (the tab left): nothing to place
                return
            placed = Placement(screen.shown, screen.look(), tuple(messages)) if screen.leads else None
        if placed is not None and placed.messages and self.placed is not None:
            self.placed(placed)  # outside our lock: the followers take theirs

    def replay(self, placed: Placement) -> bool:
        """Another tab placed the labels of a drawing we replay: place ours alike, if we show that very
        drawing (its state, replayed, for the same look). False when we do not show it (yet): the
        placement is then queued after the drawing it belongs to (:class:`app.core.commands.LabelsPlaced`)."""
        with self._lock:
            screen = self._screen()
            if screen is None or self._closed() or screen.shown is not placed.state:
                return False
            if screen.scene is not None and screen.own_scene is None and screen.look() == placed.look:
                with self.client.atomic():
                    replay_scene(self.client, placed.messages)
            return True

    def close(self) -> None:
        with self._tlock:
            if self._timer is not None:
                self._timer.cancel()
                self._timer = None
