"""Where the 3-D view can be seen: the rectangle of the window not under the panel, at any window size.

viser lays its control panel out in one of two ways (its client, ``App.tsx``): from 577 CSS px wide the
panel is docked in a right column (:data:`~app.views.panel.layout.COLUMN` px wide, zoomed by the page
script in :mod:`app.views.panel.layout`); up to Mantine's ``xs`` breakpoint (36 em = 576 px, a phone
held upright) it is a sheet at the bottom of the screen, which our CSS makes as wide as the window and
at most :data:`SHEET_MAX` of its height. The 3-D view's canvas is the part left of the column (viser
lays it beside the docked panel: 876×720 in a 1280×720 window, measured in Chromium) or above the sheet
(:data:`PHONE_CSS` ends it there): :func:`visible_view_rect` is the canvas, and the tab's labels are
placed inside it (pure: the same numbers as the page script's, tested in Chromium).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from .layout import COLUMN, ZOOM_MAX

__all__ = [
    "MOBILE_MAX_WIDTH",
    "PHONE_CSS",
    "SHEET_MAX",
    "Rect",
    "is_phone_layout",
    "panel_zoom",
    "visible_view_rect",
]

MOBILE_MAX_WIDTH = 576
"""Widest window [CSS px] in which viser shows its panel as a bottom sheet (Mantine's xs, 36 em)."""
SHEET_MAX = 0.5
"""Largest share of the window's height the bottom sheet takes (viser's own is 60 %): the 3-D view keeps
at least half of a phone's screen."""
PHONE_LINES_PX = 40.0
"""On a phone, the most the status's lines in the motion's readout take [px] (two lines of 13 px text and
their gap; the rest scrolls inside): the readout over a 422 px view leaves the arm in sight."""


class Rect(NamedTuple):
    """A rectangle in CSS px, from the window's top-left corner."""

    x: float
    y: float
    width: float
    height: float


def is_phone_layout(width: float) -> bool:
    """Whether viser shows the panel as a bottom sheet at this window width [CSS px]."""
    return width <= MOBILE_MAX_WIDTH


def panel_zoom(width: float, height: float, touch: bool = False) -> float:
    """The docked column's zoom the page script sets (``zoomFor`` in :data:`layout.LAYOUT_JS`);
    ``touch``: a touch screen (CSS ``pointer: coarse``), where short screens keep zoom 1 (12 px text)."""
    if height < 600:
        return 1.0 if touch else max(0.8, math.floor(height / 600 * 20) / 20)
    z = min(width / 1280, height / 720)
    return min(ZOOM_MAX, max(1.0, math.floor(z * 20) / 20))


def visible_view_rect(width: float, height: float, touch: bool = False) -> Rect:
    """The part of the 3-D view not under the panel in a window of ``width``×``height`` CSS px.

    On a phone held upright it is the part above the bottom sheet when the sheet is pulled up (the
    least that is seen); elsewhere the part left of the docked column. ``touch``: a touch screen
    (a phone held sideways keeps the column at zoom 1)."""
    if is_phone_layout(width):
        return Rect(0.0, 0.0, float(width), float(height) * (1 - SHEET_MAX))
    column = COLUMN * panel_zoom(width, height, touch)
    return Rect(0.0, 0.0, max(0.0, float(width) - column), float(height))


PHONE_CSS = f"""
<style>
@media (max-width: {MOBILE_MAX_WIDTH}px) {{
  /* viser's bottom sheet: as wide as the phone (viser's is 20 em, leaving a strip of view beside it) and
     at most SHEET_MAX of its height, so the 3-D view keeps the upper half. */
  .mantine-Paper-root[style*="position: fixed"][style*="bottom: 0"] {{ width: 100% !important;
    max-height: {SHEET_MAX * 100:g}% !important; max-height: {SHEET_MAX * 100:g}dvh !important; }}
  div[style="width: 20em;"] {{ width: 100% !important; }}
  .mantine-ScrollArea-content:has(> div[style="width: 20em;"]) {{ display: block !important;
    width: 100% !important; min-width: 0 !important; }}
  /* The 3-D view is drawn in the upper half only (what the sheet leaves), so the camera frames the arm
     there rather than half under the sheet. */
  div:has(> canvas) {{ bottom: {SHEET_MAX * 100:g}% !important; }}
  div[style="width: 20em;"] .mantine-Text-root {{ font-size: max(1em, 12px) !important; }}
  /* The first hint and the motion's numbers: across the top of the view, above the arm (their sizes are
     app.views.panel.hint_box's and live_box's too). */
  .jl-hint {{ left: 8px; right: 8px; top: 8px; bottom: auto; max-width: none; font-size: 14px; }}
  .jl-live {{ left: 8px; right: 8px; top: 8px; width: auto; }}
  .jl-live-head {{ font-size: 14px; flex-wrap: wrap; gap: 0 10px; }}
  .jl-live-head b, .jl-live-rate b {{ font-size: 16px; }}
  .jl-live-rate {{ font-size: 13px; }}
  /* The status's lines under the rates at a stop: at most {PHONE_LINES_PX:g} px (two lines, the rest
     scrolled inside), so the readout leaves the arm in view (it took 200 of the view's 422 px). */
  .jl-live-lines {{ max-height: {PHONE_LINES_PX:g}px; overflow-y: auto; }}
  /* Thumbs large enough for a finger. */
  .mantine-Slider-thumb {{ width: 20px !important; height: 20px !important; border-radius: 50% !important; }}
  .mantine-Slider-root {{ min-height: 2.4em; }}
  /* A slider's value box (viser's 3 rem): its text is 12 px here, and "-179.9" lost its last digit. */
  .mantine-NumberInput-root[style*="width: 3rem"] {{ width: 3.6rem !important; }}
  /* A menu's list (Configuration, Robot) fixed to the screen: placed absolutely, the list opened below a
     menu at the sheet's foot made the page taller, which hid the menu from the list's placement, which
     closed the list: it flickered shut under a tap (hundreds of times a second). Fixed, it makes nothing
     taller and flips above the menu when the screen ends below it. */
  .mantine-Popover-dropdown {{ position: fixed !important; }}
}}
</style>
"""
"""CSS for a phone held upright (viser's bottom sheet): the sheet as wide as the screen and at most half
of it high, the hint and the motion's numbers over the top of the 3-D view."""
