"""The DH walk's tool step in a real headless Chromium (issue 29, item 1): the elbow 3R (001's spatial
3R, tool frame 4 = Tx(L3)), Derive tab, "DH frames", Next to step 4: ³T₄ and ⁰T₄ shown inside the
window and the frames drawn. Screenshot (1280×720) in ``$APP_SCREENSHOT_DIR``."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import VIEWPORT, app_page, steady_canvas
from fakes import poll

from app.core.commands import ChooseRobot
from app.core.snapshot.derive import METHODS
from app.server import Lab

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def test_the_dh_walk_ends_with_3T4_and_0T4(tmp_path):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        session.dispatch(ChooseRobot("elbow3r"))
        session.settle()
        page.get_by_role("tab", name="Derive").click()
        page.get_by_text("θᵢ", exact=True).first.wait_for()
        page.get_by_label("Walk through", exact=True).first.click()
        page.get_by_role("option", name=METHODS["dh"], exact=True).click()
        poll(lambda: session.state.options.derive == "dh")
        before = steady_canvas(page)
        for step in range(1, 4):
            page.get_by_role("button", name="Next ▶", exact=True).click()
            poll(lambda s=step: session.state.options.derive_step == s)
        head = page.get_by_text("Step 4 of 4: the tool frame, row 4 of the DH table", exact=True).first
        head.wait_for()
        page.get_by_role("button", name="Next ▶", exact=True).click()  # the end: it stays
        poll(lambda: session.state.options.derive_step == 3)
        body = page.locator(".jl-t4s").first
        text = body.inner_text()
        assert "³T₄" in text and "⁰T₄ = A₁ A₂ A₃ · ³T₄" in text and "0.4" in text  # a₃ = L3 = 0.4 m
        head.scroll_into_view_if_needed()
        box = body.bounding_box()
        assert box is not None and box["x"] + box["width"] <= VIEWPORT["width"]
        after = steady_canvas(page)
        changed = np.abs(after - before).max(axis=-1) > 30
        assert changed.mean() > 0.001  # the two frames drawn
        page.screenshot(path=str(out / "derive_dh_tool_step.png"))
    assert not errors, errors
