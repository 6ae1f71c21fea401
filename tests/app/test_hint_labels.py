"""Issue 28, "labels collide": the 3-D labels keep out of the first hint (``.jl-hint``: what a new tab says to
do first, over the 3-D view until the tab's first change), as they keep out of the motion's readout.

Server level: a real lab whose websocket client has the window's visible view as its canvas and whose page
reported the window opens on the Puma's or the planar arm's first screen (nothing changed: the hint shown),
in a projector's 1280×720 and 1366×768 windows (the latter's column zoomed 1.05), a phone held upright
(390×844) and sideways (844×390), and a tablet (768×1024). The hint's box is estimated from its HTML
(:func:`app.views.panel.hint_box.hint_box`; against Chromium's boxes in test_hint_box.py and
test_browser_hint_labels.py); once the labels were placed for the camera it is what they avoid, and every
shown label's box (through the camera, viser's layout of its text) lies outside it, inside the visible view,
apart from the others: as the tab opens (where no label comes near the hint), and after the user pans the
view (a camera message; the hint stays) so that the label nearest the hint has its anchor under the hint's
middle. On the old code every one of the ten panned screens had labels under the hint (1280×720: the Puma's
q5 at 378..406 × 653..681 px in the hint's 71..713 × 654.5..707; the planar arm's q1 and q2)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from app_helpers import labels_placed, running_lab
from fakes import poll
from test_live_overlay_labels import TOL, apart_from, boxes_through_the_camera

from app.core.actions import SetJoint
from app.core.commands import PageReport
from app.views.camera import View, project
from app.views.panel.hint_box import hint_box
from app.views.panel.live_box import live_box
from app.views.panel.viewport import visible_view_rect
from app.views.scene.labels import label_anchor
from app.views.scene.placement import overlaps
from app.viser_adapter import message_class

WINDOWS = {
    "1280x720": (1280, 720, False),
    "1366x768": (1366, 768, False),
    "390x844": (390, 844, True),
    "844x390": (844, 390, True),
    "768x1024": (768, 1024, True),
}
ROBOTS = ("puma560", "planar2")


def send_camera(ws, window, position, look_at, fov) -> None:
    """The browser's camera message: its pose and its canvas (the window's visible view)."""
    r = visible_view_rect(*window)
    ws.send(
        message_class("ViewerCameraMessage")(
            wxyz=(1.0, 0.0, 0.0, 0.0), position=tuple(map(float, position)), fov=float(fov), near=0.01,
            far=100.0, image_height=int(r.height), image_width=int(r.width),
            look_at=tuple(map(float, look_at)), up_direction=(0.0, 0, 1),
        )
    )  # fmt: skip


def panned(session, window, box) -> tuple[np.ndarray, np.ndarray, str]:
    """A pan of the tab's camera (the camera and its target moved alike, across the line of sight) that
    puts the anchor of the label nearest the hint's box (x0, y0, x1, y1) at the box's centre: the camera's
    position, its target and that label's text."""
    r = visible_view_rect(*window)
    cam = session.client.camera
    view = View(
        np.asarray(cam.position), np.asarray(cam.look_at), np.array([0.0, 0, 1]), cam.fov, r.width / r.height
    )
    shown = [h for h in session.scene.labels.handles if h.visible]
    anchors = np.array([label_anchor(h) for h in shown]).reshape(-1, 3)
    centre = np.array([(box[0] + box[2]) / 2, (box[1] + box[3]) / 2])
    k = int(np.nanargmin(np.hypot(*(project(view, anchors, r.width, r.height) - centre).T)))
    at = project(view, anchors[k : k + 1], r.width, r.height)[0]
    forward = (view.look_at - view.position) / np.linalg.norm(view.look_at - view.position)
    right = np.cross(forward, view.up) / np.linalg.norm(np.cross(forward, view.up))
    up = np.cross(right, forward)
    z = (anchors[k] - view.position) @ forward
    f = r.height / 2 / np.tan(view.fov / 2)  # [px] per unit of tangent (three.js: a vertical fov)
    shift = (-(centre[0] - at[0]) * right + (centre[1] - at[1]) * up) * z / f
    position, look = view.position + shift, view.look_at + shift
    moved = View(position, look, view.up, view.fov, view.aspect)
    assert np.allclose(project(moved, anchors[k : k + 1], r.width, r.height)[0], centre, atol=1e-6)
    return position, look, str(shown[k].text)


def pan(session, ws, window, box) -> str:
    """Pan the camera as a person does in the browser (its camera message; no change of the state, the
    hint stays) by :func:`panned`; the text of the label whose anchor it puts under the hint's centre.
    First the browser's echo of the pose the app framed (a browser sends its camera whenever it changes):
    the app then knows the canvas's shape, and keeps the user's pan (the first camera message of a tab is
    taken as a new canvas, re-framed when something is out of view)."""
    cam = session.client.camera
    position, look, text = panned(session, window, box)
    echo = session.scene.labels.layout
    send_camera(ws, window, cam.position, cam.look_at, cam.fov)  # the browser's echo of the pose set
    poll(lambda: session.scene.labels.layout is not echo, what="the echo taken (labels placed for it)")
    send_camera(ws, window, position, look, cam.fov)
    poll(
        lambda: np.allclose(session.scene.labels.layout.view.position, position, atol=1e-6),
        what="the labels placed for the panned camera",
    )
    return text


def check_apart(session, window, box) -> None:
    """Every shown label's box apart from ``box``, inside the visible view and apart from the others."""
    r = visible_view_rect(*window)
    boxes, texts = boxes_through_the_camera(session, window)
    assert len(texts) >= 2, texts  # the joints' labels at least
    clear = apart_from(boxes, box)
    assert clear.all(), (box, [(t, b) for t, b, ok in zip(texts, boxes, clear, strict=True) if not ok])
    inside = (
        (boxes[:, :2] >= -TOL).all(axis=1) & (boxes[:, 2] <= r.width + TOL) & (boxes[:, 3] <= r.height + TOL)
    )
    assert inside.all(), [(t, b) for t, b, ok in zip(texts, boxes, inside, strict=True) if not ok]
    shrunk = boxes + np.array([TOL, TOL, -TOL, -TOL])
    assert not overlaps(shrunk), [(texts[i], texts[j]) for i, j in overlaps(shrunk)]


def opened(session, window) -> None:
    """The page reports its window, as the browser does once it is drawn."""
    report = {"kind": "view", "width": window[0], "height": window[1], "touch": window[2]}
    session.dispatch(PageReport(json.dumps(report)))
    session.settle()


@pytest.mark.slow
@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize("size", list(WINDOWS))
def test_labels_on_a_new_tab_keep_out_of_the_first_hint(robot, size):
    window = WINDOWS[size]
    r = visible_view_rect(*window)
    with running_lab((int(r.width), int(r.height)), robot=robot) as (_, session, ws):
        opened(session, window)
        assert not session.state.started
        assert session.panel.hint.visible and session.screen.hint == session.panel.hint.content
        est = hint_box(session.panel.hint.content, window)
        assert est is not None
        box = (est.x, est.y, est.x + est.width, est.y + est.height)
        assert box[0] >= 0 and box[1] >= 0 and box[2] <= r.width and box[3] <= window[1]
        labels_placed(session)
        assert live_box(session.screen.live, window) is None  # no motion: the hint alone
        assert session.scene.labels.layout.avoid == (box,)
        check_apart(session, window, box)  # as the tab opens
        text = pan(session, ws, window, box)  # a label's anchor under the hint's middle
        labels_placed(session)
        assert not session.state.started and session.scene.labels.layout.avoid == (box,)
        check_apart(session, window, box)
        assert any(h.text == text for h in session.scene.labels.handles if h.visible), text


def test_the_hint_leaves_the_labels_once_the_tab_changed_something():
    """The first change (a joint moved) takes the hint away, and its box from what the labels avoid."""
    window = WINDOWS["1280x720"]
    r = visible_view_rect(*window)
    with running_lab((int(r.width), int(r.height))) as (_, session, _ws):
        opened(session, window)
        labels_placed(session)
        assert len(session.scene.labels.layout.avoid) == 1
        session.dispatch(SetJoint(0, 0.3))
        session.settle()
        assert session.state.started and session.screen.hint == ""
        labels_placed(session)
        assert session.scene.labels.layout.avoid == ()
