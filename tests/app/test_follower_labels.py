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


def _last_positions(ws: ViserWsClient) -> dict[str, np.ndarray]:
    """The position each scene node was last moved to, in the messages ``ws``'s browser received."""
    with ws._cond:
        received = list(ws.messages)
    return {
        m["name"]: np.asarray(m["position"]) for _, m in received if m.get("type") == "SetPositionMessage"
    }


def test_the_presenters_orbit_moves_the_labels_of_followers_replaying_its_scene_and_a_new_window_draws_own():
    """A laptop the presenter's size replays the presenter's scene, labels placed for that screen: when
    the presenter turns the camera, its labels are placed again and the laptop's browser is sent the
    very same placements (it has no scene of its own to place). When the laptop's window then becomes a
    phone's, its look is another: it draws its own scene, its labels placed inside the phone's view."""
    big = visible_view_rect(*PROJECTOR)
    size = (int(big.width), int(big.height))
    with running_lab(size, presenter_token=TOKEN) as (lab, presenter, ws):
        _report(presenter, kind="view", width=PROJECTOR[0], height=PROJECTOR[1], touch=PROJECTOR[2])
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", *size) as laptop_ws:
            wait_until(lambda: len(lab.sessions) == 2)
            (laptop,) = (s for s in lab.sessions.values() if s is not presenter)
            _report(laptop, kind="view", width=PROJECTOR[0], height=PROJECTOR[1], touch=PROJECTOR[2])
            presenter.panel.classroom.token.value = TOKEN
            wait_until(lambda: presenter.role.presenting and laptop.role.following)
            presenter.dispatch(GoTo("wrist_singular"))
            presenter.settle()
            wait_until(lambda: laptop.state is presenter.state)
            laptop.settle()
            assert laptop.screen.own_scene is None and laptop.screen.look() == presenter.screen.look()
            labels_placed(presenter)
            before = {h.name: np.array(h.position) for h in presenter.scene.labels.placed}
            position, look = _turned(presenter.client.camera, 80.0, 0.2)
            cam = presenter.client.camera
            ws.send(
                message_class("ViewerCameraMessage")(
                    wxyz=(1.0, 0.0, 0.0, 0.0), position=tuple(position), fov=float(cam.fov), near=0.01,
                    far=100.0, image_height=int(cam.image_height), image_width=int(cam.image_width),
                    look_at=tuple(look), up_direction=(0.0, 0, 1),
                )
            )  # fmt: skip
            wait_until(lambda: np.allclose(presenter.client.camera.position, position, atol=1e-9))
            labels_placed(presenter)
            after = {h.name: np.array(h.position) for h in presenter.scene.labels.placed}
            moved = [n for n in after if n in before and not np.allclose(after[n], before[n], atol=1e-6)]
            assert moved, "the orbit moved no label: nothing to relay"

            def shown_as_presenters() -> bool:
                seen = _last_positions(laptop_ws)
                return all(n in seen and np.allclose(seen[n], p, atol=1e-5) for n, p in after.items())

            wait_until(shown_as_presenters, what="the laptop's browser shows the presenter's placements")
            # Its window becomes a phone's: another look, so its own scene, its labels in its own view.
            _report(laptop, kind="view", width=PHONE[0], height=PHONE[1], touch=PHONE[2])
            wait_until(lambda: laptop.screen.own_scene is not None, what="the laptop drew its own scene")
            labels_placed(laptop)
            phone = visible_view_rect(*PHONE)
            layout = laptop.scene.labels.layout
            assert (layout.width, layout.height) == (phone.width, phone.height)
            boxes = laptop.scene.labels.boxes
            assert len(boxes) and (boxes[:, 0] >= -TOL).all() and (boxes[:, 2] <= phone.width + TOL).all()
            assert (boxes[:, 1] >= -TOL).all() and (boxes[:, 3] <= phone.height + TOL).all()
