"""The first hint's box (:func:`app.views.panel.hint_box.hint_box`) against Chromium's: in every language
(Portuguese, Spanish and Polish longer than English) and ten windows (projectors 1280×720 to 1920×1080,
short screens zoomed 0.8, a phone and a tablet held either way), the estimate holds the box Chromium gave
``.jl-hint`` (``getBoundingClientRect``, measured with this commit's page; checked live in
test_browser_hint_labels.py), at most a line of its text (and the 1 px margin each way) taller; and its
sizes are the CSS's."""

from __future__ import annotations

import re

import pytest

import robots
from app.core.i18n import CODES, translations
from app.core.state import LabState
from app.views.panel.hint import hint_html
from app.views.panel.hint_box import BOTTOM, EDGE, FONT_PX, LEFT, MAX_WIDTH, RESERVED, hint_box
from app.views.panel.live_box import LINE
from app.views.panel.style import BASE_CSS
from app.views.panel.viewport import PHONE_CSS, is_phone_layout, panel_zoom

MEASURED = {
    ("en", (1280, 720, False)): (72, 675.75, 626.5, 30.25),
    ("en", (1366, 768, False)): (75.5938, 721.6875, 657.0938, 31.625),
    ("en", (390, 844, True)): (8, 8, 374, 47.7812),
    ("en", (844, 390, True)): (72, 325.5, 344, 50.5),
    ("en", (768, 1024, True)): (72, 939.25, 268, 70.75),
    ("en", (853, 480, False)): (57.5938, 428.0625, 282.3906, 40.75),
    ("en", (1920, 1080, False)): (108, 1014.625, 938.75, 44.375),
    ("en", (360, 740, True)): (8, 8, 344, 47.7812),
    ("en", (1024, 768, False)): (72, 703.5, 524, 50.5),
    ("en", (800, 600, False)): (72, 515.25, 300, 70.75),
    ("pt", (1280, 720, False)): (72, 655.5, 640, 50.5),
    ("pt", (1366, 768, False)): (75.5938, 700.4375, 672, 52.875),
    ("pt", (390, 844, True)): (8, 8, 374, 66.6719),
    ("pt", (844, 390, True)): (72, 305.25, 344, 70.75),
    ("pt", (768, 1024, True)): (72, 919, 268, 91),
    ("pt", (853, 480, False)): (57.5938, 411.875, 282.3906, 56.9375),
    ("pt", (1920, 1080, False)): (108, 984.25, 960, 74.75),
    ("pt", (360, 740, True)): (8, 8, 344, 66.6719),
    ("pt", (1024, 768, False)): (72, 703.5, 524, 50.5),
    ("pt", (800, 600, False)): (72, 515.25, 300, 70.75),
    ("es", (1280, 720, False)): (72, 655.5, 640, 50.5),
    ("es", (1366, 768, False)): (75.5938, 700.4375, 672, 52.875),
    ("es", (390, 844, True)): (8, 8, 374, 66.6719),
    ("es", (844, 390, True)): (72, 305.25, 344, 70.75),
    ("es", (768, 1024, True)): (72, 919, 268, 91),
    ("es", (853, 480, False)): (57.5938, 411.875, 282.3906, 56.9375),
    ("es", (1920, 1080, False)): (108, 984.25, 960, 74.75),
    ("es", (360, 740, True)): (8, 8, 344, 66.6719),
    ("es", (1024, 768, False)): (72, 703.5, 524, 50.5),
    ("es", (800, 600, False)): (72, 495, 300, 91),
    ("pl", (1280, 720, False)): (72, 655.5, 640, 50.5),
    ("pl", (1366, 768, False)): (75.5938, 700.4375, 672, 52.875),
    ("pl", (390, 844, True)): (8, 8, 374, 66.6719),
    ("pl", (844, 390, True)): (72, 305.25, 344, 70.75),
    ("pl", (768, 1024, True)): (72, 919, 268, 91),
    ("pl", (853, 480, False)): (57.5938, 411.875, 282.3906, 56.9375),
    ("pl", (1920, 1080, False)): (108, 984.25, 960, 74.75),
    ("pl", (360, 740, True)): (8, 8, 344, 66.6719),
    ("pl", (1024, 768, False)): (72, 703.5, 524, 50.5),
    ("pl", (800, 600, False)): (72, 515.25, 300, 70.75),
}
"""Chromium's ``.jl-hint`` box [CSS px]: x, y, width, height, by language and window (width, height, touch)."""


def new_tab_hint(code: str) -> str:
    state = LabState.initial("puma560", robots.load("puma560"))
    assert not state.started
    return hint_html(state, translations(code))


def zoom_of(window) -> float:
    return 1.0 if is_phone_layout(window[0]) else panel_zoom(*window)


@pytest.mark.parametrize(("code", "window"), list(MEASURED))
def test_the_estimate_holds_chromiums_box_at_most_a_line_taller(code, window):
    x, y, w, h = MEASURED[code, window]
    est = hint_box(new_tab_hint(code), window)
    assert est is not None
    assert est.x <= x and est.y <= y and est.x + est.width >= x + w and est.y + est.height >= y + h
    zoom, px = zoom_of(window), FONT_PX[is_phone_layout(window[0])]
    assert est.height <= h + (px * LINE + 2) * zoom + 0.5, (est, h)  # a line and the margin
    assert est.width <= w + (14 + 2) * zoom + 0.5, (est, w)  # English's 606 px line taken 640 wide


def test_every_language_has_a_hint_and_the_longer_ones_are_no_lower():
    english = hint_box(new_tab_hint("en"), (1280, 720, False))
    assert english is not None
    for code in CODES:
        html = new_tab_hint(code)
        assert "jl-hint" in html and (code == "en") == ("First:" in html)
        for window in {w for _, w in MEASURED}:
            est, en = hint_box(html, window), hint_box(new_tab_hint("en"), window)
            assert est is not None and en is not None and est.height >= en.height - 1e-9


def test_no_hint_no_box():
    state = LabState.initial("puma560", robots.load("puma560")).replace(started=True)
    assert hint_html(state) == "" and hint_box("", (1280, 720, False)) is None


def test_its_sizes_are_the_css():
    rule = re.search(r"\.jl-hint \{([^}]*)\}", BASE_CSS)
    assert rule is not None
    css = " ".join(rule.group(1).split())
    for part in (
        f"left: {LEFT:g}px;",
        f"bottom: {BOTTOM:g}px;",
        f"max-width: min({MAX_WIDTH:g}px, calc(100vw - {RESERVED:g}px));",
        f"font-size: {FONT_PX[False]:g}px;",
        "border: 1px solid",
        "padding: 4px 10px;",
    ):
        assert part in css, (part, css)
    phone = re.search(r"\.jl-hint \{\{([^}]*)\}\}|\.jl-hint \{([^}]*)\}", PHONE_CSS)
    assert phone is not None
    css = " ".join((phone.group(1) or phone.group(2)).split())
    for part in (
        f"left: {EDGE:g}px;",
        f"right: {EDGE:g}px;",
        f"top: {EDGE:g}px;",
        f"font-size: {FONT_PX[True]:g}px;",
    ):
        assert part in css, (part, css)
