"""Issue 28, stumble 2, the pure part: labels placed in screen space (app.views.scene.placement) at
every named configuration of every robot and every Derive step, at 1280×720 and at a phone's 390×844:
no two boxes overlap and every box lies inside the visible view. The camera is the one the app frames
with (facing the arm, the points fitted); the anchors are the joints' origins and the step's labels.
The 3-D label put back at its anchor's depth projects onto its placed spot."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import robots
from app.core.actions import GoTo
from app.core.i18n import translations
from app.core.reducer import reduce
from app.core.snapshot import compute
from app.core.state import LabState
from app.views.camera import View, facing, framing, project
from app.views.methods import METHODS
from app.views.scene.placement import label_size, lift, overlaps, place, visible_rect, wrap

SCREENS = [(1280, 720), (390, 844)]
FONT = 17.0  # px: LABEL_SCALE 1.6 of viser's ~11 px
FOV = 1.3


def _camera(points: np.ndarray, width: int, height: int) -> View:
    start = View(np.array([1.3, -1.5, 0.9]), np.zeros(3), np.array([0.0, 0, 1]), FOV, width / height)
    position, look_at = framing(start, points, facing(points), pad=0.1)
    return View(position, look_at, np.array([0.0, 0, 1]), FOV, width / height)


def _check(anchors3: np.ndarray, texts: list[str], width: int, height: int, what) -> None:
    view = _camera(anchors3, width, height)
    rect = visible_rect(width, height)
    texts = [wrap(t, FONT, 0.9 * (rect[2] - rect[0])) for t in texts]  # a phone's view is narrow
    anchors = project(view, anchors3, width, height)
    sizes = np.array([label_size(t, FONT) for t in texts])
    boxes = place(anchors, sizes, rect)
    assert not overlaps(boxes), (what, overlaps(boxes))
    x0, y0, x1, y1 = rect
    assert (boxes[:, 0] >= x0 - 1e-9).all() and (boxes[:, 2] <= x1 + 1e-9).all(), what
    assert (boxes[:, 1] >= y0 - 1e-9).all() and (boxes[:, 3] <= y1 + 1e-9).all(), what
    np.testing.assert_allclose(boxes[:, 2:] - boxes[:, :2], sizes)  # the box is the label's size


def _configurations():
    return [
        pytest.param(name, conf.name, id=f"{name}-{conf.name}")
        for name in robots.names()
        for conf in robots.load(name).configurations
    ]


@pytest.mark.parametrize(("screen"), SCREENS, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize(("robot_name", "conf_name"), _configurations())
def test_joint_and_lost_labels_placed_apart_and_inside(robot_name, conf_name, screen):
    robot = robots.load(robot_name)
    state = reduce(LabState.initial(robot_name, robot), GoTo(conf_name))
    snap = compute(state)
    origins = snap.link_frames[:-1, :3, 3]
    texts = [f"q{j + 1}" for j in range(len(origins))]
    tr = translations("es")  # the longest words of the four languages
    words = {"arm": "arm: lost translation (wrist centre)", "wrist": "wrist: lost rotation axis"}
    for loss in snap.losses[:3]:
        texts.append(tr.gettext(words.get(loss.part, "lost translation")).replace(": ", ":\n", 1))
        origins = np.vstack([origins, loss.point])
    _check(origins, texts, *screen, (robot_name, conf_name))


def _steps():
    return [
        pytest.param(name, method, id=f"{name}-{method}")
        for name in robots.names()
        for method in METHODS
        if method
    ]


@pytest.mark.parametrize(("screen"), SCREENS, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize(("robot_name", "method"), _steps())
def test_every_derive_steps_labels_placed_apart_and_inside(robot_name, method, screen):
    robot = robots.load(robot_name)
    base = LabState.initial(robot_name, robot)
    tr = translations()
    for step in range(robot.dof):
        options = dataclasses.replace(base.options, derive=method, derive_step=step)
        state = dataclasses.replace(base, options=options)
        snap = compute(state)
        _, _, _, labels = METHODS[method].draw(robot, snap.derive, snap, 0.2, 0.5, tr)
        origins = snap.link_frames[:-1, :3, 3]
        anchors = np.vstack([origins, *[np.asarray(p, float) for _, p in labels]]) if labels else origins
        texts = [f"q{j + 1}" for j in range(len(origins))] + [t for t, _ in labels]
        _check(anchors, texts, *screen, (robot_name, method, step))


def test_a_placed_label_lifted_back_projects_onto_its_spot():
    view = View(np.array([2.0, -2.0, 1.5]), np.zeros(3), np.array([0.0, 0, 1]), FOV, 16 / 9)
    anchor = np.array([0.2, 0.1, 0.4])
    spot = np.array([700.0, 200.0])
    point = lift(view, spot, anchor, 1280, 720)
    np.testing.assert_allclose(project(view, point[None], 1280, 720)[0], spot, atol=1e-6)
    forward = view.look_at - view.position
    forward /= np.linalg.norm(forward)
    assert (point - view.position) @ forward == pytest.approx((anchor - view.position) @ forward)


def test_crowded_anchors_on_one_point_are_spread_apart():
    anchors = np.full((6, 2), 300.0)
    sizes = np.array([label_size(f"label {k}", FONT) for k in range(6)])
    assert len(overlaps(np.column_stack([anchors, anchors + sizes]))) == 15  # unplaced: all on one another
    boxes = place(anchors, sizes, visible_rect(1280, 720))
    assert not overlaps(boxes)
    centres = (boxes[:, :2] + boxes[:, 2:]) / 2
    assert np.linalg.norm(centres - 300.0, axis=1).max() < 200  # still near their anchor


def test_labels_keep_out_of_an_occupied_box():
    """Labels anchored under a box the page draws over the view (the motion's readout, 8..382 × 8..209 px
    on a phone) are placed outside it, apart, inside the view; without it they stay at their anchors."""
    anchors = np.array([[100.0, 160.0], [140.0, 170.0], [200.0, 150.0], [390.0 - 30, 120.0]])
    sizes = np.array([[27.2, 27.6]] * 4)
    rect = (0.0, 0.0, 390.0, 422.0)
    readout = (8.0, 8.0, 382.0, 209.0)
    free = place(anchors, sizes, rect)
    assert np.allclose(free[:, [0, 3]], anchors)  # nothing in the way: each at its anchor
    boxes = place(anchors, sizes, rect, occupied=np.array([readout]))
    x0, y0, x1, y1 = readout
    clear = (boxes[:, 2] <= x0) | (boxes[:, 0] >= x1) | (boxes[:, 3] <= y0) | (boxes[:, 1] >= y1)
    assert clear.all(), boxes
    assert not overlaps(boxes) and (boxes[:, :2] >= 0).all() and (boxes[:, 2:] <= (390, 422)).all()
    assert (boxes[:, 1] - y1 < 3 * 27.6).all(), boxes  # just below it, near their anchors
