"""The picture of a singularity in Chromium at 1280×720: at named singular configurations of the library
robots the camera ends across every lost direction, the lost direction is on screen in its colour with
its label, and the words agree with the decoupling (one page, several configurations)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from app_helpers import scene_node
from browser_helpers import app_page, steady_canvas
from fakes import poll

from app.core.actions import GoTo
from app.core.commands import ChooseRobot
from app.server import Lab
from app.views.camera import lost_axes
from app.views.scene.overlays import MAX_LOSSES

pytestmark = pytest.mark.browser

VISITS = (
    ("puma560", "wrist_singular", "Wrist singular", "wrist: lost rotation axis"),
    ("puma560", "shoulder_singular", "Arm singular", "arm: lost translation (wrist centre)"),
    ("iiwa14", "candle", "Arm singular", "wrist: lost rotation axis"),
    ("planar2", "stretched", "Lost</b>: translation", "lost translation"),
)


def _view_angles(session, axes: np.ndarray) -> np.ndarray:
    cam = session.client.camera
    d = np.asarray(cam.position, float) - np.asarray(cam.look_at, float)
    d /= np.linalg.norm(d)
    return np.degrees(np.arccos(np.clip(np.abs(axes @ d), 0.0, 1.0)))


def _project(session, shape, point) -> tuple[float, float]:
    """Pixel (x, y) of a 3-D point in the browser's camera (pinhole, vertical fov)."""
    cam = session.client.camera
    pos, look = np.asarray(cam.position, float), np.asarray(cam.look_at, float)
    f = (look - pos) / np.linalg.norm(look - pos)
    r = np.cross(f, [0.0, 0.0, 1.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    d = np.asarray(point, float) - pos
    t = np.tan(float(cam.fov) / 2)
    h, w = shape[:2]
    x = (d @ r) / (d @ f) / (t * w / h)
    y = (d @ u) / (d @ f) / t
    return (x + 1) / 2 * w, (1 - y) / 2 * h


def _drawn_segments(session) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every lost translation arrow (start, end) and every lost rotation axis (its first segment)."""
    out = []
    arrows = scene_node(session, "/lab/jacobian/lost_translation")
    if arrows.visible:
        out += [(a, b) for a, b in np.asarray(arrows.points, float)]
    axis = scene_node(session, "/lab/jacobian/lost_rotation")
    if axis.visible:
        out.append(tuple(np.asarray(axis.points, float)[0]))
    return out


def test_named_singularities_are_drawn_across_the_view_with_the_course_words(tmp_path):
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    with app_page(Lab(port=0)) as (page, session, errors):
        for robot, conf, words, label in VISITS:
            session.dispatch(ChooseRobot(robot))
            session.settle()
            session.dispatch(GoTo(conf))
            session.settle()
            poll(lambda conf=conf: session.state.configuration == conf)
            snap = session.snapshot
            axes = lost_axes(snap.losses)
            # The camera glides until every lost direction lies across the view (≥ 45° from it).
            poll(lambda axes=axes: _view_angles(session, axes).min() >= 45.0)
            # (after a robot switch the canvas may be laid out again: wait for it to have a size)
            poll(lambda: (page.locator("canvas").first.bounding_box() or {"width": 0})["width"] > 100)
            pixels = steady_canvas(page)
            # The words: the panel says the same story as the snapshot's losses.
            status = session.panel.status.content
            assert words in status, status
            page_text = page.locator(".jl-status").first.locator("xpath=..").inner_text()
            assert words.replace("</b>", "") in page_text.replace("\n", " ")
            # Each lost direction is on screen in its dark crimson (shaded: red without green) where the
            # camera projects it, drawn long (across the view), with its label shown.
            crimson = (pixels[..., 0] - pixels[..., 1] > 60) & (pixels[..., 1] < 90)
            for a, b in _drawn_segments(session):
                (xa, ya), (xb, yb) = _project(session, pixels.shape, a), _project(session, pixels.shape, b)
                assert np.hypot(xb - xa, yb - ya) > 25, f"{robot} {conf}: seen end-on"
                seen = []  # along the outer part (the inner end of an axis is in the wrist)
                for t in (0.6, 0.7, 0.8, 0.9):
                    x, y = int(xa + t * (xb - xa)), int(ya + t * (yb - ya))
                    seen.append(int(crimson[max(y - 8, 0) : y + 9, max(x - 8, 0) : x + 9].sum()))
                assert max(seen) >= 5, f"{robot} {conf}: no lost-direction pixels near ({x}, {y})"
            shown = [scene_node(session, f"/lab/jacobian/lost_label_{i}") for i in range(MAX_LOSSES)]
            assert label in [x.text for x in shown if x.visible]
            page.screenshot(path=str(out_dir / f"singularity_{robot}_{conf}.png"))
        assert errors == []
