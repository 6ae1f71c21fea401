"""The app in a real headless Chromium: it loads, a keyboard-moved slider changes readouts and 3-D view.

Uses Debian's ``/usr/bin/chromium`` through Playwright (never ``playwright
install``). Where ``CI`` is set a missing browser or Playwright fails the
test; locally it is skipped. The final screenshot is saved to
``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import (
    VIEWPORT,
    app_page,
    canvas_box,
    steady_canvas,
)
from fakes import poll

from app.server import Lab
from app.viser_adapter import handle_uuid

pytestmark = pytest.mark.browser


def _modal_open(page) -> bool:
    return page.locator(".mantine-Modal-content .jl-big").count() > 0


@pytest.mark.slow
def test_app_in_chromium_at_1280x720(tmp_path):
    """Layout, keyboard sliders, the view changing, a singular configuration, and the enlarged J closing
    with Escape, its × and a click outside."""
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        poll(lambda: session.snapshot is not None and page.locator(".jl-matrix").count() > 0)
        poll(lambda: page.title() == "Jacobian Lab")

        # The 3-D view is the largest thing on screen, and joints and J are both in sight.
        box = canvas_box(page)
        share = box["width"] * box["height"] / (VIEWPORT["width"] * VIEWPORT["height"])
        assert share >= 0.55, f"the 3-D view has {share:.0%} of the window"
        last_slider = page.locator("[role=slider]").nth(session.state.robot.dof - 1).bounding_box()
        assert last_slider["y"] + last_slider["height"] <= VIEWPORT["height"]
        matrix = page.locator(".jl-matrix").first.bounding_box()
        assert matrix["y"] < VIEWPORT["height"] - 100, "the numeric J is out of sight"
        assert "regular" in page.locator(".jl-status").first.inner_text()

        # Arrow keys on a slider move the joint (1° a press; Shift: 0.1°), never the camera.
        canvas_before = steady_canvas(page)
        matrix_before = page.locator(".jl-matrix").first.inner_text()
        slider = session.panel.joints.sliders[1]
        q_before = float(session.state.q[1])
        camera_before = session.client.camera.position.copy()
        thumb = page.locator(f'[id="{handle_uuid(slider)}"] [role=slider]')
        thumb.first.focus()
        for _ in range(8):
            page.keyboard.press("ArrowRight")
        poll(lambda: session.state.q[1] == pytest.approx(q_before + math.radians(8.0), abs=1e-6))
        page.keyboard.press("Shift+ArrowRight")
        poll(lambda: session.state.q[1] == pytest.approx(q_before + math.radians(8.1), abs=1e-6))
        poll(lambda: page.locator(".jl-matrix").first.inner_text() != matrix_before)
        canvas_after = steady_canvas(page)
        np.testing.assert_allclose(session.client.camera.position, camera_before, atol=1e-6)
        changed = np.abs(canvas_after - canvas_before).max(axis=-1) > 30
        assert changed.mean() > 0.002, f"the 3-D view barely changed ({changed.mean():.4%} of pixels)"

        # A singular configuration reads out in words and as ∞.
        page.get_by_label("Configuration", exact=True).first.click()
        page.get_by_role("option", name="wrist singular (singular)", exact=True).click()
        poll(lambda: "singular: wrist" in page.locator(".jl-status").first.inner_text())
        assert "∞" in page.locator(".jl-status").first.inner_text()
        body = page.locator("body").inner_text()
        assert "NaN" not in body and "nan" not in body.split()
        steady_canvas(page)
        shot = out_dir / "app_browser.png"
        page.screenshot(path=str(shot))
        print(f"screenshot: {shot}")

        # The enlarged J: live, and it closes with Escape, with its ×, and with a click outside.
        enlarge = page.get_by_role("button", name="Enlarge J (Esc closes)")
        for close in ("Escape", "x", "outside"):
            enlarge.click()
            poll(lambda: _modal_open(page))
            assert session.panel.matrix.enlarged
            if close == "Escape":
                page.keyboard.press("Escape")
            elif close == "x":
                page.locator(".jl-close-x").click()
            else:
                page.mouse.click(8, VIEWPORT["height"] - 8)
            poll(lambda: not _modal_open(page))
            poll(lambda: not session.panel.matrix.enlarged)
    assert not errors, errors
    assert session.errors == 0


@pytest.mark.slow
def test_explorer_in_chromium_play_a_preset_and_click_the_map(tmp_path):
    """The Motion tab: a preset and Play move the arm by itself (the 3-D view changes with no input)
    and the charts appear; the Maps tab: a click on the joint map moves the two joints there."""
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        page.get_by_role("tab", name="Motion").click()
        # The Motion tab opens on the robot's first preset: Play applies it and runs it.
        preset = page.get_by_label("Preset", exact=True).first
        assert preset.input_value() == "straight line into the wrist singularity"
        before = steady_canvas(page)
        page.get_by_role("button", name="Play", exact=True).click()
        poll(lambda: session.state.playing)
        assert session.state.motion.preset == "straight line into the wrist singularity"
        # Nothing else is touched: the arm moves by itself until it stops, saying why.
        poll(lambda: not session.state.playing)
        assert session.state.stopped.startswith("stopped:")
        # Moved over many steps of the tab's ticker: the motion's own time (where the path stops) does not
        # depend on the machine; the number of steps does (a busy machine ticks less often, each step at
        # most 4 periods), so the count is held against that cap.
        trace, period = session.state.motion.trace, session.ticker.period
        assert trace.t[-1] - trace.t[0] > 60 * period and len(trace) > 60 / 4
        after = steady_canvas(page)
        changed = np.abs(after - before).max(axis=-1) > 30
        assert changed.mean() > 0.01, f"the 3-D view barely changed ({changed.mean():.4%} of pixels)"
        page.get_by_text("joint rates q̇", exact=True).first.scroll_into_view_if_needed()
        poll(lambda: page.locator(".uplot").count() >= 3)
        assert page.locator(".uplot canvas").first.bounding_box()["width"] > 200
        page.screenshot(path=str(out_dir / "app_motion.png"))

        page.get_by_role("tab", name="Maps").click()
        page.get_by_label("Joint-space map of w", exact=True).first.check()
        poll(lambda: page.locator(".jl-map img").count() > 0)
        q_before = np.array(session.state.q)
        image = page.locator(".jl-map img").first
        image.scroll_into_view_if_needed()
        box = image.bounding_box()
        # A click lands on a whole pixel: the values wanted are those of the pixel clicked.
        x, y = round(box["x"] + 0.25 * box["width"]), round(box["y"] + 0.5 * box["height"])
        page.mouse.click(x, y)
        jm = session.snapshot.joint_map
        want_i = jm.lo[0] + (x - box["x"]) / box["width"] * (jm.hi[0] - jm.lo[0])
        want_j = jm.hi[1] - (y - box["y"]) / box["height"] * (jm.hi[1] - jm.lo[1])
        poll(lambda: abs(math.degrees(session.state.q[jm.i]) - want_i) < 1.0)
        poll(lambda: abs(math.degrees(session.state.q[jm.j]) - want_j) < 1.0)
        others = [k for k in range(len(q_before)) if k not in (jm.i, jm.j)]
        np.testing.assert_allclose(np.array(session.state.q)[others], q_before[others])
        page.screenshot(path=str(out_dir / "app_maps.png"))
    assert not errors, errors
    assert session.errors == 0
