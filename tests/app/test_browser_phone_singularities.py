"""Issue 28, the named singularities on a phone (390×844 held upright and 844×390 sideways; touch, mobile,
scale 2): the Puma's wrist, elbow and shoulder singularities and the UR5's shoulder and wrist ones. At
each, the camera ends across the lost directions, the status says the course's words, and the lost
direction's dark crimson is on screen in the part of the 3-D view the panel leaves
(:func:`app.views.panel.viewport.visible_view_rect`). Screenshots go to ``$APP_SCREENSHOT_DIR`` (default:
pytest's temporary directory), one per orientation and configuration."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import app_page, steady_canvas
from fakes import poll

from app.core.actions import GoTo
from app.core.commands import ChooseRobot
from app.server import Lab
from app.views.camera import lost_axes
from app.views.panel.viewport import visible_view_rect

pytestmark = [pytest.mark.browser, pytest.mark.slow]

VISITS = (
    ("puma560", "wrist_singular", "singular: wrist"),
    ("puma560", "elbow_singular", "singular: elbow"),
    ("puma560", "shoulder_singular", "singular: shoulder"),
    ("ur5", "shoulder_singular", "singular: shoulder"),
    ("ur5", "wrist_singular", "singular: wrist"),
)
SIZES = {"upright": (390, 844), "sideways": (844, 390)}


def _view_angles(session, axes: np.ndarray) -> np.ndarray:
    cam = session.client.camera
    d = np.asarray(cam.position, float) - np.asarray(cam.look_at, float)
    d /= np.linalg.norm(d)
    return np.degrees(np.arccos(np.clip(np.abs(axes @ d), 0.0, 1.0)))


@pytest.mark.parametrize("held", list(SIZES))
def test_named_singularities_on_a_phone_show_the_lost_direction_where_it_is_seen(tmp_path, held):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    width, height = SIZES[held]
    seen = visible_view_rect(width, height, touch=True)
    viewport = {"width": width, "height": height}
    with app_page(Lab(port=0), viewport, scale=2, touch=True) as (page, session, errors):
        for robot, conf, words in VISITS:
            if session.state.robot_name != robot:
                session.dispatch(ChooseRobot(robot))
                session.settle()
            session.dispatch(GoTo(conf))
            session.settle()
            poll(lambda conf=conf: session.state.configuration == conf)
            axes = lost_axes(session.snapshot.losses)
            poll(lambda axes=axes: _view_angles(session, axes).min() >= 45.0, what=f"{robot} {conf} across")
            poll(lambda: (page.locator("canvas").first.bounding_box() or {"width": 0})["width"] > 100)
            poll(lambda words=words: words in page.locator(".jl-status").first.inner_text(), what=words)
            pixels = steady_canvas(page)
            box = page.locator("canvas").first.bounding_box()
            assert box is not None
            k = pixels.shape[1] / box["width"]  # device pixels per CSS pixel
            # The part of the canvas that is not under the panel (the canvas starts at the window's corner).
            x1 = int(k * (seen.x + seen.width - box["x"]))
            y1 = int(k * (seen.y + seen.height - box["y"]))
            visible = pixels[: max(y1, 0), : max(x1, 0)]
            crimson = (visible[..., 0] - visible[..., 1] > 60) & (visible[..., 1] < 90)
            page.screenshot(path=str(out / f"phone_{held}_{robot}_{conf}.png"))
            assert crimson.sum() >= 4 * k * k * 25, f"{robot} {conf} {held}: {crimson.sum()} crimson pixels"
        assert not errors
