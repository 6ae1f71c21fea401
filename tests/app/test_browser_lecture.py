"""The demo the back row follows, in a real headless Chromium (issue 21, items 7–9): Play on a fresh page
moves the arm at a pace a teacher can narrate with the rates readable beside it, and the layout serves the
open tab at 1024×768, 1280×720, 150 % zoom and 1920×1080. Screenshots go to ``$APP_SCREENSHOT_DIR``
(default: pytest's temporary directory), one per size and tab.
"""

from __future__ import annotations

import os
import re
import time
from pathlib import Path

import pytest
from browser_helpers import app_page, text_contrasts, wait

from app.server import Lab
from app.views.panel.layout import KEY_TEXT_PX, MIN_TEXT_PX, TOP_MAX

pytestmark = pytest.mark.browser

_MEASURE = """() => {
  const box = (e) => { const b = e.getBoundingClientRect(); return {top: b.top, bottom: b.bottom, left: b.left,
    right: b.right, height: b.height, width: b.width}; };
  const column = document.querySelector('[data-dock-region="right"]');
  const top = column.querySelector('.jl-top'), views = column.querySelector('.jl-views');
  const shown = (cell) => [...cell.querySelectorAll('.mantine-ScrollArea-viewport')].find((v) => v.clientHeight > 0);
  const topView = shown(top), view = shown(views);
  const conf = [...top.querySelectorAll('label')].find((l) => l.textContent.trim() === 'Configuration');
  const row = conf.closest('.mantine-Flex-root');
  return {column: box(column), top: box(topView), view: box(view),
          sliders: [...top.querySelectorAll('[role=slider]')].map(box), configuration: box(row),
          topCut: top.querySelector('.jl-more') !== null,
          labelPx: parseFloat(getComputedStyle(conf).fontSize) * parseFloat(getComputedStyle(column).zoom || 1)};
}"""


def _out(tmp_path: Path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def test_play_on_a_fresh_page_runs_the_preset_at_a_narratable_pace_with_the_rates_beside_the_arm(tmp_path):
    out = _out(tmp_path)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        page.locator('[role=tab][title="Motion"]').first.click(timeout=120_000)
        page.get_by_role("button", name="Play", exact=True).click(timeout=120_000)  # the first click works
        wait(lambda: session.state.playing)
        started = time.monotonic()
        start = session.state.motion.start.copy()
        # The readout, read in one go in the page (it is redrawn every frame while the arm moves).
        read = """() => { const e = document.querySelector('.jl-live');
          const panel = document.querySelector('[data-dock-region="right"]').getBoundingClientRect();
          const b = e && e.getBoundingClientRect(); if (!b || b.width === 0) return null;
          return {text: e.innerText, x: b.left, y: b.top, right: b.right, bottom: b.bottom, panel: panel.left}; }"""
        # Near the singularity it is slowed down, and the readout says so with the rates as numbers:
        # watched (polled) until the motion stops.
        seen: dict[str, object] = {"pace": 1.0, "text": "", "box": None}

        def watch() -> bool:
            state = session.state
            seen["pace"] = min(float(seen["pace"]), state.motion.pace)  # type: ignore[arg-type]
            if not seen["text"] and state.playing:
                box = page.evaluate(read)
                if box is not None and "slowed ×" in box["text"]:
                    seen["text"], seen["box"] = box["text"], box
                    page.screenshot(path=str(out / "lecture_play_1280x720.png"))
            return not state.playing

        wait(watch, timeout=240)
        text = str(seen["text"])
        box = seen["box"]
        assert text, (
            f"the readout never said it was slowed down (least pace {seen['pace']}, "
            f"{time.monotonic() - started:.1f} s, {session.state.stopped!r}, t = {session.state.time:.2f} s)"
        )
        assert float(seen["pace"]) < 0.3  # type: ignore[arg-type]
        rates = re.findall(r"q̇[₁-₆]\s*([−-]?\d+\.\d)\s*°/s", text)
        assert len(rates) == 6, text
        assert "κ" in text and "σ" in text
        # Beside the arm: in the 3-D view (left of the panel), all of it in the window.
        assert isinstance(box, dict)
        assert box["x"] >= 0 and box["y"] >= 0 and box["right"] <= box["panel"] and box["bottom"] <= 720
        # The text is large enough for the back row (the rates at 18 px or more).
        size = page.evaluate(
            "() => parseFloat(getComputedStyle(document.querySelector('.jl-live-rate b')).fontSize)"
        )
        assert size >= 18
        wait(lambda: not session.state.playing, timeout=180)
        took = time.monotonic() - started
        end = session.state
        assert end.stopped.startswith("stopped:")
        assert abs(end.q - start).max() > 0.3  # the arm moved
        # Held at real time the Puma runs into its wrist singularity in 3 s; paced, the climax lasts.
        assert took > 7.0, f"over in {took:.1f} s"
        assert end.time < 0.5 * took  # the motion's own time ran slower than the clock
        page.screenshot(path=str(out / "lecture_stopped_1280x720.png"))
    assert not errors, errors


def test_the_split_is_tagged_right_when_the_status_comes_late():
    """The layout script finds the joints' cell by its status line. Run before the status was drawn, it
    marked every cell as a view for good (a CI run at ecd69c7: two ".jl-views" at 1024×768, the split
    never set). Here the script runs (a resize event: synchronously) once without the status, once with."""
    with app_page(Lab(port=0)) as (page, session, errors):
        wait(lambda: page.locator(".jl-top").count() == 1)
        counts = page.evaluate(
            """() => {
              const status = document.querySelector('.jl-status');
              status.classList.replace('jl-status', 'jl-status-later');
              window.dispatchEvent(new Event('resize'));
              status.classList.replace('jl-status-later', 'jl-status');
              window.dispatchEvent(new Event('resize'));
              return [document.querySelectorAll('.jl-top').length, document.querySelectorAll('.jl-views').length,
                      document.querySelectorAll('.jl-top.jl-views').length];
            }"""
        )
        assert counts == [1, 1, 0], counts
    assert not errors, errors


SIZES = [
    ("1024x768", {"width": 1024, "height": 768}, 1.0, 270),
    ("1280x720", {"width": 1280, "height": 720}, 1.0, 230),
    ("zoom150", {"width": 853, "height": 480}, 1.5, 120),
    ("1920x1080", {"width": 1920, "height": 1080}, 1.0, 340),
]
"""Name, viewport [CSS px], device pixels per CSS pixel, and the least height of the views of J [px]
(before: 226, 206, 110 and 350; at 1920×1080 the panel is now 1.5 times larger, its text too). The
joint labels keep one line ("q6 wrist swivel [°]"); the home's description wraps to two lines (issue 21:
no longer cut at one), paid for by tighter margins under the status."""


@pytest.mark.parametrize(("name", "viewport", "scale", "least"), SIZES, ids=[s[0] for s in SIZES])
def test_the_layout_serves_the_open_tab(tmp_path, name, viewport, scale, least):
    out = _out(tmp_path)
    lab = Lab(port=0)
    with app_page(lab, viewport=viewport, scale=scale) as (page, session, errors):
        wait(
            lambda: page.locator(".jl-top").count() == 1 and page.locator(".jl-views").count() == 1,
            timeout=120,
        )
        for tab in ("J(q)", "Motion"):
            page.locator(f'[role=tab][title="{tab}"]').first.click(timeout=120_000)
            wait(lambda: page.evaluate(_MEASURE)["view"]["height"] >= least)
            m = page.evaluate(_MEASURE)
            # Every joint slider and the Configuration menu are in sight, above the views of J.
            assert len(m["sliders"]) == session.state.robot.dof
            for b in [*m["sliders"], m["configuration"]]:
                assert m["top"]["top"] - 1 <= b["top"] and b["bottom"] <= m["top"]["bottom"] + 1, (
                    tab,
                    b,
                    m["top"],
                )
                assert b["bottom"] <= viewport["height"]
            assert not m["topCut"]
            # The joints' panel takes what it needs, at most TOP_MAX; the views of J the rest.
            assert m["top"]["bottom"] <= m["column"]["top"] + TOP_MAX * m["column"]["height"] + 1
            assert m["view"]["bottom"] <= viewport["height"] + 1
            page.screenshot(path=str(out / f"lecture_{name}_{tab.replace('(', '').replace(')', '')}.png"))
        # A panel that scales: 1.5 times at 1920×1080, its labels as well.
        zoom = {"1920x1080": 1.5, "zoom150": 0.8}.get(name, 1.0)
        assert m["column"]["width"] == pytest.approx(404 * zoom, abs=2)
        assert m["labelPx"] >= 13 * zoom - 0.5
        # On the projector's own pixels (× the browser's zoom) no text is smaller than at 1280×720, and at
        # 150 % every text is 1.2 times larger (the docs' 10.4′ at 8 m).
        least = min(t["px"] for t in text_contrasts(page) if t["t"]) * scale
        assert least >= (1.2 if name == "zoom150" else 1.0) * MIN_TEXT_PX - 0.05, least
    assert not errors, errors


def test_the_enlarged_j_leaves_the_sliders_free(tmp_path):
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        wait(lambda: page.locator(".jl-matrix").count() > 0, timeout=120)
        assert page.locator(".jl-hint").first.is_visible()  # a fresh tab's first hint …
        page.get_by_role("button", name="Enlarge J (Esc closes)").click(timeout=120_000)
        wait(lambda: page.locator(".mantine-Modal-content .jl-big").count() > 0)
        wait(lambda: not page.locator(".jl-hint").first.is_visible())  # … is not drawn over the enlarged J
        modal = page.locator(".mantine-Modal-content").first.bounding_box()
        panel = page.locator('[data-dock-region="right"]').first.bounding_box()
        assert modal["x"] + modal["width"] <= panel["x"] + 1
        # The slider's thumb is what a click there reaches (no overlay on it), and dragging it moves J.
        thumb = page.locator("[role=slider]").nth(1)
        b = thumb.bounding_box()
        hit = page.evaluate(
            "([x, y]) => { const e = document.elementFromPoint(x, y); return !!(e && e.closest('[role=slider], .mantine-Slider-root')); }",
            [b["x"] + b["width"] / 2, b["y"] + b["height"] / 2],
        )
        assert hit
        q_before = float(session.state.q[1])
        thumb.focus()
        page.keyboard.press("ArrowRight")
        wait(lambda: float(session.state.q[1]) != q_before)
        assert page.locator(".mantine-Modal-content .jl-big").count() > 0  # still open
        page.screenshot(path=str(_out(tmp_path) / "lecture_enlarged_1280x720.png"))
    assert not errors, errors


@pytest.mark.parametrize("tab", ["J(q)", "v = J q̇", "Motion", "Maps", "Derive", "View", "Build"])
def test_every_visible_text_reaches_4_5_to_1_and_12_px_on_screen(tmp_path, tab):
    """Issue 21, item 9, as the projector shows it: the computed colour of every visible text, with the
    opacity of its element and ancestors, over the backgrounds stacked behind it (viser fades an
    unselected tab to 0.65: its 11:1 colour read 4.04:1 on screen); its size on screen at least
    MIN_TEXT_PX (J's subscripts were 10.4 px), the status at least KEY_TEXT_PX."""
    out = _out(tmp_path)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        page.locator(f'[role=tab][title="{tab}"]').first.click(timeout=120_000)
        wait(lambda: page.locator(f'[role=tab][title="{tab}"][aria-selected="true"]').count() > 0)
        texts = wait(lambda: [t for t in text_contrasts(page) if t["t"]] or None)
        page.screenshot(path=str(out / f"contrast_{re.sub(r'[^A-Za-z]', '', tab) or 'J'}.png"))
        low = [t for t in texts if t["ratio"] < 4.5]
        assert len(texts) > 30 and not low, low
        small = [(t["t"], t["px"], t["cls"]) for t in texts if t["px"] < MIN_TEXT_PX]
        assert not small, small
        # Below the fold too (the charts' legends, the Maps figure): each view scrolled to its end.
        page.evaluate(
            "() => document.querySelectorAll('[data-dock-region] .mantine-ScrollArea-viewport')"
            ".forEach((v) => { v.scrollTop = v.scrollHeight; })"
        )
        page.wait_for_function("() => !document.querySelector('.jl-views .jl-more')")
        below = text_contrasts(page)
        page.screenshot(path=str(out / f"contrast_{re.sub(r'[^A-Za-z]', '', tab) or 'J'}_end.png"))
        bad = [
            (t["t"], t["px"], t["ratio"], t["cls"])
            for t in below
            if t["px"] < MIN_TEXT_PX or t["ratio"] < 4.5
        ]
        assert not bad, bad
        status = page.evaluate(
            "() => parseFloat(getComputedStyle(document.querySelector('.jl-status')).fontSize)"
        )
        assert status >= KEY_TEXT_PX


_SPLIT = """() => {
  const column = document.querySelector('[data-dock-region="right"]');
  const top = column.querySelector('.jl-top'), views = column.querySelector('.jl-views');
  if (!top || !views) return null;
  const sliders = [...top.querySelectorAll('[role=slider]')].map((s) => s.getBoundingClientRect().bottom);
  return {top: top.getBoundingClientRect().bottom, views: views.getBoundingClientRect().height,
          last: Math.max(...sliders), grow: top.style.getPropertyValue('flex-grow')};
}"""


def test_a_page_built_again_in_polish_keeps_the_split_under_the_joints(tmp_path):
    """The panel built again in another language (``?lang=pl``: the page is first drawn in English, then in
    Polish) is re-rendered by React over the split the page script set: the joints' cell got viser's grow
    of 0.5 back and took 547 of the column's 705 px, the views of J 154 px, an empty band under q6 (seen
    at 1280×720). The script sets its split again: the joints' panel ends under q6, the views of J get
    the rest, as in English."""
    out = _out(tmp_path)
    with app_page(Lab(port=0), path="/?lang=pl") as (page, session, errors):
        wait(lambda: session.language == "pl", timeout=120)
        # the joints' panel ends under its last slider (polled: under load the rebuilt panel's sliders
        # arrive after the split is set; on the old code the split never came back)
        wait(
            lambda: (
                (m := page.evaluate(_SPLIT)) is not None
                and m["grow"] == "0"
                and m["views"] >= 230
                and m["top"] - m["last"] <= 30
            ),
            timeout=120,
        )
        page.screenshot(path=str(out / "lecture_1280x720_pl.png"))
    assert not errors, errors
