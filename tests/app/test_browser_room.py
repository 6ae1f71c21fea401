"""In headless Chromium at 1280×720: a reload keeps the tab's robot, q and open tab (from the page's
address), and number boxes keep what is typed or refuse it in words (issue 21, items 10 and 11).
Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import app_page, close_notifications, new_page, text_input, wait

from app.core.actions import SetJoint
from app.core.commands import ChooseRobot
from app.server import Lab
from app.viser_adapter import handle_uuid

pytestmark = pytest.mark.browser


def _out(tmp_path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def _tab(page, label: str):
    return page.get_by_role("tab", name=label, exact=True)


def test_a_reload_keeps_robot_q_and_tab_and_typed_numbers_are_kept_or_refused(tmp_path):
    out = _out(tmp_path)
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        session.dispatch(ChooseRobot("trr"))
        session.dispatch(SetJoint(2, -0.5))
        session.settle()
        _tab(page, "q̇ = J⁺v").click(no_wait_after=True)  # the page rewrites its address (no navigation)
        href = lambda: page.evaluate("location.href")  # noqa: E731 (replaceState: page.url may lag)
        wait(lambda: "robot=trr" in href() and "tab=" in href() and "-0.5" in href())

        # Typed numbers: the course's 17.256 m/s is kept (not 17.2); "e" and a pasted "0,3" are
        # refused in words, a pasted 1e-3 is written out.
        box = page.locator(f'[id="{handle_uuid(session.panel.inverse.sliders[0])}"]').locator(
            "xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]//input[contains(@class,'mantine-NumberInput-input')]"
        )
        box.fill("17.256")
        wait(lambda: float(session.state.v_desired[0]) == pytest.approx(17.256))
        box.fill("")
        box.press_sequentially("1e-3")  # key by key: held, then written out as 0.001 on Enter
        tip = page.locator("#jl-typed-tip")
        wait(lambda: tip.is_visible() and "1e-3" in tip.inner_text())
        box.press("Enter")
        wait(lambda: float(session.state.v_desired[0]) == pytest.approx(0.001))
        assert "written as 0.001" in tip.inner_text() and box.input_value() == "0.001"
        box.fill("")
        page.evaluate(
            """(el) => { const dt = new DataTransfer(); dt.setData('text', '0,3');
                el.dispatchEvent(new ClipboardEvent('paste', {clipboardData: dt, bubbles: true})); }""",
            box.element_handle(),
        )
        wait(lambda: "use a point" in tip.inner_text())
        page.screenshot(path=str(out / "room_typed_refused.png"))
        assert float(session.state.v_desired[0]) != pytest.approx(3.0)

        # Reload: a new tab of the server, back on the TRR at q3 = −0.5 rad with the q̇ = J⁺v tab open.
        before = set(lab.sessions.values())
        q = np.array(session.state.q)
        page.reload()  # the address keeps robot, q and tab in its query (a fragment breaks viser's reconnect)
        page.wait_for_selector("[role=slider]", timeout=120_000)
        close_notifications(page)
        wait(lambda: any(s not in before for s in lab.sessions.values()))
        again = next(s for s in lab.sessions.values() if s not in before)
        wait(lambda: again.state.robot_name == "trr" and np.allclose(again.state.q, q, atol=1e-6))
        try:
            wait(lambda: _tab(page, "q̇ = J⁺v").get_attribute("aria-selected") == "true")
        except AssertionError as exc:
            page.screenshot(path=str(out / "room_after_reload_tab.png"))
            raise AssertionError((href(), again.panel.report.value)) from exc
        wait(lambda: page.locator(".jl-status").first.is_visible())
        page.screenshot(path=str(out / "room_after_reload.png"))
        assert again.panel.robot.value.endswith("(trr)")  # the menu's label: "TRR robot (…) (trr)"
        assert not errors, errors


def test_the_token_box_is_masked_typing_tries_once_and_the_presenter_link_leaves_no_token(tmp_path):
    """Issue 18, point 6, in the browser: the token typed key by key is masked and costs one try (not
    one per key); the presenter link fills the box, makes that tab present, and the token leaves the
    address bar."""
    out = _out(tmp_path)
    token = "rK4-vq9T-w2Lm"
    lab = Lab(port=0, presenter_token=token)
    with app_page(lab) as (page, student, errors):
        box = text_input(page, student.panel.classroom.token)
        wait(lambda: box.get_attribute("type") == "password")
        box.press_sequentially("nope", delay=20)  # a loaded machine may pause mid-word: a try or two
        wait(lambda: lab.classroom.wrong_tries(student.key) >= 1)  # once the typing paused, not per key
        assert lab.classroom.wrong_tries(student.key) <= 2
        page.screenshot(path=str(out / "room_token_masked.png"))
        assert not student.role.presenting

        presenter = new_page(page.context.browser)
        presenter.goto(f"{lab.url}/?presenter={token}")  # the link serve prints
        presenter.wait_for_selector("[role=slider]")
        wait(lambda: any(s.role.presenting for s in lab.sessions.values()))
        assert token not in presenter.evaluate("location.href")
        wait(lambda: "presenting" in presenter.locator("body").inner_text().lower())
        presenter.screenshot(path=str(out / "room_presenter_link.png"))
        assert not errors  # (the student tab's wrong try never held the presenter link back)
