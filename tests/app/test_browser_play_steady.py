"""Issue 28, stumble 4: nothing in the panel moves under the pointer from the click on Play to the stop, in
headless Chromium at 1280×720. On the old code q1's slider stepped 167 → 195 → 215 px as the status's
lines came (the lost direction, then the stop); then once, at the click (195 → 244 px, the Play button
with it). Now the lines of a motion on screen are beside its rates over the 3-D view, and the block under
the banner keeps the height it had at the click."""

from __future__ import annotations

import time

import pytest
from browser_helpers import app_page
from fakes import POLL_TIMEOUT, poll

from app.server import Lab

pytestmark = [pytest.mark.browser, pytest.mark.slow]

_READ = """() => { const s = document.querySelector('[role=slider]').getBoundingClientRect();
  const l = document.querySelector('.jl-live-lines'); return [s.top, l ? l.children.length : 0]; }"""


def test_the_sliders_stay_put_while_the_status_grows_during_play():
    lab = Lab(port=0)
    with app_page(lab) as (page, session, errors):
        page.locator('[role=tab][title="Motion"]').first.click()
        play = page.get_by_role("button", name="Play", exact=True)
        poll(lambda: play.is_visible() and "home" in page.locator(".jl-lines").first.inner_text())
        before = page.evaluate(_READ)[0]
        play_top = play.bounding_box()["y"]
        play.click()
        poll(lambda: session.state.playing)
        poll(lambda: page.evaluate("document.querySelector('.jl-lines.jl-held') !== null"))
        seen = [[before, 0]]
        deadline = time.monotonic() + 10 * POLL_TIMEOUT
        while session.state.playing and time.monotonic() < deadline:
            seen.append(page.evaluate(_READ))
        assert not session.state.playing
        poll(lambda: session.state.stopped != "")
        live = page.locator(".jl-live").first
        poll(lambda: "Critical point" in live.inner_text(), what="the stop's line, beside the rates")
        seen.append(page.evaluate(_READ))
        assert len({n for _, n in seen}) >= 2, seen  # the status did grow
        ys = [y for y, _ in seen]
        assert max(ys) - min(ys) <= 1.0, sorted(set(ys))
        assert abs(play.bounding_box()["y"] - play_top) <= 1.0  # the button clicked stayed under the pointer
        assert not errors
