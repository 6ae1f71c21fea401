"""Issue 29 item 5 in Chromium at 1280×720: the line picked in the Motion tab's path folder is drawn in the
3-D view, then the planar 2R follows it by the course's Jacobian method (the folder's button; the tool
stays on the line, by fk), then a circle near the
stretched singularity is lost and the words say so."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import app_page, steady_canvas
from fakes import poll

from app.core.actions import FollowToolPath, SetConfiguration
from app.core.commands import ChooseRobot
from app.core.tool_path import laid_out
from app.server import Lab
from app.views.palette import PLANNED_RGB
from kinematics import fk

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def test_the_planar_2r_follows_a_line_and_loses_a_circle_near_the_stretch(tmp_path):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    with app_page(Lab(port=0)) as (page, session, errors):
        session.dispatch(ChooseRobot("planar2"))
        session.settle()
        session.dispatch(SetConfiguration((0.3, 1.2)))
        session.settle()
        path = laid_out(session.state, "line")
        page.locator('[role=tab]:has-text("Motion")').first.click()
        page.get_by_text("Follow a path y(t): the Jacobian method").first.click()
        bare = steady_canvas(page)
        # Picking the line draws it in the 3-D view (sea green) before it is followed.
        page.get_by_label("Path", exact=True).first.click()  # open the menu
        page.get_by_role("option", name="a line", exact=True).click()
        poll(lambda: session.state.tool_path == "line" and session.scene.planned.line.visible)
        drawn = steady_canvas(page)
        green = [np.abs(c.astype(int) - PLANNED_RGB).max(axis=-1) <= 40 for c in (bare, drawn)]
        assert green[0].sum() < 20 < green[1].sum(), (green[0].sum(), green[1].sum())
        page.get_by_role("button", name="Follow the path").scroll_into_view_if_needed()  # the menu in view
        page.screenshot(path=str(out / "planned_path_planar2_line.png"))
        button = page.get_by_role("button", name="Follow the path")
        button.scroll_into_view_if_needed()
        button.click()
        seen: list[np.ndarray] = []

        def sample() -> None:
            seen.append(fk(session.state.robot, session.state.q)[:3, 3])

        poll(lambda: sample() or (session.state.motion.kind == "path" and session.state.playing))
        poll(lambda: sample() or not session.state.playing, timeout=60)
        a, b = path.point(0.0), path.point(path.duration)
        for p in seen[2:]:  # on the segment a–b (distance to the line, and between its ends)
            u = (b - a) / np.linalg.norm(b - a)
            assert np.linalg.norm((p - a) - ((p - a) @ u) * u) < 1e-6
            assert -1e-6 <= (p - a) @ u <= np.linalg.norm(b - a) + 1e-6
        assert np.linalg.norm(seen[-1] - b) < 1e-6
        page.get_by_text("the tool followed the line").first.wait_for()
        page.screenshot(path=str(out / "tool_path_planar2_line.png"))
        session.dispatch(SetConfiguration((-0.1, 0.12)))
        session.settle()
        session.dispatch(FollowToolPath("circle"))
        poll(lambda: session.state.motion.kind == "path")
        poll(lambda: not session.state.playing, timeout=60)
        page.get_by_text("the tool left the circle near a singularity").first.wait_for()
        page.locator(".u-title", has_text="joint rates").first.scroll_into_view_if_needed()
        page.screenshot(path=str(out / "tool_path_planar2_circle_lost.png"))
        assert not errors
