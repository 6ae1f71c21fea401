"""Issue 28 in Chromium: after Play (the Puma's straight line into its wrist singularity) stops, no 3-D label
lies under the motion's readout over the 3-D view (``.jl-live``: rates, κ, σmin and the status's lines),
at 1280×720 and on a phone held upright (390×844, touch, scale 2: Motion tapped in the unfolded views).

Once the camera has stopped and the labels were placed for it, every shown label's box (through the
browser's camera, with viser's layout of its text) is apart from the readout's ``getBoundingClientRect``,
inside the visible view and apart from the others; the server's estimate of the readout's box holds the
measured one. (On the old code the phone's six joint labels and "wrist: lost rotation axis" lay under it.)
Screenshots: ``$APP_SCREENSHOT_DIR``."""

from __future__ import annotations

import numpy as np
import pytest
from app_helpers import labels_placed
from browser_helpers import app_page, screenshot_dir, steady_canvas, whole_in_view
from fakes import poll
from test_live_overlay_labels import apart_from, boxes_through_the_camera

from app.server import Lab
from app.views.panel.live_box import live_box
from app.views.panel.viewport import visible_view_rect
from app.views.scene.placement import overlaps

pytestmark = [pytest.mark.browser, pytest.mark.slow]

SCREENS = {"projector": (1280, 720, False), "phone": (390, 844, True)}
LIVE = """() => { const e = [...document.querySelectorAll('.jl-live')].find((e) => e.getClientRects().length > 0);
  if (!e) return null; const b = e.getBoundingClientRect();
  return {text: e.innerText, html: e.outerHTML, box: [b.left, b.top, b.right, b.bottom]}; }"""


def _play(page, touch: bool) -> None:
    """Open Motion and press Play, as a person does (on a phone: unfold the views, tap)."""
    if touch:
        unfold = page.locator('[aria-label^="Expand panel"]').first
        unfold.scroll_into_view_if_needed()
        unfold.tap()
        motion = page.get_by_role("tab", name="Motion").first
        poll(motion.is_visible, what="the views unfolded")
        motion.tap()
    else:
        page.locator('[role=tab][title="Motion"]').first.click()
    play = page.get_by_role("button", name="Play", exact=True).first
    poll(play.is_visible, what="the Motion view open")
    play.scroll_into_view_if_needed()
    poll(lambda: whole_in_view(page, play), what="Play whole on the screen")
    (play.tap if touch else play.click)()


@pytest.mark.parametrize("screen", list(SCREENS))
def test_no_label_lies_under_the_readout_once_play_stopped(tmp_path, screen):
    out = screenshot_dir(tmp_path)
    width, height, touch = window = SCREENS[screen]
    scale = 2 if touch else 1
    view = {"width": width, "height": height}
    with app_page(Lab(port=0), view, scale=scale, touch=touch, path=f"?fixedDpr={scale}") as (
        page,
        session,
        errors,
    ):
        poll(lambda: session.page.window == window, what="the page reported its window")
        _play(page, touch)
        poll(lambda: session.state.playing, what="the motion plays")
        poll(lambda: not session.state.playing and session.state.stopped, what="the motion stopped")
        live = poll(
            lambda: (
                (m := page.evaluate(LIVE)) is not None
                and "stopped" in m["text"]
                and "jl-live-lines" in m["html"]
                and m
            ),
            what="the readout says it stopped, with the status's lines",
        )
        labels_placed(session, still=10, interval=0.1)  # the camera stood still for a second
        steady_canvas(page)
        labels_placed(session, still=10, interval=0.1)
        live = page.evaluate(LIVE)
        measured = np.array(live["box"])
        est = live_box(live["html"], window)
        assert est is not None
        x0, y0, x1, y1 = est.x, est.y, est.x + est.width, est.y + est.height
        assert abs(x0 - measured[0]) < 0.5 and abs(y0 - measured[1]) < 0.5 and abs(x1 - measured[2]) < 0.5
        assert measured[3] - 0.5 <= y1 <= measured[3] + 13 * 1.35 + 3  # holds it, a line at most taller
        boxes, texts = boxes_through_the_camera(session, window)
        assert any("lost" in t for t in texts), texts
        clear = apart_from(boxes, tuple(measured))
        assert clear.all(), (
            measured,
            [(t, b) for t, b, ok in zip(texts, boxes, clear, strict=True) if not ok],
        )
        r = visible_view_rect(*window)
        inside = (
            (boxes[:, :2] >= -1e-6).all(axis=1)
            & (boxes[:, 2] <= r.width + 1e-6)
            & (boxes[:, 3] <= r.height + 1e-6)
        )
        assert inside.all(), [(t, b) for t, b, ok in zip(texts, boxes, inside, strict=True) if not ok]
        shrunk = boxes + np.array([1e-6, 1e-6, -1e-6, -1e-6])
        assert not overlaps(shrunk), [(texts[i], texts[j]) for i, j in overlaps(shrunk)]
        page.screenshot(path=str(out / f"labels_clear_of_readout_{screen}.png"))
        assert not errors, errors
