"""One tab's labels kept in place on its screen: after each redraw (the scene places them) and, at most
every :data:`PLACE_EVERY` seconds, while its camera moves (an orbit, the app's glide) — the last
position always placed.

The layout (:class:`app.views.scene.labels.Layout`) is the browser's camera and its canvas [CSS px]:
the part of the window the panel leaves (:func:`app.views.panel.viewport.visible_view_rect`, from the
window size the page reported), or before that report the camera's canvas in its pixels (720 px high
if it has not said). Labels are placed inside the whole canvas, out of what the page draws over it: the
motion's readout while a motion is on screen and the first hint until the tab's first change (their
boxes estimated for the window: :func:`app.views.panel.live_box.live_box`,
:func:`app.views.panel.hint_box.hint_box`).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

from ..services.later import Call, later
from ..views.panel.hint_box import hint_box
from ..views.panel.layout import COLUMN
from ..views.panel.live_box import live_box
from ..views.panel.viewport import visible_view_rect
from ..views.scene.labels import Layout

__all__ = ["TabLabels", "PLACE_EVERY", "ASSUMED_HEIGHT"]

PLACE_EVERY = 0.1
"""Labels are placed again at most this often [s] while the camera moves."""
ASSUMED_HEIGHT = 720.0
"""The canvas's height [CSS px] until the page has reported its window."""


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
    """

    def __init__(
        self,
        client: Any,
        camera: Any,
        window: Callable[[], tuple[float, float, bool] | None],
        lock: Any,
        screen: Callable[[], Any],
        closed: Callable[[], bool],
    ) -> None:
        self.client, self.camera, self._window, self._lock = client, camera, window, lock
        self._screen, self._closed = screen, closed
        self._timer: Call | None = None
        self._last = 0.0
        self._tlock = threading.Lock()

    def layout(self) -> Layout | None:
        """The camera and canvas the labels are seen in, or None before the camera is known."""
        view = self.camera.view()
        if view is None:
            return None
        window = self._window()
        if window is None:  # the camera's canvas as a device of pixel ratio 1 (a bare websocket client)
            cam = self.camera.client.camera
            height = float(getattr(cam, "image_height", 0) or ASSUMED_HEIGHT)
            width = height * view.aspect
            window = (width + COLUMN, height, False)  # beside the docked panel
        else:
            r = visible_view_rect(*window)
            width, height = r.width, r.height
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
        """Place the scene's labels for the camera as it is now."""
        with self._lock:
            scene = getattr(self._screen(), "own_scene", None)
            if scene is None or self._closed():
                return
            try:
                with self.client.atomic():
                    scene.place_labels()
            except RuntimeError:  # a node removed meanwhile (the tab left): nothing to place
                return

    def close(self) -> None:
        with self._tlock:
            if self._timer is not None:
                self._timer.cancel()
                self._timer = None
