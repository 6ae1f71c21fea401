"""Issue 28, stumble 4: the sliders do not move during Play as the status under the banner grows (the lost
direction, then the stop), in headless Chromium at 1280×720. On the old code q1's slider stepped
167 → 195 → 215 px as the lines came (measured); now it steps once, at the click on Play (167 → 216), and
then stays."""

from __future__ import annotations

import time

import pytest
from browser_helpers import app_page
from fakes import POLL_TIMEOUT, poll

from app.server import Lab

pytestmark = [pytest.mark.browser, pytest.mark.slow]

_READ = """() => { const s = document.querySelector('[role=slider]').getBoundingClientRect();
  const l = document.querySelector('.jl-lines'); return [s.top, l.children.length]; }"""


def test_the_sliders_stay_put_while_the_status_grows_during_play():
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        page.locator('[role=tab][title="Motion"]').first.click()
        page.get_by_role("button", name="Play", exact=True).click()
        poll(lambda: session.state.playing)
        # The page has drawn the playing status (the lines' height held from then on): the one step,
        # at the click, that remains (see the commit).
        poll(lambda: page.evaluate("document.querySelector('.jl-lines.jl-held') !== null"))
        seen = []
        deadline = time.monotonic() + 10 * POLL_TIMEOUT
        while session.state.playing and time.monotonic() < deadline:
            seen.append(page.evaluate(_READ))
        assert not session.state.playing
        poll(lambda: session.state.stopped != "")
        page.wait_for_timeout(1000)  # the stop's line drawn
        seen.append(page.evaluate(_READ))
        assert len({n for _, n in seen}) >= 2, seen  # the status did grow
        ys = [y for y, _ in seen]
        assert max(ys) - min(ys) <= 1.0, sorted(set(ys))
        assert not errors
