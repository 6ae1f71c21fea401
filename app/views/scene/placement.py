"""Labels placed in screen space (pure geometry): no two overlap, none leaves the visible view.

Issue 28, stumble 2. The 3-D labels (joints, lost directions, a Derive step's names) are anchored at
points of the scene; where they land on the screen depends on the camera. :func:`place` takes the
anchors already projected (:func:`app.views.camera.project`), each label's size in px
(:func:`label_size`) and the part of the canvas the panel leaves free (:func:`visible_rect`), and
returns each label's box: near its anchor, inside the rectangle, apart from the others.
:func:`lift` gives the 3-D point at the anchor's depth that projects to a placed spot, so the scene's
label can be put there. :mod:`app.views.scene.labels` does so for a tab's scene after each redraw
and camera move.
"""

from __future__ import annotations

import numpy as np

from ..camera import View, _basis

__all__ = [
    "visible_rect",
    "label_size",
    "text_width",
    "wrap",
    "place",
    "lift",
    "overlaps",
    "ADVANCE_EM",
    "CHAR_EM",
    "LINE_EM",
    "EM_PX",
]

_ADVANCES = {
    0.0: "\u0307",
    0.18: "ᵢ",
    0.191: "'",
    0.222: "ijlł‘’",
    0.26: "|",
    0.278: " !,./:;I[\\]ftíÍ·",
    0.334: "()-`r¹²³“”{}",
    0.355: '"',
    0.389: "*ᵀ",
    0.401: "ₙ°₀₁₂₃₄₅₆₇₈₉⁰⁴⁵⁶⁷⁸⁹",
    0.448: "ₑξ",
    0.5: "^∂Jcksvxyzçśźżć‖γλκν",
    0.556: "0123456789#$?L_abdeghnopquáéóúãõñąęńŁθ–δ√≈≤≥",
    0.584: "+<=>~×−βμα",
    0.617: "FTZŻσ",
    0.668: "&ABEKPSVXYÁÉŚΔπ",
    0.722: "CDHNRUwÚ",
    0.781: "GOQÓω",
    0.833: "Mm",
    0.889: "%",
    0.944: "W",
    1.015: "→←—…@",
}
ADVANCE_EM: dict[str, float] = {c: w for w, chars in _ADVANCES.items() for c in chars}
"""Advance width of a character [em] in the font viser's labels are drawn with: Arial's metrics
(viser's stack ends in Arial; Chromium on Linux draws it as the metric-compatible Liberation Sans),
measured with ``measureText`` in Chromium (GlyphAtlas.ts measures the same way), rounded up to the
next width of the table."""
CHAR_EM = 0.62
"""Advance of a character not in :data:`ADVANCE_EM` [em] (a wide average)."""
FONT_SLACK = 1.06
"""Widths grown by this: Segoe UI, Roboto and the Apple system font, ahead of Arial in viser's stack,
are up to a few per cent wider."""
LINE_EM = 1.2
"""Height of one line of a label [em]: the font's ascent + descent (Arial 0.91 + 0.21; Segoe UI
and Roboto up to 1.2)."""
PAD_LINES = 0.2
"""viser's background box is one ``BACKGROUND_PADDING_FRACTION`` (0.2) of a line wider and higher than
its text (labelLayout.ts)."""
EM_PX = 12.0
"""A label's em [CSS px] at ``font_screen_scale`` 1 (viser's ``SCREEN_EM_CSS_PX``)."""


def visible_rect(width: float, height: float, panel: float = 400.0) -> tuple[float, float, float, float]:
    """The part (x0, y0, x1, y1) [px] of a ``width`` × ``height`` canvas that the panel leaves visible:
    the canvas minus the docked panel's width on the right at 800 px wide or more, the upper 55 %
    on narrower (phone) screens. One function, to be swapped for the phone layout's own."""
    if width >= 800:
        return 0.0, 0.0, float(width - panel), float(height)
    return 0.0, 0.0, float(width), 0.55 * float(height)


def text_width(line: str, font_px: float) -> float:
    """Estimated advance width [px] of one line of text at ``font_px``."""
    return sum(ADVANCE_EM.get(c, CHAR_EM) for c in line) * font_px * FONT_SLACK


def label_size(text: str, font_px: float) -> tuple[float, float]:
    """Estimated (width, height) [px] of the box viser draws behind a label showing ``text`` (its
    lines) at ``font_px``: the text block plus :data:`PAD_LINES` of a line each way."""
    lines = text.split("\n") or [""]
    pad = PAD_LINES * LINE_EM * font_px
    width = max(text_width(line, font_px) for line in lines) + pad
    return width, len(lines) * LINE_EM * font_px + pad


def wrap(text: str, font_px: float, max_px: float) -> str:
    """``text`` with its lines broken at spaces so that each fits ``max_px`` [px] (by
    :func:`label_size`'s estimate; a single word longer than that stays whole): a phone's view is
    narrower than "traslación perdida (centro de la muñeca)"."""
    most = max_px - PAD_LINES * LINE_EM * font_px
    out: list[str] = []
    for line in text.split("\n"):
        current = ""
        for word in line.split(" "):
            longer = f"{current} {word}"
            if current and text_width(longer, font_px) > most:
                out.append(current)
                current = word
            else:
                current = longer if current else word
        out.append(current)
    return "\n".join(out)


def overlaps(boxes: np.ndarray) -> list[tuple[int, int]]:
    """The pairs (i, j) of boxes (N, 4: x0, y0, x1, y1) [px] that overlap."""
    b = np.asarray(boxes, float).reshape(-1, 4)
    out = []
    for i in range(len(b)):
        for j in range(i + 1, len(b)):
            if b[i, 0] < b[j, 2] and b[j, 0] < b[i, 2] and b[i, 1] < b[j, 3] and b[j, 1] < b[i, 3]:
                out.append((i, j))
    return out


_DIRECTIONS = np.array([(1, 0), (0, -1), (-1, 0), (0, 1), (1, -1), (-1, -1), (-1, 1), (1, 1)], float)
"""The spots of a ring, in the order they are tried: right, up, left, down, then the corners."""


def _candidates(anchor: np.ndarray, size: np.ndarray, step: float, rings: int) -> np.ndarray:
    """Top-left corners (K, 2) around ``anchor``: right above it first, then around it, ring by ring."""
    w, h = size
    d = np.tile(_DIRECTIONS, (rings, 1))
    out = anchor + d * (np.repeat(np.arange(1, rings + 1), len(_DIRECTIONS)) * step)[:, None]
    out[:, 1] -= h
    out[:, 0] -= np.where(d[:, 0] < 0, w, 0.0)  # a spot to the left ends there
    return np.vstack([anchor + (0.0, -h), out])  # first: the bottom-left corner on the anchor, as viser's


def place(
    anchors: np.ndarray,
    sizes: np.ndarray,
    rect: tuple[float, float, float, float],
    rings: int = 40,
    occupied: np.ndarray | tuple = (),
) -> np.ndarray:
    """Boxes (N, 4: x0, y0, x1, y1) [px] for labels of ``sizes`` (N, 2) [px] at ``anchors`` (N, 2) [px].

    In order (the first labels get the spots nearest their anchors): each label takes the first spot,
    on rings around its anchor, that lies inside ``rect`` and overlaps neither a label placed before nor
    a box of ``occupied`` (K, 4) [px] (what the page draws over the view: the motion's readout); an
    anchor outside ``rect`` (or not finite) is first moved to its nearest point inside. When no spot is
    free (more text than the view holds) the label takes the spot inside that overlaps least.
    """
    A = np.asarray(anchors, float).reshape(-1, 2)
    S = np.asarray(sizes, float).reshape(-1, 2)
    x0, y0, x1, y1 = rect
    step = max(4.0, float(S[:, 1].min()) / 2) if len(S) else 4.0
    taken = [np.asarray(b, float) for b in np.asarray(occupied, float).reshape(-1, 4)]
    placed: list[np.ndarray] = []
    for anchor, (w, h) in zip(A, S, strict=True):
        a = np.where(np.isfinite(anchor), anchor, ((x0 + x1) / 2, (y0 + y1) / 2))
        a = np.clip(a, (x0, y0), (x1, y1))
        corners = _candidates(a, np.array([w, h]), step, rings)
        corners[:, 0] = np.clip(corners[:, 0], x0, max(x0, x1 - w))
        corners[:, 1] = np.clip(corners[:, 1], y0, max(y0, y1 - h))
        boxes = np.column_stack([corners, corners + (w, h)])
        if placed or taken:
            P = np.array(taken + placed)
            ox = np.clip(
                np.minimum(boxes[:, None, 2], P[None, :, 2]) - np.maximum(boxes[:, None, 0], P[None, :, 0]),
                0,
                None,
            )
            oy = np.clip(
                np.minimum(boxes[:, None, 3], P[None, :, 3]) - np.maximum(boxes[:, None, 1], P[None, :, 1]),
                0,
                None,
            )
            cost = (ox * oy).sum(axis=1)
        else:
            cost = np.zeros(len(boxes))
        free = np.flatnonzero(cost <= 0)
        placed.append(boxes[free[0]] if len(free) else boxes[int(np.argmin(cost))])
    return np.array(placed).reshape(-1, 4)


def lift(view: View, spot: np.ndarray, anchor: np.ndarray, width: float, height: float) -> np.ndarray:
    """The 3-D point [m] at ``anchor``'s depth that projects to ``spot`` (2,) [px] on a ``width`` ×
    ``height`` canvas (the inverse of :func:`app.views.camera.project` at one depth)."""
    forward, right, up = _basis(view)
    z = float((np.asarray(anchor, float) - view.position) @ forward)
    f = height / 2 / np.tan(view.fov / 2)
    x, y = (spot[0] - width / 2) / f * z, (height / 2 - spot[1]) / f * z
    return view.position + forward * z + right * x + up * y
