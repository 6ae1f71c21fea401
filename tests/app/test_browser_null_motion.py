"""Issue 29 item 3 in Chromium at 1280×720: on the Puma's wrist singularity the Motion tab says the null
motion (q̇4 = −q̇6) and its button plays it: q4 and q6 swing, the tool pose does not move (fk)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import app_page
from fakes import poll

from app.core.actions import GoTo
from app.server import Lab
from kinematics import fk

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def test_the_null_motion_is_said_and_played_on_the_pumas_wrist_singularity(tmp_path):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    with app_page(Lab(port=0)) as (page, session, errors):
        session.dispatch(GoTo("wrist_singular"))
        poll(lambda: session.state.configuration == "wrist_singular")
        q0 = np.array(session.state.q)
        assert abs(q0[4]) < 1e-12
        T0 = fk(session.state.robot, q0)
        page.locator('[role=tab]:has-text("Motion")').first.click()
        page.get_by_text("Null motion at a singularity (Ker J)").first.click()  # open the folder
        words = page.get_by_text("lies in Ker J").first
        words.wait_for()
        assert "q̇4 = −q̇6" in words.inner_text()
        button = page.get_by_role("button", name="Play the null motion")
        button.scroll_into_view_if_needed()
        box = button.bounding_box()
        assert box is not None and box["width"] > 100 and box["y"] + box["height"] / 2 < 720
        page.screenshot(path=str(out / "null_motion_puma_wrist_words.png"))
        button.click()
        seen: list[np.ndarray] = []

        def sample() -> None:
            seen.append(np.array(session.state.q))

        poll(lambda: sample() or (session.state.motion.kind == "path" and abs(seen[-1][3] - q0[3]) > 0.5))
        page.screenshot(path=str(out / "null_motion_puma_wrist_playing.png"))
        poll(lambda: sample() or not session.state.playing, timeout=60)
        Q = np.array(seen)
        assert np.ptp(Q[:, 3]) > 0.5 and np.ptp(Q[:, 5]) > 0.5
        for q in Q:
            assert np.abs(fk(session.state.robot, q) - T0).max() < 1e-12
        page.get_by_text("moved the joints; the tool stood still").first.wait_for()
        page.screenshot(path=str(out / "null_motion_puma_wrist_done.png"))
        assert not errors
