"""Issue 28: a presenter's label placements reach a follower that replays its scene in the order they were
made, also when the follower has not yet drawn the state they were placed in (it lags): the placement is
then queued after that state's drawing, its messages replayed right after the drawing's own.

Replaying deltas out of order leaves labels where the presenter no longer shows them: a placement's
messages only hold the labels that moved, measured against the presenter's previous positions."""

from __future__ import annotations

import pytest
from browser_helpers import PHONE_USER_AGENT

from app.core.commands import LabelsPlaced, Mirror
from app.core.role import Role
from app.core.state import LabState
from app.services.catalog import RobotCatalog
from app.tab.batch import Batch
from app.tab.following import Following
from app.tab.labels import Placement

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


PHONE_UA = PHONE_USER_AGENT


def test_before_a_phone_reports_its_window_its_labels_are_placed_for_its_canvas_in_css_pixels():
    """A phone's camera reports its canvas in device pixels (780×1688 for 390×844 at scale 2): until its
    page reports the window, its labels are placed for 390×844 CSS px (its User-Agent says it is a phone),
    not for a canvas twice as large (labels then lay twice as far apart as they could, some off the
    screen). A browser that is not a phone keeps a ratio of 1; once the window is reported, it decides."""
    import json

    from app_helpers import labels_placed, running_lab
    from fakes import poll
    from wsclient import ViserWsClient

    from app.core.commands import PageReport
    from app.tab.labels import PHONE_PIXEL_RATIO, guessed_pixel_ratio
    from app.views.panel.viewport import visible_view_rect

    assert guessed_pixel_ratio(PHONE_UA) == PHONE_PIXEL_RATIO == 2.0
    assert guessed_pixel_ratio("Mozilla/5.0 (X11; Linux x86_64) Chrome/156.0.0.0 Safari/537.36") == 1.0
    with running_lab((876, 720)) as (lab, desk, _):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", 780, 1688, headers={"User-Agent": PHONE_UA}):
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
