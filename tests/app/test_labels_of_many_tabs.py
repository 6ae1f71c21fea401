"""Issue 28 (and 32), labels of many tabs: a presenter's label placements reach a follower that replays its
scene in the order they were made, also when the follower has not yet drawn the state they were placed in
(it lags): the placement is then queued after that state's drawing, its messages replayed right after the
drawing's own (a placement's messages only hold the labels that moved, measured against the presenter's
previous positions: replayed out of order, labels stay where the presenter no longer shows them). Tabs
that place the same labels through the same camera work the placement out once. Before a phone's page
reports its window, its labels are placed for its canvas in CSS pixels."""

from __future__ import annotations

import json

import numpy as np
import pytest
from app_helpers import labels_placed, running_lab
from browser_helpers import PHONE_USER_AGENT
from fakes import poll
from wsclient import ViserWsClient

from app.core.actions import GoTo
from app.core.commands import LabelsPlaced, Mirror, PageReport
from app.core.role import Role
from app.core.state import LabState
from app.services.catalog import RobotCatalog
from app.tab.batch import Batch
from app.tab.following import Following
from app.tab.labels import PHONE_PIXEL_RATIO, Placement, guessed_pixel_ratio
from app.views.camera import View
from app.views.panel.viewport import visible_view_rect
from app.views.scene import labels as L

STATE = LabState.initial("planar2", RobotCatalog().load("planar2"))


def test_a_placement_in_the_state_a_batch_replays_comes_right_after_that_states_scene_messages():
    s1, s2 = STATE.replace(configuration="a"), STATE.replace(configuration="b")
    batch = Batch(STATE)
    batch.take_mirror(Mirror(s1, object(), scene=("s1-a", "s1-b")), has_scene=True, look="en")
    batch.take_placed(Placement(s1, "en", ("p1-a",)))
    batch.take_mirror(Mirror(s2, object(), scene=("s2-a",)), has_scene=True, look="en")
    batch.take_placed(Placement(s2, "en", ("p2-a", "p2-b")))
    _, replay = batch.mirrored()
    assert replay == ["s1-a", "s1-b", "p1-a", "s2-a", "p2-a", "p2-b"]  # each after its own drawing
    assert batch.placed == []


def test_a_placement_of_a_state_the_batch_does_not_replay_waits_for_the_commit():
    s1 = STATE.replace(configuration="a")
    batch = Batch(STATE)
    other = Placement(s1, "en", ("p1",))  # the state on screen already (drawn in an earlier visit)
    batch.take_placed(other)
    assert batch.placed == [other] and batch.mirrored() == (None, None)
    own = Batch(STATE)
    own.take_mirror(Mirror(s1, object(), scene=()), has_scene=True, look="en")  # drawn by the tab itself
    mine = Placement(s1, "en", ("p1",))
    own.take_placed(mine)
    assert own.placed == [mine] and own.mirrored()[1] is None


class _Labels:
    def __init__(self, shows: bool) -> None:
        self.shows, self.replayed = shows, []

    def replay(self, placed) -> bool:
        self.replayed.append(placed)
        return self.shows


def _following(labels) -> tuple[Following, list]:
    sent: list = []
    f = Following(1, None, sent.append, None, lambda: None, None, None, lambda: None, lambda: ())
    f.role, f.labels = Role(following=True, presenter=True), labels
    return f, sent


def test_a_follower_showing_the_drawing_replays_at_once_and_one_that_lags_queues_it_after_the_drawing():
    placed = Placement(STATE, "en", ("p",))
    shows, sent = _following(_Labels(True))
    shows.mirror_labels(placed)
    assert shows.labels.replayed == [placed] and sent == []
    lags, sent = _following(_Labels(False))
    lags.mirror_labels(placed)
    assert len(sent) == 1 and isinstance(sent[0], LabelsPlaced) and sent[0].placed is placed
    alone, sent = _following(_Labels(True))
    alone.role = Role(presenter=True)  # exploring on its own: its scene is its own
    alone.mirror_labels(placed)
    assert alone.labels.replayed == [] and sent == []


def test_before_a_phone_reports_its_window_its_labels_are_placed_for_its_canvas_in_css_pixels():
    """A phone's camera reports its canvas in device pixels (780×1688 for 390×844 at scale 2): until its
    page reports the window, its labels are placed for 390×844 CSS px (its User-Agent says it is a phone),
    not for a canvas twice as large (labels then lay twice as far apart as they could, some off the
    screen). A browser that is not a phone keeps a ratio of 1; once the window is reported, it decides."""

    assert guessed_pixel_ratio(PHONE_USER_AGENT) == PHONE_PIXEL_RATIO == 2.0
    assert guessed_pixel_ratio("Mozilla/5.0 (X11; Linux x86_64) Chrome/156.0.0.0 Safari/537.36") == 1.0
    with running_lab((876, 720)) as (lab, desk, _):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", 780, 1688, headers={"User-Agent": PHONE_USER_AGENT}):
            phone = poll(lambda: next((s for s in lab.sessions.values() if s is not desk), None))
            labels_placed(phone)
            layout = phone.scene.labels.layout
            assert (layout.width, layout.height) == pytest.approx((390.0, 844.0))
            labels_placed(desk)
            assert desk.scene.labels.layout.height == pytest.approx(720.0)  # a bare client: ratio 1
            phone.dispatch(
                PageReport(json.dumps({"kind": "view", "width": 390, "height": 844, "touch": True}))
            )
            phone.settle()
            labels_placed(phone)
            r = visible_view_rect(390, 844, True)
            assert (phone.scene.labels.layout.width, phone.scene.labels.layout.height) == (r.width, r.height)


def test_tabs_that_place_the_same_labels_through_the_same_camera_work_the_placement_out_once(monkeypatch):
    """Followers drawing their own scenes (they joined since the presenter's last change) each place their
    labels when the presenter turns the camera: the same labels, camera and canvas give the same places,
    worked out once in the process and put on every tab (each sends its own label moves). Another
    camera is another placement."""

    with running_lab((876, 720)) as (lab, one, _), ViserWsClient(f"ws://127.0.0.1:{lab.port}", 876, 720):
        two = poll(lambda: next((s for s in lab.sessions.values() if s is not one), None))
        for s in (one, two):
            s.dispatch(GoTo("wrist_singular"))
            s.settle()
            labels_placed(s)
        layout = one.scene.labels.layout  # placed for each tab's own camera before; now both for one
        made: list = []
        real = L._placed
        monkeypatch.setattr(L, "_PLACED", L._Recent(4))
        monkeypatch.setattr(L, "_placed", lambda *a: made.append(a) or real(*a))
        for s in (one, two):
            with s.lock, s.client.atomic():
                s.scene.labels.place(layout)
        assert len(made) == 1  # once for both tabs
        np.testing.assert_array_equal(one.scene.labels.boxes, two.scene.labels.boxes)
        for h1, h2 in zip(one.scene.labels.placed, two.scene.labels.placed, strict=True):
            assert h1.text == h2.text and np.allclose(h1.position, h2.position)
        v = layout.view
        turned = L.Layout(
            View(v.position + np.array([0.3, -0.2, 0.0]), v.look_at, v.up, v.fov, v.aspect),
            layout.width, layout.height, layout.rect, layout.avoid,
        )  # fmt: skip
        with two.lock, two.client.atomic():
            two.scene.labels.place(turned)
        assert len(made) == 2  # another camera: worked out again
        fresh = real(*made[-1])  # and the same as working it out anew
        np.testing.assert_allclose(two.scene.labels.boxes, fresh[1])
