"""Issue 29 items 7 and 8 in Chromium at 1280×720: a slider at its end names the critical point in the
status (the whole sentence in the panel); the IK solutions folder finds the planar 2R's elbow up and down
and the student picks the other one from the menu (the tool stays, by fk)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import app_page
from fakes import poll

from app.core.actions import SetConfiguration, SetJoint
from app.core.commands import ChooseRobot
from app.server import Lab
from kinematics import fk

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def _out(tmp_path: Path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def test_a_joint_at_its_limit_is_named_a_critical_point(tmp_path):
    with app_page(Lab(port=0)) as (page, session, errors):
        session.dispatch(SetJoint(1, 10.0))  # the Puma's shoulder past its upper limit: held at it
        session.settle()
        line = page.get_by_text("Critical point").first
        line.wait_for()
        text = line.evaluate("e => e.parentElement.innerText")
        assert (
            "joint q2 shoulder is at" in text
            and text.count("q2 shoulder") == 1
            and "q̇2 ≤ 0" in text
            and "opposite sense only" in text
        )
        box = line.evaluate(
            "e => { const r = e.parentElement.getBoundingClientRect(); return [r.left, r.right]; }"
        )
        assert box[0] >= 870 and box[1] <= 1280  # inside the panel, wrapped, not cut
        page.screenshot(path=str(_out(tmp_path) / "critical_point_puma_shoulder_limit.png"))
        assert not errors


def test_the_ik_solutions_are_found_and_the_other_elbow_chosen(tmp_path):
    with app_page(Lab(port=0)) as (page, session, errors):
        session.dispatch(ChooseRobot("planar2"))
        session.settle()
        session.dispatch(SetConfiguration((0.2, 1.0)))
        session.settle()
        p0 = fk(session.state.robot, session.state.q)[:3, 3]
        page.locator('[role=tab]:has-text("Motion")').first.click()
        page.get_by_text("The IK solutions of this pose").first.click()
        find = page.get_by_role("button", name="Find the IK solutions")
        find.scroll_into_view_if_needed()
        find.click()
        page.get_by_text("2 IK solutions reach this pose").first.wait_for()
        menu = session.panel.motion.course.solutions.menu
        poll(lambda: len(menu.options) == 2)
        page.get_by_label("Solution", exact=True).first.click()  # open the menu
        page.get_by_role("option", name=menu.options[1], exact=True).click()
        poll(lambda: np.allclose(session.state.q, (1.2, -1.0), atol=1e-9))
        assert np.abs(fk(session.state.robot, session.state.q)[:3, 3] - p0).max() < 1e-9
        words = page.get_by_text("2 IK solutions reach this pose").first
        words.wait_for()
        words.evaluate("e => e.scrollIntoView({block: 'center'})")
        page.screenshot(path=str(_out(tmp_path) / "ik_solutions_planar2_elbow_down.png"))
        assert not errors


def test_the_workspace_cloud_marks_both_kinds_of_critical_points(tmp_path):
    from app.core.actions import SetOption

    with app_page(Lab(port=0)) as (page, session, errors):
        session.dispatch(SetOption("workspace", True))
        session.settle()
        page.get_by_role("tab", name="Maps").click()
        key = page.get_by_text("Critical points:").first
        key.wait_for()
        key.evaluate("e => e.scrollIntoView({block: 'center'})")
        text = key.inner_text()
        assert "near a singularity" in text and "with a joint at a limit" in text
        right = key.evaluate("e => e.getBoundingClientRect().right")
        assert right <= 1280
        page.screenshot(path=str(_out(tmp_path) / "workspace_cloud_critical_points.png"))
        assert not errors
