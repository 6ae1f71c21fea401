"""Where the motion's readout over the 3-D view (``.jl-live``, :func:`app.views.panel.live.live_html`) lies
in the window, estimated from its HTML and the sizes the CSS gives it, so the 3-D labels keep out of it.

The readout is ``position: fixed`` in the window's top-left corner (:data:`app.views.panel.layout.LAYOUT_CSS`:
12 px from the edges, 350 px wide, inside the docked column so zoomed with it), or across the top of a
phone held upright (:data:`app.views.panel.viewport.PHONE_CSS`: 8 px from the edges, its text
smaller). Its height is the sum of its rows (measured in Chromium: a head row of 27.6 px, or 24.8 on a
phone; a row of three rates 24.3 px, 21.6 on a phone; a line of 13 px text 17.55 px) and of its text's
lines, each line of words wrapped at the readout's width by an estimate of their widths
(:func:`app.views.scene.placement.text_width`, bold :data:`BOLD` wider, and :data:`WRAP_SLACK` more
for the fonts of other systems), so it errs towards a line too many. Against Chromium playing the Puma's
wrist blow-up (English and Polish; 1280×720, 1920×1080, 853×480, 390×844, 360×740): never lower; within
a pixel on the phones; elsewhere up to a line of 13 px text and the margin for rounding (zoomed) higher.
"""

from __future__ import annotations

import functools
import html as html_lib
import math
import re

from ..scene.placement import text_width
from .viewport import PHONE_LINES_PX, Rect, is_phone_layout, panel_zoom

__all__ = ["live_box", "text_lines", "text_span", "LINE", "WRAP_SLACK", "BOLD"]

LINE = 1.35
""".jl's line height [em]."""
SUB_EXTRA = 3.4
"""A line with a subscript (σ_min, J₁₁) is this much taller [px] (measured 3.25)."""
BOLD = 1.08
"""Bold text is this much wider than regular (measured in Chromium: 1.066 to 1.077)."""
WRAP_SLACK = 1.05
"""Text taken this much wider than estimated when wrapping: the readout is in the system's font (measured in
Chromium on Linux: Arial's widths; DejaVu Sans, where it is the system's, is about 10 % wider than
Arial, as wide as this with the estimate's own 6 %)."""
_EDGE = {False: 12.0, True: 8.0}  # [px] from the window's left and top (a phone's from its right too)
_WIDTH = 350.0  # [px] border box, on a projector
_CHROME = 2 * 1.0 + 2 * 4.0  # border and padding, top and bottom [px]
_INSET = 2 * 1.0 + 2 * 8.0  # border and padding, left and right [px]
_SUB_PAD = 10.0  # .jl-sub's padding-right [px]
_LINES_TOP = 3.0 + 1.0 + 3.0  # .jl-live-lines: margin, border and padding above [px]
_LINE_GAP = 2.0  # below each of its lines [px]
_ROUNDING = 2.0  # [px] more: a zoomed column rounds its rows (853×480, zoom 0.8: 1.35 px taller)
_TEXT_PX = 13.0  # the foot's and the lines' text [px]
_DESC_LINE = 1.2  # a configuration's description: its line height [em], at most two lines
_HEAD_PX = {False: 18.0, True: 16.0}  # the head's numbers (its words are smaller) [px]
_RATE_PX = {False: 18.0, True: 16.0}  # a rate's number [px]

_RATE = re.compile(r'class="jl-live-rate"')
_FOOT = re.compile(r'<div class="jl-live-foot">(.*?)</div>', re.S)
_HEAD_ROW = re.compile(r'<div class="jl-live-head">(.*?)</div>', re.S)
_LINES = re.compile(r'<div class="jl-live-lines">(.*)</div>\s*</div>\s*$', re.S)
_PIECE = re.compile(r'(?=<div class="jl-sub">)|(?=<input type="checkbox")')
_TAG = re.compile(r"<[^>]*>")


def _runs(fragment: str) -> list[tuple[str, bool]]:
    """The words of an HTML fragment with whether each is bold; a line break as ``("\\n", False)``."""
    out: list[tuple[str, bool]] = []
    bold = 0
    for token in re.split(r"(<[^>]*>)", fragment):
        if token.startswith("<"):
            name = token.strip("</>").split()[0].lower() if token.strip("</> ") else ""
            if name in ("b", "strong"):
                bold += -1 if token.startswith("</") else 1
            elif name == "br":
                out.append(("\n", False))
            continue
        for word in html_lib.unescape(token).split():
            out.append((word, bold > 0))
    return out


def text_lines(fragment: str, px: float, most: float) -> int:
    """How many lines ``fragment`` takes at ``px`` in ``most`` px (greedy at spaces; a word wider than a
    line breaks anywhere, as ``overflow-wrap: anywhere`` does)."""
    space = text_width(" ", px)
    count, used = 1, 0.0
    for word, bold in _runs(fragment):
        if word == "\n":
            count, used = count + 1, 0.0
            continue
        w = text_width(word, px) * (BOLD if bold else 1.0) * WRAP_SLACK
        if used and used + space + w > most:
            count, used = count + 1, 0.0
        if w > most:  # broken anywhere: its last part begins the next words' line
            count += math.ceil(w / most) - 1
            used = w - (math.ceil(w / most) - 1) * most
        else:
            used = used + space + w if used else w
    return count


def text_span(fragment: str, px: float) -> float:
    """How wide [px] ``fragment``'s longest line is unwrapped, by the estimate :func:`text_lines` wraps with
    (so a box as wide as its text, ``width: fit-content``, is taken this wide: never narrower)."""
    space, widest, used = text_width(" ", px), 0.0, 0.0
    for word, bold in _runs(fragment) + [("\n", False)]:
        if word == "\n":
            widest, used = max(widest, used), 0.0
            continue
        w = text_width(word, px) * (BOLD if bold else 1.0) * WRAP_SLACK
        used = used + space + w if used else w
    return widest


def _subs(fragment: str) -> int:
    return len(re.findall(r"<su[bp]>", fragment))


@functools.lru_cache(maxsize=256)  # a pure estimate, asked for by every follower's look of one state
def live_box(content: str, window: tuple[float, float, bool]) -> Rect | None:
    """The box (x, y, width, height) [CSS px, from the window's top-left corner] of the readout showing
    ``content`` (:func:`~app.views.panel.live.live_html`) in a window of (width, height, touch); None
    when it shows nothing."""
    if "jl-live" not in content:
        return None
    width, height, touch = window
    phone = is_phone_layout(width)
    zoom = 1.0 if phone else panel_zoom(width, height, touch)
    edge = _EDGE[phone]
    outer = width - 2 * edge if phone else _WIDTH
    inner = outer - _INSET
    numbers = _HEAD_PX[phone]
    h = _CHROME
    head = _HEAD_ROW.search(content)
    if head is not None:  # its three spans wrap on a narrow phone (flex-wrap), 10 px apart
        rows, used = 1, 0.0
        for span in re.split(r"</span>\s*<span>", head.group(1)):
            w = text_width(html_lib.unescape(_TAG.sub("", span)), numbers) * WRAP_SLACK
            if used and used + 10 + w > inner:
                rows, used = rows + 1, w
            else:
                used = used + 10 + w if used else w
        h += rows * (numbers * LINE + SUB_EXTRA)
    h += math.ceil(len(_RATE.findall(content)) / 3) * _RATE_PX[phone] * LINE
    foot = _FOOT.search(content)
    if foot is not None:
        h += text_lines(foot.group(1), _TEXT_PX, inner) * _TEXT_PX * LINE
    lines = _LINES.search(content)
    if lines is not None:
        below = 0.0
        for piece in _PIECE.split(lines.group(1)):
            if not _TAG.sub("", piece).strip():
                continue
            n = text_lines(piece, _TEXT_PX, inner - _SUB_PAD)
            if "jl-desc" in piece:  # two lines at most
                below += min(n, 2) * _TEXT_PX * _DESC_LINE + _LINE_GAP
            else:
                below += n * _TEXT_PX * LINE + min(n, _subs(piece)) * SUB_EXTRA + _LINE_GAP
        h += _LINES_TOP + (min(below, PHONE_LINES_PX) if phone else below)  # a phone's scroll inside
    return Rect(edge * zoom, edge * zoom, outer * zoom, (h + _ROUNDING) * zoom)
