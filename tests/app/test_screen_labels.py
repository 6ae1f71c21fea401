"""Issue 28, stumble 2, in the app: the tab's 3-D labels placed on its screen at every named configuration
of every robot and at every Derive step, on a projector (1280×720) and on a phone held upright (390×844,
touch: the canvas is the upper half, above the sheet).

Each tab is a real lab with a websocket client whose canvas has that size and whose page reports its
window (as the page script does). Once the camera the app chose has stopped and the labels were placed
for it, every shown label's box is worked out here from its 3-D position, through that camera
(:func:`app.views.camera.project`), with viser's layout of its text (:func:`label_box`): no two boxes
overlap and every box lies inside the part of the canvas the panel leaves visible
(:func:`app.views.panel.viewport.visible_view_rect`)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from app_helpers import derive_walk, labels_placed, running_lab
from fakes import poll

import robots
from app.core.actions import GoTo
from app.core.commands import ChooseRobot, PageReport
from app.views.camera import View, project
from app.views.methods import METHODS
from app.views.panel.viewport import visible_view_rect
from app.views.scene.labels import LEADER_PX, label_anchor, label_box
from app.views.scene.placement import overlaps
from app.viser_adapter import message_class

SCREENS = {"projector": (1280, 720, False), "phone": (390, 844, True)}
TOL = 1e-6  # [px]: the lift back to 3-D and the projection agree to round-off


@pytest.fixture(scope="module", params=list(SCREENS))
def tab(request):
    width, height, touch = SCREENS[request.param]
    r = visible_view_rect(width, height, touch)  # the canvas: beside the docked panel, above the sheet
    with running_lab((int(r.width), int(r.height))) as (_, session, _ws):
        report = {"kind": "view", "width": width, "height": height, "touch": touch}
        session.dispatch(PageReport(json.dumps(report)))
        session.settle()
        session.screen_size = (width, height, touch)
        session.ws = _ws
        yield session


def settled_boxes(session) -> tuple[np.ndarray, list[str]]:
    """The shown labels' boxes [px] through the tab's camera once it has stopped and they were placed
    for it; their texts."""
    labels_placed(session)
    cam = session.client.camera
    r = visible_view_rect(*session.screen_size)
    cw, ch = r.width, r.height
    view = View(np.asarray(cam.position), np.asarray(cam.look_at), np.array([0.0, 0, 1]), cam.fov, cw / ch)
    shown = [h for h in session.scene.labels.handles if h.visible]
    at = project(view, np.array([h.position for h in shown]).reshape(-1, 3), cw, ch)
    boxes = np.array([label_box(h, p) for h, p in zip(shown, at, strict=True)]).reshape(-1, 4)
    check_leaders(session, view, shown, boxes, cw, ch, [h.text for h in shown])
    return boxes, [h.text for h in shown]


def check_leaders(session, view: View, shown: list, boxes: np.ndarray, cw: float, ch: float, what) -> None:
    """A label whose box ends more than LEADER_PX from its anchor has a leader line from its box to it."""
    anchors = np.array([label_anchor(h) for h in shown]).reshape(-1, 3)
    at = project(view, anchors, cw, ch)
    gap = np.hypot(*(np.clip(at, boxes[:, :2], boxes[:, 2:]) - at).T)
    far = np.flatnonzero(gap > LEADER_PX + 1e-6)
    leaders = session.scene.labels.leaders
    assert leaders.visible == bool(len(far)), what
    segments = np.asarray(leaders.points, float)
    for k in far:
        ends = np.flatnonzero(np.linalg.norm(segments[:, 1] - anchors[k], axis=1) < 1e-5)
        assert len(ends), (what, shown[k].text)
        starts = project(view, segments[ends, 0], cw, ch)
        on_box = (starts >= boxes[k, :2] - 0.01).all(axis=1) & (starts <= boxes[k, 2:] + 0.01).all(axis=1)
        assert on_box.any(), (what, shown[k].text, starts, boxes[k])


def check(session, what) -> None:
    boxes, texts = settled_boxes(session)
    assert len(boxes), what
    r = visible_view_rect(*session.screen_size)  # the canvas, from its top-left corner
    inside = (
        (boxes[:, 0] >= -TOL)
        & (boxes[:, 1] >= -TOL)
        & (boxes[:, 2] <= r.width + TOL)
        & (boxes[:, 3] <= r.height + TOL)
    )
    assert inside.all(), (what, [(t, b) for t, b, ok in zip(texts, boxes, inside, strict=True) if not ok], r)
    shrunk = boxes + np.array([TOL, TOL, -TOL, -TOL])
    assert not overlaps(shrunk), (what, [(texts[i], texts[j]) for i, j in overlaps(shrunk)])


@pytest.mark.slow
@pytest.mark.parametrize("robot_name", robots.names())
def test_labels_apart_and_in_view_at_every_named_configuration(tab, robot_name):
    tab.dispatch(ChooseRobot(robot_name))
    tab.settle()
    for conf in robots.load(robot_name).configurations:
        tab.dispatch(GoTo(conf.name))
        tab.settle()
        check(tab, (robot_name, conf.name))


@pytest.mark.slow
@pytest.mark.parametrize("method", [m for m in METHODS if m])
@pytest.mark.parametrize("robot_name", robots.names())
def test_labels_apart_and_in_view_at_every_derive_step(tab, robot_name, method):
    tab.dispatch(ChooseRobot(robot_name))
    tab.settle()
    for step in range(tab.state.robot.dof):
        derive_walk(tab, method, step)
        check(tab, (robot_name, method, step))


@pytest.mark.slow
def test_labels_placed_again_when_the_user_turns_the_camera(tab):
    """An orbit in the browser (its camera message, no redraw): the labels are placed again for it."""
    tab.dispatch(ChooseRobot("puma560"))
    tab.dispatch(GoTo("wrist_singular"))
    tab.settle()
    check(tab, "before the turn")
    cam = tab.client.camera
    look, start = np.asarray(cam.look_at, float), np.asarray(cam.position, float)
    c, s = np.cos(np.radians(120)), np.sin(np.radians(120))
    turned = look + np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ (start - look)  # 120° about the vertical
    r = visible_view_rect(*tab.screen_size)
    tab.ws.send(
        message_class("ViewerCameraMessage")(
            wxyz=(1.0, 0.0, 0.0, 0.0), position=tuple(turned), fov=float(cam.fov), near=0.01, far=100.0,
            image_height=int(r.height), image_width=int(r.width), look_at=tuple(look), up_direction=(0.0, 0, 1),
        )
    )  # fmt: skip
    placed = tab.scene.labels
    poll(lambda: np.allclose(placed.layout.view.position, turned, atol=1e-6), what="the labels placed again")
    check(tab, "after the turn")
