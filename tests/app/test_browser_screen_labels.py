"""Issue 28, stumble 2, in Chromium at 1280×720: the five moments where labels collided ("lost rq6tation"
at the climax, the UR5's "lost translatio(q6)", Whitney step 1's "arm: lost translation" over
"z₀ × (pₙ − p₀)", step 3's "z₂" on "q4", the Puma's "elbow singular" label cut by the panel).

At each, once the camera has stopped and the labels were placed for it: every shown label's box
(through the browser's camera, with viser's layout of its text) is apart from the others and inside
the part of the canvas the panel leaves visible; and each label's drawn pixels (the difference of the
canvas with the label shown and hidden) lie inside the box the server worked out for it and fill most of
its width (the font's measured metrics hold in the real browser). Screenshots: APP_SCREENSHOT_DIR."""

from __future__ import annotations

import os
from functools import partial
from pathlib import Path

import numpy as np
import pytest
from app_helpers import derive_walk, labels_placed
from browser_helpers import app_page, canvas_box, steady_canvas
from fakes import poll

from app.core.actions import GoTo
from app.core.commands import ChooseRobot, OpenTab
from app.server import Lab
from app.views.camera import View, project
from app.views.panel import TAB_LABELS
from app.views.panel.viewport import visible_view_rect
from app.views.scene.labels import label_box
from app.views.scene.placement import overlaps

pytestmark = pytest.mark.browser

MOMENTS = (
    ("climax", "puma560", "wrist_singular", "", 0),
    ("ur5_elbow", "ur5", "elbow_singular", "", 0),
    ("whitney_step1", "puma560", "shoulder_singular", "whitney", 0),
    ("whitney_step3", "puma560", "home", "whitney", 2),
    ("puma_elbow", "puma560", "elbow_singular", "", 0),
)
WIDTH, HEIGHT = 1280, 720
CANVAS = visible_view_rect(WIDTH, HEIGHT)
"""The 3-D view's canvas: beside the docked panel (876×720)."""


def _placed(session) -> None:
    """Wait until the camera has stood still for a second (the browser's own camera messages too) and the
    labels were placed for it."""
    labels_placed(session, still=10, interval=0.1)


def _boxes(session, canvas=CANVAS) -> tuple[list, np.ndarray]:
    cam = session.client.camera
    view = View(np.asarray(cam.position), np.asarray(cam.look_at), np.array([0.0, 0, 1]), cam.fov, cam.aspect)
    shown = [h for h in session.scene.labels.handles if h.visible]
    points = np.array([h.position for h in shown]).reshape(-1, 3)
    at = project(view, points, canvas.width, canvas.height)
    return shown, np.array([label_box(h, p) for h, p in zip(shown, at, strict=True)]).reshape(-1, 4)


def _ink(with_label: np.ndarray, without: np.ndarray, near: np.ndarray | None = None) -> np.ndarray | None:
    """The bounding box (x0, y0, x1, y1) [px] of what the label changed on the canvas (``near``: only
    within 40 px of that box)."""
    changed = np.abs(with_label - without).max(axis=-1) > 40
    if near is not None:
        x0, y0 = np.maximum(np.floor(near[:2]).astype(int) - 40, 0)
        x1, y1 = np.ceil(near[2:]).astype(int) + 40
        around = np.zeros_like(changed)
        around[y0:y1, x0:x1] = True
        changed &= around
    ys, xs = np.nonzero(changed)
    if not len(xs):
        return None
    return np.array([xs.min(), ys.min(), xs.max() + 1, ys.max() + 1], float)


def _changed(page, before: np.ndarray) -> np.ndarray | None:
    """The settled canvas once it differs from ``before`` (None until then)."""
    now = steady_canvas(page)
    return now if _ink(now, before) is not None else None


def test_the_five_moments_have_their_labels_apart_in_view_and_sized_as_drawn(tmp_path):
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    with app_page(Lab(port=0), path="?fixedDpr=1") as (page, session, errors):  # no adaptive re-render
        poll(lambda: session.page.window == (WIDTH, HEIGHT, False), what="the page reported its window")
        assert canvas_box(page) == {"x": 0, "y": 0, "width": CANVAS.width, "height": CANVAS.height}
        for name, robot, conf, method, step in MOMENTS:
            session.dispatch(ChooseRobot(robot))
            session.settle()
            session.dispatch(GoTo(conf))
            session.settle()
            session.dispatch(OpenTab("Derive" if method else TAB_LABELS[0]))
            if method:
                derive_walk(session, method, step)
                poll(lambda: session.page.tab == "Derive", what="the Derive tab open")
            _placed(session)
            steady_canvas(page)
            _placed(session)
            shown, boxes = _boxes(session)
            texts = [h.text for h in shown]
            if method:
                assert any("z" in t and "₀" in t or "z₂" in t for t in texts), (name, texts)
            else:
                assert any("lost" in t for t in texts), (name, texts)
            shrunk = boxes + np.array([1e-6, 1e-6, -1e-6, -1e-6])
            assert not overlaps(shrunk), (name, [(texts[i], texts[j]) for i, j in overlaps(shrunk)])
            assert (boxes[:, :2] >= -1e-6).all(), (name, texts, boxes)
            assert (boxes[:, 2] <= CANVAS.width + 1e-6).all() and (boxes[:, 3] <= CANVAS.height + 1e-6).all()
            shown_canvas = steady_canvas(page)
            page.screenshot(path=str(out_dir / f"labels_{name}_1280.png"))
            # Each label as drawn: the canvas with it hidden, then shown again, compared.
            for handle, box in zip(shown, boxes, strict=True):
                if name != "climax" and any(handle is j for j in session.scene.arm.labels):
                    continue  # the joints' labels measured once, at the climax (a browser test is slow)
                handle.visible = False
                hidden = poll(partial(_changed, page, shown_canvas), what=f"{handle.text} hidden")
                handle.visible = True
                shown_canvas = poll(partial(_changed, page, hidden), what=f"{handle.text} shown again")
                ink = _ink(shown_canvas, hidden, box)
                assert ink is not None
                # inside its box (a pixel of antialiasing either way), and as wide as the box's text
                assert (ink[:2] >= box[:2] - 2).all() and (ink[2:] <= box[2:] + 2).all(), (
                    handle.text,
                    ink,
                    box,
                )
                assert ink[2] - ink[0] >= 0.75 * (box[2] - box[0]), (handle.text, ink, box)
        assert not errors, errors


def test_the_climax_on_a_phone_has_its_labels_apart_above_the_sheet(tmp_path):
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    phone = {"width": 390, "height": 844}
    with app_page(Lab(port=0), viewport=phone, touch=True, path="?fixedDpr=1") as (page, session, errors):
        poll(lambda: session.page.window == (390, 844, True), what="the phone reported its window")
        canvas = visible_view_rect(390, 844, touch=True)
        assert canvas_box(page) == {"x": 0, "y": 0, "width": canvas.width, "height": canvas.height}
        session.dispatch(ChooseRobot("puma560"))
        session.dispatch(GoTo("wrist_singular"))
        session.settle()
        _placed(session)
        shown, boxes = _boxes(session, canvas)
        texts = [h.text for h in shown]
        assert any("lost" in t for t in texts), texts
        shrunk = boxes + np.array([1e-6, 1e-6, -1e-6, -1e-6])
        assert not overlaps(shrunk), [(texts[i], texts[j]) for i, j in overlaps(shrunk)]
        assert (boxes[:, :2] >= -1e-6).all(), (texts, boxes)
        assert (boxes[:, 2] <= canvas.width + 1e-6).all() and (boxes[:, 3] <= canvas.height + 1e-6).all()
        steady_canvas(page)
        page.screenshot(path=str(out_dir / "labels_climax_phone_390.png"))
        assert not errors, errors
