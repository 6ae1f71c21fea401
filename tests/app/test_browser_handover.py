"""Issue 28, item 7, in headless Chromium at 1280×720: a second tab typing the presenter token does not
take the projector; the teacher's tab is asked (its Classroom box unfolds with "Hand over" and "Keep
presenting", in view), and only its click hands over. Screenshots go to ``$APP_SCREENSHOT_DIR``
(default: pytest's temporary directory)."""

from __future__ import annotations

import pytest
from browser_helpers import app_page, new_page, screenshot_dir, text_input, wait, whole_in_view

from app.server import Lab
from app.services.classroom import HANDED_OVER

pytestmark = [pytest.mark.browser, pytest.mark.slow]

TOKEN = "rK4-vq9T-w2Lm-8xPz"


def test_the_teacher_is_asked_and_hands_over_by_a_click(tmp_path):
    out = screenshot_dir(tmp_path)
    lab = Lab(port=0, presenter_token=TOKEN)
    with app_page(lab, path=f"/?presenter={TOKEN}") as (teacher_page, teacher, errors):
        wait(lambda: teacher.role.presenting)
        # The teacher's own notices are shown in this test (app_page hides the start-up toasts).
        teacher_page.add_style_tag(content=".mantine-Notifications-root { display: block !important; }")
        student_page = new_page(teacher_page.context.browser)
        student_page.on("pageerror", lambda exc: errors.append(f"pageerror: {exc}"))
        student_page.goto(lab.url)
        student_page.wait_for_selector("[role=slider]")
        wait(lambda: len(lab.sessions) == 2)
        student = next(s for s in lab.sessions.values() if s is not teacher)
        wait(lambda: student.role.following)
        box = text_input(student_page, student.panel.classroom.token)
        # A follower's box folds to its title line (the layout script, once per role, whenever it runs:
        # later on a busy machine): wait for the fold, then open it.
        wait(lambda: student_page.locator("[data-jl-folded]").count() > 0)
        student_page.get_by_text("Classroom ·").first.click()
        wait(box.is_visible)
        box.press_sequentially(TOKEN, delay=10)

        wait(lambda: teacher.role.asked and student.role.waiting)
        assert teacher.role.presenting and not student.role.presenting  # nothing switched yet
        hand_over = teacher_page.get_by_role("button", name="Hand over", exact=True)
        keep = teacher_page.get_by_role("button", name="Keep presenting", exact=True)
        wait(lambda: hand_over.is_visible() and keep.is_visible())  # the folded box unfolded
        wait(lambda: whole_in_view(teacher_page, hand_over) and whole_in_view(teacher_page, keep))
        body = teacher_page.locator("body").inner_text()
        assert "Another tab typed the presenter token and asks to present." in body
        wait(lambda: not box.is_visible())  # the asking tab's token box is hidden while it waits
        assert "this tab presents as soon as it agrees" in student_page.locator("body").inner_text()
        teacher_page.screenshot(path=str(out / "handover_teacher_asked.png"))
        student_page.screenshot(path=str(out / "handover_student_waiting.png"))

        hand_over.click()
        wait(lambda: student.role.presenting and teacher.role.following)
        assert teacher.role.note == HANDED_OVER
        wait(lambda: HANDED_OVER in teacher_page.locator("body").inner_text())
        wait(lambda: not hand_over.is_visible())
        teacher_page.screenshot(path=str(out / "handover_teacher_follows.png"))
        student_page.screenshot(path=str(out / "handover_student_presents.png"))
        assert not errors
