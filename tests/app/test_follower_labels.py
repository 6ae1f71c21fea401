"""Issue 28, a follower's own labels: a phone (390×844, touch) following an English presenter in Polish
draws its own scene (its words are not the presenter's) and places its labels for its own camera, the
presenter's pose as the phone shows it, in the phone's own window.

Server level: a real lab in classroom mode with two websocket clients, the phone's canvas 390×422 (above
the sheet) and its page's window reported, the presenter's 876×720. The presenter goes to a named
configuration of the Puma, then its browser turns the camera (a drag: its camera message), which the
classroom hands the phone. Once the phone's camera is the presenter's, every label the phone shows lies,
through that camera (:func:`app.views.camera.project`, viser's layout of its text), inside the phone's
visible view (:func:`app.views.panel.viewport.visible_view_rect`), apart from the others. (A bare client,
like this one, does not echo a pose the server sets: the labels are placed when the pose is set.)"""

from __future__ import annotations

import json

import numpy as np
import pytest
from app_helpers import labels_placed, running_lab, wait_until
from test_live_overlay_labels import boxes_through_the_camera
from wsclient import ViserWsClient

from app.core.actions import GoTo
from app.core.commands import PageReport
from app.views.panel.viewport import visible_view_rect
from app.views.scene.placement import overlaps
from app.viser_adapter import message_class

TOKEN = "lecture-28-labels"
PHONE = (390, 844, True)
PROJECTOR = (1280, 720, False)
TOL = 1e-6  # [px]


def _report(session, **fields) -> None:
    session.dispatch(PageReport(json.dumps(fields)))
    session.settle()
    session.settle()


def _turned(camera, degrees: float, closer: float) -> tuple[np.ndarray, np.ndarray]:
    """``camera``'s pose turned ``degrees`` about the vertical through its look-at point and brought
    ``closer`` (a fraction of the distance) to it: a presenter's drag."""
    look, start = np.asarray(camera.look_at, float), np.asarray(camera.position, float)
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    turn = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    return look + (1 - closer) * turn @ (start - look), look


def phone_boxes(follower) -> tuple[np.ndarray, list[str]]:
    """The phone's shown labels' boxes [px] through its camera, in its canvas; their texts."""
    return boxes_through_the_camera(follower, PHONE)


@pytest.fixture(scope="module")
def room():
    phone = visible_view_rect(*PHONE)
    with running_lab((int(phone.width), int(phone.height)), presenter_token=TOKEN) as (lab, follower, _):
        _report(follower, kind="load", address="?lang=pl")
        _report(follower, kind="view", width=PHONE[0], height=PHONE[1], touch=PHONE[2])
        big = visible_view_rect(*PROJECTOR)
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", int(big.width), int(big.height)) as ws:
            wait_until(lambda: len(lab.sessions) == 2)
            presenter = next(s for s in lab.sessions.values() if s is not follower)
            _report(presenter, kind="view", width=PROJECTOR[0], height=PROJECTOR[1], touch=PROJECTOR[2])
            presenter.panel.classroom.token.value = TOKEN
            wait_until(lambda: presenter.role.presenting and follower.role.following)
            assert presenter.language == "en" and follower.language == "pl"
            yield presenter, ws, follower


@pytest.mark.parametrize("conf", ["wrist_singular", "elbow_singular", "shoulder_singular"])
def test_a_polish_phone_following_an_english_presenter_places_its_labels_in_its_own_view(room, conf):
    presenter, ws, follower = room
    presenter.dispatch(GoTo(conf))
    presenter.settle()
    wait_until(lambda: follower.state.configuration == conf and follower.snapshot is not None)
    follower.settle()
    assert follower.screen.own_scene is not None  # its own scene, in its words
    labels_placed(presenter)
    position, look = _turned(presenter.client.camera, 100.0, 0.3)
    cam = presenter.client.camera
    ws.send(
        message_class("ViewerCameraMessage")(
            wxyz=(1.0, 0.0, 0.0, 0.0), position=tuple(position), fov=float(cam.fov), near=0.01, far=100.0,
            image_height=int(cam.image_height), image_width=int(cam.image_width), look_at=tuple(look),
            up_direction=(0.0, 0, 1),
        )
    )  # fmt: skip
    wait_until(lambda: np.allclose(follower.client.camera.position, position, atol=1e-9), what="followed")
    labels_placed(follower)  # placed for the presenter's pose as the phone shows it
    layout = follower.scene.labels.layout
    r = visible_view_rect(*PHONE)
    assert (layout.width, layout.height) == (r.width, r.height)  # the phone's canvas, not the presenter's
    boxes, texts = phone_boxes(follower)
    assert any("utracon" in t for t in texts), texts  # the lost direction, in Polish
    inside = (
        (boxes[:, 0] >= -TOL)
        & (boxes[:, 1] >= -TOL)
        & (boxes[:, 2] <= r.width + TOL)
        & (boxes[:, 3] <= r.height + TOL)
    )
    assert inside.all(), [(t, b) for t, b, ok in zip(texts, boxes, inside, strict=True) if not ok]
    shrunk = boxes + np.array([TOL, TOL, -TOL, -TOL])
    assert not overlaps(shrunk), [(texts[i], texts[j]) for i, j in overlaps(shrunk)]


def test_a_phone_in_the_presenters_language_draws_its_own_scene_and_a_same_screen_follower_replays():
    """Labels are placed per screen: a phone in the presenter's language does not replay the projector's
    scene (its labels would be placed for the projector's canvas); of two phones of one size one draws
    the scene, inside its view, and the other replays that drawing; a follower whose screen is the
    presenter's replays the presenter's messages."""
    phone = visible_view_rect(*PHONE)
    big = visible_view_rect(*PROJECTOR)
    with running_lab((int(phone.width), int(phone.height)), presenter_token=TOKEN) as (lab, follower, _):
        _report(follower, kind="view", width=PHONE[0], height=PHONE[1], touch=PHONE[2])
        url, size = f"ws://127.0.0.1:{lab.port}", (int(big.width), int(big.height))
        with ViserWsClient(url, *size), ViserWsClient(url, *size):
            wait_until(lambda: len(lab.sessions) == 3)
            presenter, laptop = (s for s in lab.sessions.values() if s is not follower)
            for s in (presenter, laptop):
                _report(s, kind="view", width=PROJECTOR[0], height=PROJECTOR[1], touch=PROJECTOR[2])
            with ViserWsClient(url, int(phone.width), int(phone.height)):
                wait_until(lambda: len(lab.sessions) == 4)
                (other,) = (s for s in lab.sessions.values() if s not in (follower, presenter, laptop))
                _report(other, kind="view", width=PHONE[0], height=PHONE[1], touch=PHONE[2])
                presenter.panel.classroom.token.value = TOKEN
                room = (follower, laptop, other)
                wait_until(lambda: presenter.role.presenting and all(s.role.following for s in room))
                assert {s.language for s in (presenter, *room)} == {"en"}
                for conf in ("elbow_singular", "wrist_singular"):
                    presenter.dispatch(GoTo(conf))
                    presenter.settle()
                    wait_until(lambda: all(s.state is presenter.state for s in room))
                    for s in room:
                        s.settle()
                assert presenter.screen.look() == laptop.screen.look() != follower.screen.look()
                assert follower.screen.look() == other.screen.look()
                assert laptop.screen.own_scene is None  # the presenter's scene, replayed
                phones = [s for s in (follower, other) if s.screen.own_scene is not None]
                assert len(phones) == 1, len(phones)  # one phone drew the scene, the other replayed it
                drew = phones[0]
                labels_placed(drew)
                layout = drew.scene.labels.layout
                assert (layout.width, layout.height) == (phone.width, phone.height)
                boxes = drew.scene.labels.boxes
                assert len(boxes) and (boxes[:, 0] >= -TOL).all() and (boxes[:, 2] <= phone.width + TOL).all()
                assert (boxes[:, 1] >= -TOL).all() and (boxes[:, 3] <= phone.height + TOL).all()
