"""A student's phone and tablet (issue 28, "Phones and tablets"), in headless Chromium with a touch screen:
the 3-D view keeps what :func:`app.views.panel.viewport.visible_view_rect` says (measured on the real
boxes), the sheet and the hint do not overlap, no text is under 12 px, and a touch drag on a slider moves
the arm on the server. Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory).
"""

from __future__ import annotations

import os
import re
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from browser_helpers import app_page, screenshot_dir, text_contrasts, whole_in_view
from fakes import POLL_TIMEOUT, poll

from app.server import Lab
from app.views.panel.layout import MIN_TEXT_PX
from app.views.panel.viewport import visible_view_rect
from kinematics import jacobian

pytestmark = pytest.mark.browser

SIZES = {"phone": (390, 844), "landscape": (844, 390), "tablet": (768, 1024)}
LAYOUTS = [*SIZES, "phone-pl", "phone-pt"]
"""Each size in English, and the phone in Polish and Portuguese (longer words: the labels must still fit)."""

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


def _touch_page(size: tuple[int, int], path: str = ""):
    """The app on a touch screen of ``size`` CSS px at scale 2 (a phone's or tablet's); ``path``: after
    the address (``?lang=pl``)."""
    return app_page(Lab(port=0), {"width": size[0], "height": size[1]}, scale=2, touch=True, path=path)


def _overlap(a: dict[str, float], b: dict[str, float]) -> bool:
    return (
        a["x"] < b["x"] + b["w"] - 0.5
        and b["x"] < a["x"] + a["w"] - 0.5
        and (a["y"] < b["y"] + b["h"] - 0.5 and b["y"] < a["y"] + a["h"] - 0.5)
    )


@pytest.mark.parametrize("layout", LAYOUTS)
def test_the_view_keeps_what_visible_view_rect_says_and_nothing_overlaps(tmp_path, layout):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    name, _, lang = layout.partition("-")
    width, height = SIZES[name]
    with _touch_page(SIZES[name], f"?lang={lang}" if lang else "") as (page, session, errors):
        if lang:
            poll(lambda: session.language == lang, what="the page's language")

        # The page script settles the split and the zoom (it polls every 0.4 s): wait for the panel.
        def settled() -> dict[str, Any] | None:
            m = page.evaluate(_BOXES)
            panel = m["sheet"] if name == "phone" else m["column"]
            return m if panel and m["canvas"] and m["hint"] and panel["w"] > 0 else None

        m = poll(settled, what="the panel laid out")
        page.wait_for_timeout(1000)  # two more rounds of the page script; then read again
        m = poll(settled, what="the panel laid out")
        page.screenshot(path=str(out / f"phone-layout-{layout}.png"))
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
        if lang:  # the panel speaks the language (its labels were built again in it)
            assert page.get_by_text("Configuration", exact=True).count() == 0
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


def test_taps_open_the_configuration_menu_and_pick_a_singularity(tmp_path):
    """Touch on a menu (not only a slider): taps, as a finger gives them (touchstart/end, no mouse), on the
    Configuration menu and one of its named singularities. Before PHONE_CSS fixed the menu's list to the
    screen, the list flickered shut under the tap (it opened below the menu at the sheet's foot)."""
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    with _touch_page(SIZES["phone"]) as (page, session, errors):
        page.evaluate(
            "() => { window.__taps = []; addEventListener('touchend', (e) => __taps.push(e.type), true); }"
        )
        page.get_by_label("Configuration", exact=True).first.tap()
        option = page.get_by_role("option", name="wrist singular (singular)", exact=True)
        option.tap()
        poll(lambda: session.state.configuration == "wrist_singular", what="the tapped configuration")
        # The arm is at a singularity: J, computed here from the server's q, has lost rank.
        sigma = np.linalg.svd(jacobian(session.state.robot, session.state.q), compute_uv=False)
        assert sigma[-1] < 1e-9 * sigma[0]
        poll(
            lambda: "singular: wrist" in page.locator(".jl-status").first.inner_text(),
            what="the status says so",
        )
        page.screenshot(path=str(out / "phone-tap-wrist-singular.png"))
        taps = page.evaluate("() => window.__taps")
        assert len(taps) >= 2, taps  # both steps above were touches, not mouse clicks
        assert not errors


def test_a_tap_on_play_plays_the_blow_up_and_the_button_stays_under_the_finger(tmp_path):
    """On a phone the views of J are one folded line at the sheet's foot: a tap unfolds it, a tap opens
    Motion, a tap on Play plays the Puma's preset into its wrist singularity. Under the finger the Play
    button does not move while the motion plays and stops (the status above it grows out of sight: the
    sheet keeps its scroll anchored), and the joint-rate overlay shows the six rates above the arm."""
    out = screenshot_dir(tmp_path)
    with _touch_page(SIZES["phone"]) as (page, session, errors):
        unfold = page.locator('[aria-label^="Expand panel"]').first
        unfold.scroll_into_view_if_needed()
        unfold.tap()
        motion = page.get_by_role("tab", name="Motion").first
        poll(motion.is_visible, what="the views unfolded")
        motion.tap()
        play = page.get_by_role("button", name="Play", exact=True).first
        poll(play.is_visible, what="the Motion view open")
        play.scroll_into_view_if_needed()
        poll(lambda: whole_in_view(page, play), what="Play whole on the screen")
        start = play.bounding_box()
        assert start is not None
        q0 = np.array(session.state.q)
        play.tap()
        poll(lambda: session.state.playing, what="the motion plays")
        tops = []
        deadline = time.monotonic() + 10 * POLL_TIMEOUT  # a safety net: the preset stops in ~10 s
        while (session.state.playing or not session.state.stopped) and time.monotonic() < deadline:
            box = play.bounding_box()  # each read is a round trip to the page: no busy loop
            assert box is not None
            tops.append(box["y"])
        assert session.state.stopped, "the motion did not stop"
        assert max(abs(y - start["y"]) for y in tops) <= 1.0, sorted(set(tops))
        assert np.linalg.norm(np.array(session.state.q) - q0) > 0.1  # the arm went somewhere
        live = page.locator(".jl-live").first
        poll(lambda: "stopped" in live.inner_text(), what="the overlay says the motion stopped")
        text = live.inner_text()
        assert len(re.findall(r"q̇[₁-₆]\s*[−-]?\d+\.\d\s*°/s", text)) == 6, text
        box = live.bounding_box()
        assert box is not None and box["y"] >= 0 and box["y"] + box["height"] <= SIZES["phone"][1] / 2
        page.screenshot(path=str(out / "phone-tap-play-stopped.png"))
        assert not errors


_VALUE_BOXES = """() => [...document.querySelectorAll('input.mantine-NumberInput-input')]
  .filter((i) => i.getBoundingClientRect().width > 0)
  .map((i) => ({value: i.value, text: i.scrollWidth, box: i.clientWidth}))"""


@pytest.mark.parametrize("size", ["phone", "tablet"])
def test_every_slider_s_value_box_shows_its_whole_value(tmp_path, size):
    """Every joint just above its lower limit (the longest numbers a slider shows, "-179.9"): each value
    box shows its whole text. On a phone the box was 2 px short of "-179.9" (its last digit cut)."""
    from app.core.actions import SetJoint
    from app.core.ranges import from_display

    with app_page(
        Lab(port=0, robot="puma560"), {"width": SIZES[size][0], "height": SIZES[size][1]}, scale=2, touch=True
    ) as (page, session, errors):
        joints = session.panel.joints
        assert joints is not None
        for i, r in enumerate(joints.ranges):
            session.dispatch(SetJoint(i, from_display(r, r.lo + 0.1)))
        session.settle()
        shown = [f"{r.lo + 0.1:.1f}" for r in joints.ranges]

        def boxes() -> list[dict[str, Any]] | None:
            got = page.evaluate(_VALUE_BOXES)
            return got if [b["value"] for b in got[: len(shown)]] == shown else None

        got = poll(boxes, what=f"the sliders' boxes showing {shown}")
        page.screenshot(path=str(screenshot_dir(tmp_path) / f"value_boxes_{size}.png"))
        assert [b for b in got if b["text"] > b["box"]] == []
        assert not errors
