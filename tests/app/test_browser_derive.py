"""The Derive tab in a real headless Chromium at 1280×720: pick Whitney's method on the Puma, step to
joint 3, see the step's numbers and the 3-D view change, and nothing wider than the panel."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import (
    app_page,
    steady_canvas,
)
from fakes import poll

from app.server import Lab
from app.views.fmt import fixed
from kinematics import link_frames

pytestmark = pytest.mark.browser


@pytest.mark.slow
def test_derive_tab_in_chromium_walks_whitney_on_the_puma(tmp_path):
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    lab = Lab(robot="puma560", port=0)
    with app_page(lab) as (page, session, errors):
        page.get_by_role("tab", name="Derive").click()
        page.get_by_text("θᵢ", exact=True).first.wait_for()  # the DH table
        before = steady_canvas(page)
        page.get_by_label("Walk through", exact=True).first.click()
        page.get_by_role("option", name="Whitney: Jᵢ = zᵢ₋₁ × (pₙ − pᵢ₋₁)", exact=True).click()
        poll(lambda: session.state.options.derive == "whitney")
        for _ in range(2):
            page.get_by_role("button", name="Next ▶", exact=True).click()
        poll(lambda: session.state.options.derive_step == 2)
        page.get_by_text("Step 3 of 6: joint 3", exact=False).first.wait_for()
        # The step's numbers, computed here from DH frame 2: z₂ × (pₙ − p₂).
        L = link_frames(session.state.robot, session.state.q)
        column = np.cross(L[2, :3, 2], L[-1, :3, 3] - L[2, :3, 3])
        shown = ", ".join(fixed(x, 3) for x in column)
        cell = page.get_by_text(f"({shown}) m/rad", exact=True).first
        cell.scroll_into_view_if_needed()
        assert cell.is_visible()
        after = steady_canvas(page)
        changed = np.abs(after - before).max(axis=-1) > 30
        assert changed.mean() > 0.0005, f"the step is not drawn ({changed.mean():.4%} of pixels)"
        # Nothing in the tab is wider than the docked panel.
        widest = page.evaluate(
            "Math.max(...[...document.querySelectorAll('.jl-vec, .jl-dh, .jl-t4s')]"
            ".map(e => e.scrollWidth - e.clientWidth))"
        )
        assert widest <= 1, f"a Derive table overflows by {widest} px"
        page.screenshot(path=str(out_dir / "app_derive.png"))
    assert not errors, errors
    assert session.errors == 0
