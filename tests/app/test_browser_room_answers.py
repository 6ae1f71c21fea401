"""Issue 31 in headless Chromium: a presenter (1280×720) asks the room about the Puma's wrist singularity,
two followers answer on their own screens (a laptop, and a phone at 390×844 by touch), the presenter
watches the bars and reveals. Every kind of question goes round once. Screenshots go to
``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_helpers import app_page, close_notifications, new_page, wait

from app.core.actions import GoTo
from app.core.i18n import translations
from app.server import Lab
from app.views.panel.question import ASK_LABELS
from app.viser_adapter import handle_uuid

pytestmark = [pytest.mark.browser, pytest.mark.slow]

TOKEN = "qA7-rT3m-Zk9w-4LpX"
PHONE = {"width": 390, "height": 844}


def _out(tmp_path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def _in_view(page, locator) -> bool:
    box = locator.bounding_box()
    size = page.viewport_size
    return (
        box is not None
        and box["width"] > 0
        and box["x"] >= 0
        and box["y"] >= 0
        and box["x"] + box["width"] <= size["width"]
        and box["y"] + box["height"] <= size["height"]
    )


def _text(page) -> str:
    return page.locator("body").inner_text()


def _choose(page, kind: str) -> None:
    """Pick a question in the presenter's menu (a Mantine select: its box, then the option)."""
    label = translations().gettext(ASK_LABELS[kind])
    page.get_by_label("Question", exact=True).first.click()
    page.get_by_role("option", name=label, exact=True).click()


def test_a_peer_instruction_round_on_laptops_and_a_phone(tmp_path):
    out = _out(tmp_path)
    lab = Lab(port=0, presenter_token=TOKEN)
    with app_page(lab, path=f"/?presenter={TOKEN}") as (teacher_page, teacher, errors):
        wait(lambda: teacher.role.presenting)
        browser = teacher_page.context.browser
        laptop_page = new_page(browser)
        phone_page = new_page(browser, PHONE, scale=2.0, touch=True)
        for page in (laptop_page, phone_page):
            page.on("pageerror", lambda exc: errors.append(f"pageerror: {exc}"))
            page.goto(lab.url)
            page.wait_for_selector("[role=slider]")
            close_notifications(page)
        wait(lambda: len(lab.sessions) == 3)
        laptop, phone = (s for s in lab.sessions.values() if s is not teacher)
        wait(lambda: laptop.role.following and phone.role.following)
        teacher.dispatch(GoTo("wrist_singular"))
        wait(lambda: laptop.state.configuration == "wrist_singular" == phone.state.configuration)

        # The teacher opens "Ask the room" and asks the first question of its menu (the kind).
        teacher_page.get_by_text("Ask the room", exact=True).first.click()
        ask = teacher_page.get_by_role("button", name="Ask the room", exact=True)
        wait(lambda: ask.is_visible())
        ask.click()
        wait(lambda: laptop.role.question is not None and phone.role.question is not None)
        wrist = laptop_page.get_by_role("button", name="wrist", exact=True)
        wait(lambda: wrist.is_visible() and _in_view(laptop_page, wrist))
        assert "The room is answering" in _text(teacher_page)  # the status line's "wrist" is hidden
        assert "singular: wrist" not in _text(teacher_page)
        elbow = phone_page.get_by_role("button", name="elbow", exact=True)
        wait(lambda: elbow.is_visible())
        elbow.scroll_into_view_if_needed()
        elbow.tap()  # a touch, not a mouse click
        wrist.click()
        wait(lambda: "2 of 2 tabs answered" in _text(teacher_page))
        wait(lambda: "● wrist" in _text(laptop_page))  # its own answer marked
        teacher_page.screenshot(path=str(out / "room_kind_teacher_bars.png"))
        laptop_page.screenshot(path=str(out / "room_kind_laptop_answered.png"))
        phone_page.screenshot(path=str(out / "room_kind_phone_answered.png"))
        reveal = teacher_page.get_by_role("button", name="Reveal the answer", exact=True)
        reveal.click()
        wait(lambda: "Right!" in _text(laptop_page))
        wait(lambda: "Not this time" in _text(phone_page))
        wait(lambda: "wrist" in teacher.panel.status.content)
        laptop_page.screenshot(path=str(out / "room_kind_laptop_right.png"))
        phone_page.screenshot(path=str(out / "room_kind_phone_wrong.png"))

        # Which direction is lost: four lines in the 3-D view, the answer by letter.
        _choose(teacher_page, "lost")
        ask.click()
        wait(lambda: laptop.role.question is not None and laptop.role.question.question.kind == "lost")
        seen = laptop.role.question
        (right,) = seen.question.right
        letter = laptop_page.get_by_role("button", name=right, exact=True)
        wait(lambda: letter.is_visible())
        letter.click()
        wrong = next(c for c in seen.question.choices if c != right)
        phone_letter = phone_page.get_by_role("button", name=wrong, exact=True)
        wait(lambda: phone_letter.is_visible())
        phone_letter.scroll_into_view_if_needed()
        phone_letter.tap()
        wait(lambda: "2 of 2 tabs answered" in _text(teacher_page))
        teacher_page.screenshot(path=str(out / "room_lost_teacher_candidates.png"))
        phone_page.screenshot(path=str(out / "room_lost_phone.png"))
        reveal.click()
        wait(lambda: "Right!" in _text(laptop_page))
        teacher_page.screenshot(path=str(out / "room_lost_teacher_revealed.png"))

        # det J: typed as the phone's language writes numbers (English here), then closed and revealed.
        _choose(teacher_page, "det")
        ask.click()
        wait(lambda: phone.role.question is not None and phone.role.question.question.kind == "number")
        box = phone_page.locator(f'label[for="{handle_uuid(phone.panel.question.typed)}"]').locator(
            "xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]//input"
        )
        wait(lambda: box.is_visible())
        box.scroll_into_view_if_needed()
        box.tap()
        box.fill("0")
        phone_page.get_by_role("button", name="Send", exact=True).tap()
        wait(lambda: "1 of 2 tabs answered" in _text(teacher_page))
        teacher_page.get_by_role("button", name="Close", exact=True).click()
        wait(lambda: "Closed" in _text(phone_page))
        reveal.click()
        wait(lambda: "Right!" in _text(phone_page))  # det J = 0 at the singularity, within the tolerance
        phone_page.screenshot(path=str(out / "room_det_phone_right.png"))
        assert not errors
