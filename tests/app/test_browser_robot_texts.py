"""A robot's configuration text in Polish and Portuguese, which run longer than English, is shown whole in
the panel at 1280×720 and at a phone's 390×844 in Chromium (issue 27). The line under the status keeps
two lines (so the sliders never move, f68bd56) with the whole text as its tooltip; a click shows it all:
then nothing is cut off or clipped, and it lies within the window's width."""

from __future__ import annotations

from pathlib import Path

import pytest
from browser_helpers import app_page
from fakes import FakeSymbolicService, poll

import robots
from app.core.actions import GoTo
from app.server import Lab

SHOTS = Path("/work/notes/shots/s27/trobots")

# The text's element and every ancestor up to the panel: none may clip it (overflow hidden with content
# wider or taller than its box), and the text's box lies within the window's width.
_CLIPPED = """(needle) => {
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    if (!n.textContent.includes(needle)) continue;
    const range = document.createRange(); range.selectNodeContents(n);
    const box = range.getBoundingClientRect();
    const out = {found: true, right: box.right, width: innerWidth, clipped: []};
    for (let e = n.parentElement; e && e !== document.body; e = e.parentElement) {
      const s = getComputedStyle(e);
      const hides = (v) => v === "hidden" || v === "clip";
      if ((hides(s.overflowX) && e.scrollWidth > e.clientWidth + 1) ||
          (hides(s.overflowY) && e.scrollHeight > e.clientHeight + 1) || s.textOverflow === "ellipsis")
        out.clipped.push(e.tagName + "." + (e.className || "").toString().slice(0, 30));
    }
    return out;
  }
  return {found: false};
}"""


@pytest.mark.browser
@pytest.mark.slow
@pytest.mark.parametrize("code", ["pl", "pt"])
@pytest.mark.parametrize("viewport", [(1280, 720), (390, 844)], ids=["1280x720", "390x844"])
def test_a_configuration_text_in_a_long_language_is_shown_whole(code, viewport):
    puma = robots.load("puma560")
    text = next(c for c in puma.configurations if c.name == "elbow_singular").translations[code][
        "description"
    ]
    lab = Lab(robot="puma560", port=0, language=code, symbolic=FakeSymbolicService())
    with app_page(lab, {"width": viewport[0], "height": viewport[1]}) as (page, session, errors):
        assert session.language == code
        session.dispatch(GoTo("elbow_singular"))
        session.settle()
        end = text[-30:]  # the text's last words: shown only if the whole text is
        poll(lambda: page.evaluate(_CLIPPED, end)["found"])
        label = page.locator("label.jl-desc")
        assert text in label.get_attribute("title")  # the whole text, in the tab's language
        label.click()

        def unclamped() -> dict | None:
            seen = page.evaluate(_CLIPPED, end)
            return seen if not seen["clipped"] else None

        seen = poll(unclamped, what="the whole text, unclamped")
        page.screenshot(path=str(SHOTS / f"panel_puma_elbow_{code}_{viewport[0]}x{viewport[1]}.png"))
        assert seen["right"] <= seen["width"] + 0.5, seen
        assert errors == []
