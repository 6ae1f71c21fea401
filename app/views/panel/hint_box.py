"""Where the first hint (``.jl-hint``, :func:`app.views.panel.hint.hint_html`) lies in the window, estimated
from its HTML and the sizes its CSS gives it, so the 3-D labels keep out of it while it is shown.

On a projector the hint is ``position: fixed`` in the 3-D view's lower-left corner
(:data:`app.views.panel.style.BASE_CSS`: 72 px from the left, 14 px from the bottom, as wide as its text
up to ``min(640px, 100vw - 500px)``, 15 px text), inside the docked column, so zoomed with it
(:func:`app.views.panel.viewport.panel_zoom`: its offsets and sizes times the zoom, ``100vw`` the
window's own width). On a phone held upright it lies across the top of the view
(:data:`app.views.panel.viewport.PHONE_CSS`: 8 px from the edges, 14 px text). Its height is its lines
(wrapped by :func:`app.views.panel.live_box.text_lines`' estimate, which errs towards a line too many)
times the line height, with its padding and border. Against Chromium (English, Portuguese, Spanish and
Polish; 1280×720, 1366×768, 1920×1080, 853×480, 1024×768, 800×600, 844×390 and 768×1024 touch, 390×844
and 360×740 phones): never smaller; at most a line of its text higher, 1 px more each way; as wide, or
where its estimate of English's one line (606 px in Chromium) is wider than 618 px, 640 px wide (times
the zoom) and a line higher.
"""

from __future__ import annotations

import functools
import re

from .live_box import LINE, text_lines, text_span
from .viewport import Rect, is_phone_layout, panel_zoom

__all__ = ["hint_box", "LEFT", "BOTTOM", "MAX_WIDTH", "RESERVED", "EDGE", "FONT_PX"]

LEFT = 72.0
"""[px] from the window's left edge, on a projector (in the column's units: times its zoom)."""
BOTTOM = 14.0
"""[px] from the window's bottom edge, on a projector (times the column's zoom)."""
MAX_WIDTH = 640.0
"""Its widest border box [px], on a projector (times the column's zoom)."""
RESERVED = 500.0
"""It is at most the window's width less this [px] wide (``calc(100vw - 500px)``; times the zoom)."""
EDGE = 8.0
"""[px] from a phone's left, right and top edges."""
FONT_PX = {False: 15.0, True: 14.0}
"""Its text [px] on a projector and on a phone."""
_INSET = 2 * 1.0 + 2 * 10.0  # border and padding, left and right [px]
_CHROME = 2 * 1.0 + 2 * 4.0  # border and padding, top and bottom [px]
_MARGIN = 1.0  # [px] more each way: a zoomed column rounds its offsets (1366×768: its bottom 0.02 px lower)

_BODY = re.compile(r'<div class="[^"]*\bjl-hint\b[^"]*">(.*)</div>\s*$', re.S)


@functools.lru_cache(maxsize=256)  # a pure estimate, asked for by every follower's look of one state
def hint_box(content: str, window: tuple[float, float, bool]) -> Rect | None:
    """The box (x, y, width, height) [CSS px, from the window's top-left corner] of the first hint showing
    ``content`` (:func:`~app.views.panel.hint.hint_html`) in a window of (width, height, touch); None when
    there is no hint."""
    body = _BODY.search(content)
    if body is None:
        return None
    text = body.group(1)
    width, height, touch = window
    phone = is_phone_layout(width)
    px = FONT_PX[phone]
    if phone:  # across the top, at zoom 1
        outer = width - 2 * EDGE
        h = text_lines(text, px, outer - _INSET) * px * LINE + _CHROME
        x, y, zoom = EDGE, EDGE, 1.0
    else:
        zoom = panel_zoom(width, height, touch)
        outer = min(MAX_WIDTH, width - RESERVED, text_span(text, px) + _INSET)
        h = text_lines(text, px, outer - _INSET) * px * LINE + _CHROME
        x, y = LEFT, height / zoom - BOTTOM - h  # in the column's units
    m = _MARGIN / zoom
    return Rect((x - m) * zoom, (y - m) * zoom, (outer + 2 * m) * zoom, (h + 2 * m) * zoom)
