"""002's third way to J⁻¹ in a real headless Chromium (issue 29, item 4): the TRR at the course's q in
the q̇ = J⁺v tab shows J⁻¹ from the closed-form inverse kinematics under the inverse of J, with the
course's figures, inside the window. Screenshot (1280×720) in ``$APP_SCREENSHOT_DIR``."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest
from browser_helpers import VIEWPORT, app_page
from fakes import poll

from app.core.actions import SetConfiguration
from app.core.commands import ChooseRobot
from app.server import Lab

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def test_trr_closed_form_jinv_beside_the_inverse_of_j(tmp_path):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        session.dispatch(ChooseRobot("trr"))
        session.dispatch(SetConfiguration((5.0, math.radians(60), math.radians(-15))))
        session.settle()
        page.get_by_role("tab", name="q̇ = J⁺v").click()
        closed = page.locator(".jl-closed")
        poll(lambda: closed.count() == 1 and "0.9647" in closed.inner_text())
        text = closed.inner_text()
        for figure in ("−0.5464", "0.9647", "0.7879", "third way", "the largest difference is 0"):
            assert figure in text, figure
        assert page.locator(".jl-matrix").filter(has_text="q̇1").count() >= 2  # J⁻¹ and ∂g/∂x
        closed.scroll_into_view_if_needed()
        box = closed.bounding_box()
        assert box is not None and box["x"] + box["width"] <= VIEWPORT["width"]
        assert box["y"] + box["height"] <= VIEWPORT["height"]
        page.screenshot(path=str(out / "closed_form_trr.png"))
    assert not errors, errors
