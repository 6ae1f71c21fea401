"""The acceleration map in a real headless Chromium (issue 29, items 6 and 2): in the v = J q̇ tab, q̈
typed into its slider draws the magenta J q̈ arrow beside the violet J̇ q̇ one, and 000's per-joint
terms J̇ᵢ q̇ᵢ stand beside J̇ q̇ with their difference. Screenshots (1280×720) go to
``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory)."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import VIEWPORT, app_page, image, steady_canvas
from fakes import poll

from app.core.actions import SetRate
from app.server import Lab
from app.viser_adapter import handle_uuid

pytestmark = [pytest.mark.browser, pytest.mark.slow]

_INPUT = (
    "xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]"
    "//input[contains(@class,'mantine-NumberInput-input')]"
)


def test_qdd_slider_draws_j_qdd_and_the_per_joint_terms_show_their_gap(tmp_path):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        page.get_by_role("tab", name="v = J q̇").click()
        session.dispatch(SetRate(1, math.radians(40.0)))  # the shoulder alone
        session.settle()
        panel = page.locator(".jl-accel")
        poll(lambda: "Only" in panel.inner_text())
        page.get_by_text("Joint accelerations q̈").click()  # the closed folder opens
        forward = session.panel.forward
        box = page.locator(f'[id="{handle_uuid(forward.accel_sliders[2])}"]').locator(_INPUT)
        before = steady_canvas(page)
        box.fill("120")
        box.press("Enter")
        poll(lambda: float(session.state.qdd[2]) == pytest.approx(math.radians(120.0)))
        poll(lambda: "magenta" in panel.inner_text())
        text = panel.inner_text()
        assert "J q̈" in text and "ẍ" in text and "the difference is zero" in text
        after = steady_canvas(page)
        magenta = np.all(np.abs(after.astype(int) - np.array([200, 0, 110])) < 40, axis=-1)
        was = np.all(np.abs(before.astype(int) - np.array([200, 0, 110])) < 40, axis=-1)
        assert magenta.sum() > 50 > was.sum(), (magenta.sum(), was.sum())  # the J q̈ arrow is drawn
        panel.scroll_into_view_if_needed()
        page.screenshot(path=str(out / "accel_qdd_one_joint.png"))

        for i, w in enumerate([30.0, 40.0, -35.0, 20.0, 45.0, -25.0]):
            session.dispatch(SetRate(i, math.radians(w)))
        session.settle()
        poll(lambda: "6 joints move" in panel.inner_text())
        gap = float(np.linalg.norm(session.snapshot.jdot_gap[:3]))
        assert gap > 0.05
        warn = panel.locator(".jl-warn").first
        assert "m/s²" in warn.inner_text()
        table = panel.locator("table.jl-vec").nth(1)
        box = table.bounding_box()
        assert box is not None and box["x"] + box["width"] <= VIEWPORT["width"]
        assert "J̇ q̇ − Σ" in table.inner_text()
        page.locator(".jl-accel summary").click()
        poll(lambda: page.locator(".jl-accel details .jl-matrix").nth(1).is_visible())
        warn.scroll_into_view_if_needed()
        page.screenshot(path=str(out / "accel_jdot_several_joints.png"))
        assert image(page.screenshot()).shape[:2] == (VIEWPORT["height"], VIEWPORT["width"])
    assert not errors, errors
