"""Issue 32: followers in Chromium show the presenter's readouts and arm, drawn once per worker. The
server starts as the docs print it (``jacobian-lab serve --presenter``: the default workers, one per core),
the presenter opens the printed link and moves q1 with the keyboard; three followers (the kernel
spreads them over the workers; which one each lands on is not asserted) show the very J the presenter
shows, before and after the move. Screenshots go to ``$APP_SCREENSHOT_DIR``
(default: pytest's temporary directory)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_helpers import new_page, presenting_lab, served_browser
from fakes import poll

pytestmark = [pytest.mark.browser, pytest.mark.slow]

FIRST_TABLE = """() => {
  const t = Array.from(document.querySelectorAll('table')).find((e) => e.offsetParent !== null);
  return t ? t.innerText : '';
}"""


def test_followers_show_the_presenters_readouts_after_a_move(tmp_path):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    with served_browser(tmp_path, ["serve", "--presenter", "--port", "0"]) as (link, browser):
        base = link.split("?", 1)[0]
        presenter = new_page(browser)
        presenter.goto(link)
        title = presenter.get_by_text("Classroom · presenting", exact=False)
        poll(lambda: title.count() > 0 and title.first.is_visible(), what="the tab presents")
        followers = []
        for _ in range(3):
            page = new_page(browser)
            page.goto(base)
            page.wait_for_selector("[role=slider]", state="attached")
            followers.append(page)
        before = presenter.evaluate(FIRST_TABLE)
        assert before
        poll(lambda: all(f.evaluate(FIRST_TABLE) == before for f in followers), what="followers agree")
        thumb = presenter.locator("[role=slider]").first
        thumb.focus()
        for _ in range(8):
            thumb.press("ArrowRight")
        poll(lambda: presenter.evaluate(FIRST_TABLE) != before, what="the presenter's J moved")
        poll(
            lambda: all(f.evaluate(FIRST_TABLE) == presenter.evaluate(FIRST_TABLE) for f in followers),
            what="every follower shows the presenter's J",
        )
        presenter.screenshot(path=str(out / "hall_presenter.png"))
        followers[0].screenshot(path=str(out / "hall_follower.png"))
        followers[2].screenshot(path=str(out / "hall_follower_2.png"))


SLIDER_TEXTS = """() => Array.from(document.querySelectorAll('[role=slider]')).slice(0, 3)
  .map((s) => s.getAttribute('aria-valuenow'))"""


def test_chromium_followers_sent_one_follower_s_draw_show_the_presenter_s(tmp_path):
    """Three Chromium followers of one worker, alike: after the first moves one of them draws each move
    and the others are sent its frame as it is (app/tab/ride.py: its GUI updates and the room's scene,
    compressed once for all their sockets). Every browser decodes it and shows the presenter's J and
    sliders; the page raises no script error."""
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    with presenting_lab("hall-rides-4Rt8-long-enough-token") as (lab, browser, presenter_page, presenter):
        errors: list[str] = []
        followers = []
        for _ in range(3):
            page = new_page(browser)
            page.on("pageerror", lambda exc: errors.append(str(exc)))
            page.goto(lab.url)
            page.wait_for_selector("[role=slider]", state="attached")
            followers.append(page)
        sessions = [s for s in lab.sessions.values() if s is not presenter]
        poll(lambda: len(sessions) == 3 and all(s.role.following for s in sessions), what="three follow")
        thumb = presenter_page.locator("[role=slider]").first
        thumb.focus()
        rides = sum(s.rides for s in sessions)
        for _step in range(6):
            before = presenter.state
            thumb.press("ArrowRight")
            poll(lambda before=before: presenter.state.q != before.q, what="the presenter moved")
            poll(
                lambda: all(s.state is presenter.state for s in sessions), what="the followers took the move"
            )
            for s in sessions:
                s.settle()
        # moves were sent as one follower's draw (not every one: a follower whose panel differs for a
        # while, its symbolic J arriving later under load, draws its own until they are alike again)
        assert sum(s.rides for s in sessions) > rides
        # Every follower's page ends with what the presenter's shows, the very J and sliders (compared
        # at each poll: under load the presenter's own page may lag the server's drawing too).
        poll(
            lambda: (
                all(
                    f.evaluate(FIRST_TABLE) == presenter_page.evaluate(FIRST_TABLE)
                    and f.evaluate(SLIDER_TEXTS) == presenter_page.evaluate(SLIDER_TEXTS)
                    for f in followers
                )
                and bool(presenter_page.evaluate(FIRST_TABLE))
            ),
            what="every follower shows the presenter's J and sliders",
        )
        for i, f in enumerate(followers):
            f.screenshot(path=str(out / f"hall_rider_{i}.png"))
        assert not errors, errors
