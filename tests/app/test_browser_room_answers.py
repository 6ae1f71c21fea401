"""Issue 31 in headless Chromium: a presenter (1280×720) asks the room about the Puma's wrist singularity,
two followers answer on their own screens (a laptop, and a phone at 390×844 by touch), the presenter
watches the bars and reveals. Every kind of question goes round once. Screenshots go to
``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory)."""

from __future__ import annotations

import contextlib

import pytest
from browser_helpers import (
    app_page,
    close_notifications,
    new_page,
    screenshot_dir,
    served_browser,
    text_input,
    type_into,
    wait,
    whole_in_view,
)

from app.core.actions import GoTo
from app.core.i18n import translations
from app.server import Lab
from app.views.panel.question import ASK_LABELS

pytestmark = [pytest.mark.browser, pytest.mark.slow]

TOKEN = "qA7-rT3m-Zk9w-4LpX"
PHONE = {"width": 390, "height": 844}


def _text(page) -> str:
    return page.locator("body").inner_text()


def _choose(page, kind: str) -> None:
    """Pick a question in the presenter's menu (a Mantine select: its box, then the option)."""
    label = translations().gettext(ASK_LABELS[kind])
    page.get_by_label("Question", exact=True).first.click()
    page.get_by_role("option", name=label, exact=True).click()


@contextlib.contextmanager
def _room(langs: tuple[str, str] = ("", "")):
    """The teacher's tab presenting (1280×720), a laptop and a phone (390×844, touch) following in
    ``langs`` ("" : the browser's): yields (lab, errors, (teacher_page, laptop_page, phone_page),
    (teacher, laptop, phone)) — pages and their sessions."""
    lab = Lab(port=0, presenter_token=TOKEN)
    with app_page(lab, path=f"/?presenter={TOKEN}") as (teacher_page, teacher, errors):
        wait(lambda: teacher.role.presenting)
        browser = teacher_page.context.browser
        laptop_page = new_page(browser)
        phone_page = new_page(browser, PHONE, scale=2.0, touch=True)
        for page, lang in ((laptop_page, langs[0]), (phone_page, langs[1])):
            page.on("pageerror", lambda exc: errors.append(f"pageerror: {exc}"))
            page.goto(lab.url + (f"?lang={lang}" if lang else ""))
            page.wait_for_selector("[role=slider]")
            close_notifications(page)
        wait(lambda: len(lab.sessions) == 3)
        laptop, phone = (s for s in lab.sessions.values() if s is not teacher)
        wait(lambda: laptop.role.following and phone.role.following)
        yield lab, errors, (teacher_page, laptop_page, phone_page), (teacher, laptop, phone)


def test_a_peer_instruction_round_on_laptops_and_a_phone(tmp_path):
    out = screenshot_dir(tmp_path)
    with _room() as (lab, errors, pages, sessions):
        (teacher_page, laptop_page, phone_page), (teacher, laptop, phone) = pages, sessions
        teacher.dispatch(GoTo("wrist_singular"))
        wait(lambda: laptop.state.configuration == "wrist_singular" == phone.state.configuration)

        # The teacher opens "Ask the room" and asks the first question of its menu (the kind).
        teacher_page.get_by_text("Ask the room", exact=True).first.click()
        ask = teacher_page.get_by_role("button", name="Ask the room", exact=True)
        wait(lambda: ask.is_visible())
        ask.click()
        wait(lambda: laptop.role.question is not None and phone.role.question is not None)
        wrist = laptop_page.get_by_role("button", name="wrist", exact=True)
        wait(lambda: wrist.is_visible() and whole_in_view(laptop_page, wrist))
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
        box = text_input(phone_page, phone.panel.question.typed)
        wait(lambda: box.is_visible())
        box.scroll_into_view_if_needed()
        box.tap()
        box.fill("0")
        wait(lambda: str(phone.panel.question.typed.value) == "0")  # held before Send: see type_into
        phone_page.get_by_role("button", name="Send", exact=True).tap()
        wait(lambda: "1 of 2 tabs answered" in _text(teacher_page))
        teacher_page.get_by_role("button", name="Close", exact=True).click()
        wait(lambda: "Closed" in _text(phone_page))
        reveal.click()
        wait(lambda: "Right!" in _text(phone_page))  # det J = 0 at the singularity, within the tolerance
        phone_page.screenshot(path=str(out / "room_det_phone_right.png"))
        assert not errors


def test_a_round_on_the_default_serve_revealed_by_play_with_a_polish_phone(tmp_path):
    """What the docs print: ``jacobian-lab serve --presenter`` (a worker per core; the followers may land
    on either), the printed link for the teacher, a laptop in English and a phone in Polish (``?lang=pl``).
    The teacher asks which joint's rate blows up before Play; the reveal plays the motion on every screen."""
    out = screenshot_dir(tmp_path)
    with served_browser(tmp_path, ["serve", "--presenter", "--port", "0"]) as (link, browser):
        base = link.split("?", 1)[0]
        teacher = new_page(browser)
        teacher.goto(link)
        title = teacher.get_by_text("Classroom · presenting", exact=False)
        wait(lambda: title.count() > 0 and title.first.is_visible())
        laptop = new_page(browser)
        laptop.goto(base)
        phone = new_page(browser, PHONE, scale=2.0, touch=True)
        phone.goto(base + "?lang=pl")
        for page in (laptop, phone):
            page.wait_for_selector("[role=slider]", state="attached")
            close_notifications(page)
        wait(lambda: "2 tabs follow" in _text(teacher))
        teacher.get_by_text("Ask the room", exact=True).first.click()
        _choose(teacher, "blowup")
        teacher.get_by_role("button", name="Ask the room", exact=True).click()
        q4 = laptop.get_by_role("button", name="q4", exact=True)
        wait(lambda: q4.is_visible())
        pl = translations("pl").gettext
        wait(lambda: pl("Which joint's rate blows up first?") in _text(phone))
        q2 = phone.get_by_role("button", name="q2", exact=True)
        q2.scroll_into_view_if_needed()
        q2.tap()
        q4.click()
        wait(lambda: "2 of 2 tabs answered" in _text(teacher))
        teacher.screenshot(path=str(out / "room_blowup_teacher_bars.png"))
        phone.screenshot(path=str(out / "room_blowup_phone_pl.png"))
        before = laptop.locator("[role=slider]").nth(3).get_attribute("aria-valuenow")
        teacher.get_by_role("button", name="Reveal the answer", exact=True).click()
        wait(lambda: "Right!" in _text(laptop))
        wait(lambda: pl("Not this time: the answer is {answer}.").split(":")[0] in _text(phone))
        # Play runs: the followers' q4 slider moves with the presenter's motion.
        wait(lambda: laptop.locator("[role=slider]").nth(3).get_attribute("aria-valuenow") != before)
        laptop.screenshot(path=str(out / "room_blowup_laptop_playing.png"))
        phone.screenshot(path=str(out / "room_blowup_phone_pl_revealed.png"))


def test_kappa_and_the_teachers_own_question_in_portuguese_and_spanish(tmp_path):
    """The two kinds the first test leaves out: κ typed on a Portuguese phone with a decimal comma, and the
    teacher's own question (typed in the presenter's box) answered on a Spanish laptop and the phone."""
    out = screenshot_dir(tmp_path)
    with _room(("es", "pt")) as (lab, errors, pages, sessions):
        (teacher_page, laptop_page, phone_page), (teacher, laptop, phone) = pages, sessions
        teacher_page.get_by_text("Ask the room", exact=True).first.click()
        ask = teacher_page.get_by_role("button", name="Ask the room", exact=True)
        reveal = teacher_page.get_by_role("button", name="Reveal the answer", exact=True)

        # κ at home, typed as Portuguese writes numbers.
        _choose(teacher_page, "kappa")
        ask.click()
        wait(lambda: phone.role.question is not None and phone.role.question.question.quantity == "kappa")
        kappa = phone.role.question.question.value
        box = text_input(phone_page, phone.panel.question.typed)
        wait(lambda: box.is_visible())
        box.scroll_into_view_if_needed()
        box.tap()
        box.fill(typed := f"{kappa:.2f}".replace(".", ","))
        wait(lambda: str(phone.panel.question.typed.value) == typed)
        pt = translations("pt").gettext
        phone_page.get_by_role("button", name=pt("Send"), exact=True).tap()
        wait(lambda: "1 of 2 tabs answered" in _text(teacher_page))
        reveal.click()
        wait(lambda: pt("Right!") in _text(phone_page))
        phone_page.screenshot(path=str(out / "room_kappa_phone_pt.png"))

        # The teacher's own question, with its choices and the right one by number.
        _choose(teacher_page, "custom")
        for handle, text in (
            (teacher.panel.question.own, "Where is the Puma's tool at home?"),
            (teacher.panel.question.own_choices, "in front of the base; above the base; behind it"),
            (teacher.panel.question.own_right, "1"),
        ):
            type_into(teacher_page, handle, text)
        ask.click()
        wait(lambda: laptop.role.question is not None and laptop.role.question.question.kind == "custom")
        front = laptop_page.get_by_role("button", name="in front of the base", exact=True)
        wait(lambda: front.is_visible())
        front.click()
        above = phone_page.get_by_role("button", name="above the base", exact=True)
        wait(lambda: above.is_visible())
        above.scroll_into_view_if_needed()
        above.tap()
        wait(lambda: "2 of 2 tabs answered" in _text(teacher_page))
        teacher_page.screenshot(path=str(out / "room_custom_teacher_bars.png"))
        reveal.click()
        es = translations("es").gettext
        wait(lambda: es("Right!") in _text(laptop_page))
        wait(lambda: pt("Not this time: the answer is {answer}.").split(":")[0] in _text(phone_page))
        laptop_page.screenshot(path=str(out / "room_custom_laptop_es.png"))
        assert not errors
