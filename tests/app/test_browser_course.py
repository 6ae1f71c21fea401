"""The course's TRR example in a real headless Chromium: robot "trr", the q̇ = J⁺v tab, "Course example":
the course's J⁻¹ figures are on the page (and a 1280×720 screenshot of it is saved).

Same browser setup as :mod:`test_browser_app` (Debian's Chromium through Playwright; fails in CI,
skips locally only without a browser). Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's
temporary directory).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import VIEWPORT, app_page
from fakes import poll

from app.server import Lab

pytestmark = pytest.mark.browser


@pytest.mark.slow
def test_trr_course_example_in_three_clicks(tmp_path):
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        # Click 1: the robot.
        page.get_by_label("Robot", exact=True).first.click()
        page.get_by_role("option", name="TRR robot (course example) (trr)", exact=True).click()
        poll(lambda: session.state.robot_name == "trr")
        # Click 2: the tab. Click 3: the course's example.
        page.get_by_role("tab", name="q̇ = J⁺v").click()
        page.get_by_role("button", name="Course example").click()
        poll(lambda: float(session.state.v_desired[0]) == pytest.approx(17.256))

        inverse = page.locator(".jl-matrix").filter(has_text="q̇1")
        poll(lambda: "0.9647" in page.locator("body").inner_text())
        text = page.locator("body").inner_text()
        for figure in ("−0.5464", "0.9647", "0.7879", "10.35"):
            assert figure in text, figure
        # The rates: the course's (0.5 m/s, 90°/s, 45°/s).
        assert re.search(r"90°/s", text) and re.search(r"45°/s", text)
        expected = np.linalg.inv(session.snapshot.J_base[:3])
        np.testing.assert_allclose(session.snapshot.inverse.matrix, expected, atol=1e-12)
        box = inverse.first.bounding_box()
        assert box is not None and box["x"] + box["width"] <= VIEWPORT["width"]
        inverse.first.scroll_into_view_if_needed()
        page.screenshot(path=str(out_dir / "course_trr_inverse.png"))
    assert not errors, errors
