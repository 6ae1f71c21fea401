"""Issue 28, a follower replaying the presenter's scene while the presenter turns the camera, in Chromium: a
laptop the presenter's size (1280×720, English) shows the presenter's very scene messages, labels placed for
that screen. The presenter drags its view round at the Puma's wrist singularity; its labels are placed again
for the new pose, and the laptop is sent those placements. Once both cameras stand still, the laptop's 3-D
view is the presenter's, pixel for pixel but for rendering noise: every label where the presenter's is.
(Before, the laptop's labels stayed where they were placed for the old pose: the lost rotation's label
left hanging off the wrist, another over a joint.) Screenshots: ``$APP_SCREENSHOT_DIR``."""

from __future__ import annotations

import numpy as np
import pytest
from app_helpers import labels_placed
from browser_helpers import close_notifications, new_page, presenting_lab, screenshot_dir, steady_canvas
from fakes import poll

from app.core.actions import GoTo
from app.core.commands import ChooseRobot

pytestmark = [pytest.mark.browser, pytest.mark.slow]

TOKEN = "follower-orbit-7Hq2-wP9d-long-enough"
DIFFERENT = 40  # a pixel differs when a channel differs by more than this (of 255)


def _unlike(a: np.ndarray, b: np.ndarray) -> float:
    """The fraction of pixels of two captures of one size that differ."""
    return float((np.abs(a.astype(int) - b.astype(int)).max(axis=-1) > DIFFERENT).mean())


def test_a_follower_replaying_the_presenters_scene_shows_its_labels_where_the_presenter_does(tmp_path):
    out = screenshot_dir(tmp_path)
    with presenting_lab(TOKEN, "&fixedDpr=1") as (lab, browser, big, presenter):
        laptop = new_page(browser)
        laptop.goto(lab.url + "/?fixedDpr=1")
        laptop.wait_for_selector("[role=slider]")
        poll(lambda: len(lab.sessions) == 2, what="the laptop connected")
        follower = next(s for s in lab.sessions.values() if s is not presenter)
        poll(lambda: follower.role.following, what="the laptop follows")
        close_notifications(laptop)
        presenter.dispatch(ChooseRobot("puma560"))
        presenter.dispatch(GoTo("wrist_singular"))
        poll(lambda: follower.state.configuration == "wrist_singular", what="the laptop there")
        poll(
            lambda: follower.screen.own_scene is None and follower.screen.look() == presenter.screen.look(),
            what="the laptop replays the presenter's scene (the same look)",
        )
        labels_placed(presenter, still=10, interval=0.1)
        before = presenter.scene.labels.boxes.copy()
        big.mouse.move(420, 420)
        big.mouse.down()
        big.mouse.move(300, 380, steps=12)
        big.mouse.up()
        labels_placed(presenter, still=10, interval=0.1)  # stood still a second, labels placed
        after = presenter.scene.labels.boxes
        assert before.shape != after.shape or np.abs(after - before).max() > 20  # the labels moved
        assert follower.screen.own_scene is None  # still replaying

        def alike() -> tuple[float] | None:  # (the share of pixels unlike): 0.0 is an answer
            a, b = steady_canvas(big), steady_canvas(laptop)
            return (_unlike(a, b),) if a.shape == b.shape and _unlike(a, b) < 0.002 else None

        (share,) = poll(alike, what="the laptop's 3-D view the presenter's, labels and all")
        big.screenshot(path=str(out / "orbit_presenter.png"))
        laptop.screenshot(path=str(out / "orbit_follower.png"))
        assert share < 0.002, share
