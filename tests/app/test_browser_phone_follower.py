"""Issue 28, a student's phone at the climax: the default ``serve --presenter`` (workers, one per core), the
presenter at 1280×720 plays the Puma's first preset into its wrist singularity; a follower on a phone
(390×844, touch, mobile, scale 2) shows the same motion: the joint-rate overlay beside the arm while it is
slowed down at the singularity, and, once the motion stops, the very readout the presenter shows (the
rates, κ, σ) and the same status. Screenshots of both go to ``$APP_SCREENSHOT_DIR`` (default: pytest's
temporary directory)."""

from __future__ import annotations

import re

import pytest
from browser_helpers import (
    close_notifications,
    new_page,
    screenshot_dir,
    served_browser,
)
from fakes import poll

pytestmark = [pytest.mark.browser, pytest.mark.slow]

# The overlay is position: fixed (no offsetParent): shown means it has a box.
LIVE = """() => { const e = [...document.querySelectorAll('.jl-live')].find((e) => e.getClientRects().length > 0);
  if (!e) return null; const b = e.getBoundingClientRect();
  return {text: e.innerText, x: b.left, y: b.top, right: b.right, bottom: b.bottom}; }"""
STATUS = "() => { const e = document.querySelector('.jl-status'); return e ? e.innerText : ''; }"
# Whether the classroom box's body is hidden (folded to its title line), None when there is no such box.
CLASSROOM_FOLDED = """() => { const head = [...document.querySelectorAll('div[style*="cursor: pointer"]')]
  .find((d) => d.textContent.trim().startsWith('Classroom ·'));
  const body = head && head.nextElementSibling; return body ? body.getAttribute('aria-hidden') : null; }"""


def _rates(text: str) -> list[str]:
    return re.findall(r"q̇[₁-₆]\s*([−-]?\d+\.\d)\s*°/s", text)


def test_a_follower_on_a_phone_shows_the_presenters_wrist_blow_up_with_its_rates(tmp_path):
    out = screenshot_dir(tmp_path)
    with served_browser(tmp_path, ["serve", "--presenter", "--port", "0"]) as (link, browser):
        presenter = new_page(browser)
        presenter.goto(link)
        title = presenter.get_by_text("Classroom · presenting", exact=False)
        poll(lambda: title.count() > 0 and title.first.is_visible(), what="the tab presents")
        close_notifications(presenter)
        phone = new_page(browser, {"width": 390, "height": 844}, scale=2, touch=True)
        phone.goto(link.split("?", 1)[0])
        phone.wait_for_selector("[role=slider]", state="attached")
        close_notifications(phone)
        following = phone.get_by_text("following", exact=False)
        poll(lambda: following.count() > 0, what="the phone follows")
        # Its classroom box folds to its title line, as on a laptop: the sliders come up the sheet.
        poll(lambda: phone.evaluate(CLASSROOM_FOLDED) == "true", what="the phone's classroom box folded")
        presenter.locator('[role=tab][title="Motion"]').first.click()
        presenter.get_by_role("button", name="Play", exact=True).click()
        # At the climax the motion is slowed down; the phone shows the overlay with the six rates.
        seen: dict[str, dict] = {}

        def climax() -> bool:
            ours = presenter.evaluate(LIVE)
            live = phone.evaluate(LIVE)
            seen["last"] = {"presenter": ours, "phone": live}
            if ours is None or "slowed ×" not in ours["text"]:
                return False
            if live is not None and len(_rates(live["text"])) == 6:
                seen["phone"] = live
                phone.screenshot(path=str(out / "phone_follower_climax.png"))
                presenter.screenshot(path=str(out / "phone_follower_presenter_climax.png"))
                return True
            return False

        try:
            poll(climax, timeout=240, what="the phone shows the rates while the presenter's is slowed")
        except AssertionError as exc:
            raise AssertionError(f"{exc}: last seen {seen.get('last')}") from None
        live = seen["phone"]
        # Beside the arm: in the phone's 3-D view (the upper half), whole on the screen.
        assert 0 <= live["x"] and live["right"] <= 390 and 0 <= live["y"] and live["bottom"] <= 844 / 2 + 1
        assert "κ" in live["text"] and "σ" in live["text"]
        # Once it stops, the phone shows the presenter's very readout and status.
        poll(
            lambda: "stopped" in ((presenter.evaluate(LIVE) or {}).get("text") or ""),
            timeout=240,
            what="the presenter's motion stopped (its readout says so)",
        )
        poll(
            lambda: (
                (p := presenter.evaluate(LIVE)) is not None
                and (f := phone.evaluate(LIVE)) is not None
                and f["text"] == p["text"]
            ),
            what="the phone's overlay reads as the presenter's",
        )
        final = presenter.evaluate(LIVE)["text"]
        assert len(_rates(final)) == 6, final
        poll(lambda: phone.evaluate(STATUS) == presenter.evaluate(STATUS), what="the same status")
        phone.screenshot(path=str(out / "phone_follower_stopped.png"))
        presenter.screenshot(path=str(out / "phone_follower_presenter_stopped.png"))
