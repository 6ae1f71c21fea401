"""A student's phone and tablet (issue 28, "Phones and tablets"), in headless Chromium with a touch screen:
the 3-D view keeps what :func:`app.views.panel.viewport.visible_view_rect` says (measured on the real
boxes), the sheet and the hint do not overlap, no text is under 12 px, and a touch drag on a slider moves
the arm on the server. Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import app_page, text_contrasts
from fakes import poll

from app.server import Lab
from app.views.panel.layout import MIN_TEXT_PX
from app.views.panel.viewport import visible_view_rect

pytestmark = pytest.mark.browser

SIZES = {"phone": (390, 844), "landscape": (844, 390), "tablet": (768, 1024)}

_BOXES = """() => {
  const box = (e) => { if (!e) return null; const b = e.getBoundingClientRect();
    return {x: b.left, y: b.top, w: b.width, h: b.height}; };
  const sheet = [...document.querySelectorAll('.mantine-Paper-root')].find(
    (d) => getComputedStyle(d).position === 'fixed' && d.querySelector('[role=slider]'));
  const shown = (e) => { const b = e.getBoundingClientRect(); return b.width > 0 && b.height > 0; };
  return {canvas: box(document.querySelector('canvas')), sheet: box(sheet),
    column: box(document.querySelector('[data-dock-region="right"]')),
    hint: box(document.querySelector('.jl-hint')),
    labels: [...document.querySelectorAll('label')].filter(shown).map(box),
    thumbs: [...document.querySelectorAll('[role=slider]')].filter(shown).map(box)};
}"""


def _touch_page(size: tuple[int, int]):
    """The app on a touch screen of ``size`` CSS px at scale 2 (a phone's or tablet's)."""
    return app_page(Lab(port=0), {"width": size[0], "height": size[1]}, scale=2, touch=True)


def _overlap(a: dict[str, float], b: dict[str, float]) -> bool:
    return (
        a["x"] < b["x"] + b["w"] - 0.5
        and b["x"] < a["x"] + a["w"] - 0.5
        and (a["y"] < b["y"] + b["h"] - 0.5 and b["y"] < a["y"] + a["h"] - 0.5)
    )


@pytest.mark.parametrize("name", list(SIZES))
def test_the_view_keeps_what_visible_view_rect_says_and_nothing_overlaps(tmp_path, name):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    width, height = SIZES[name]
    with _touch_page(SIZES[name]) as (page, session, errors):
        # The page script settles the split and the zoom (it polls every 0.4 s): wait for the panel.
        def settled() -> dict[str, Any] | None:
            m = page.evaluate(_BOXES)
            panel = m["sheet"] if name == "phone" else m["column"]
            return m if panel and m["canvas"] and m["hint"] and panel["w"] > 0 else None

        m = poll(settled, what="the panel laid out")
        page.wait_for_timeout(1000)  # two more rounds of the page script; then read again
        m = poll(settled, what="the panel laid out")
        page.screenshot(path=str(out / f"phone-layout-{name}.png"))
        rect = visible_view_rect(width, height, touch=True)
        assert rect.width * rect.height >= 0.45 * width * height
        if name == "phone":
            sheet = m["sheet"]
            assert sheet["x"] == pytest.approx(0, abs=1) and sheet["w"] == pytest.approx(width, abs=1)
            assert sheet["y"] >= rect.height - 1  # the sheet starts below what is seen of the view
            assert m["canvas"]["h"] == pytest.approx(rect.height, abs=1)
            assert m["canvas"]["w"] == pytest.approx(rect.width, abs=1)
            assert not _overlap(m["hint"], sheet)
        else:
            assert m["column"]["x"] == pytest.approx(rect.width, abs=2)
            hint = m["hint"]
            assert hint["x"] + hint["w"] <= rect.width + 1
        for other in m["labels"] + m["thumbs"]:
            assert not _overlap(m["hint"], other), (m["hint"], other)
        for thumb in m["thumbs"]:
            assert 0 <= thumb["x"] and thumb["x"] + thumb["w"] <= width + 0.5
        small = [t for t in text_contrasts(page) if t["px"] < MIN_TEXT_PX - 0.05]
        assert not small, [(t["t"], t["px"]) for t in small]
        assert not errors


def test_a_touch_drag_on_a_slider_moves_the_arm():
    with _touch_page(SIZES["phone"]) as (page, session, errors):
        thumb = page.locator("[role=slider]").first
        poll(lambda: (b := thumb.bounding_box()) is not None and b["width"] > 0)
        box = thumb.bounding_box()
        assert box is not None
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        before = float(session.state.q[0])
        cdp = page.context.new_cdp_session(page)

        def touch(kind: str, px: float) -> None:
            points = [] if kind == "touchEnd" else [{"x": px, "y": y, "id": 1}]
            cdp.send("Input.dispatchTouchEvent", {"type": kind, "touchPoints": points})

        touch("touchStart", x)
        for step in range(1, 7):
            touch("touchMove", x + 10 * step)
        touch("touchEnd", x + 60)
        poll(lambda: abs(float(session.state.q[0]) - before) > 1e-3, what="q1 moved by the touch drag")
        # Dragged right: the joint's value grew.
        assert float(session.state.q[0]) > before
        assert not errors
