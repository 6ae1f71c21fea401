"""Classroom mode across worker processes (issue 17): the parent's :class:`RoomHub` and each worker's
:class:`RelayedClassroom`, over real ``multiprocessing`` pipes, in one process (the workers' tabs are
fakes; ``tests/app/test_workers.py`` runs the real thing). One presenter for the whole server, one count
of wrong tokens, followers in every worker, one snapshot computed per change per worker, robots only
the presenter has sent as file text, the room's follower count, and the presenter's reconnection."""

from __future__ import annotations

import multiprocessing
import threading
from multiprocessing.connection import wait

import numpy as np
import pytest
from fakes import FakeClock, poll

import robots
from app.core.snapshot import compute
from app.core.state import LabState
from app.services.catalog import RobotCatalog
from app.services.classroom import (
    ASKED,
    HANDED_OVER,
    HANDED_OVER_ROOM,
    KEPT,
    PRESENTER_AWAY,
    TAKEN_OVER,
    TOKEN_TRIES,
    WAITING,
    WRONG_TOKEN,
)
from app.services.classroom_relay import RelayedClassroom, RoomChannel
from app.services.room import RoomHub
from app.services.state_codec import CodecError, RobotWire, decode_state, dumps, encode_state, loads

TOKEN = "Xq7-vR2pLw9sKd4TzY"


class Tab:
    """A worker's tab as the classroom sees it (what a session's Following does, recorded)."""

    def __init__(self, state: LabState) -> None:
        self.state, self.snapshot = state, compute(state)
        self.mirrored: list[tuple[LabState, object]] = []
        self.cameras: list[tuple] = []
        self.placements: list[object] = []
        self.tabs: list[str] = []
        self.role = None
        self.told = ""  # the last note told (a note is said once: a later role, e.g. a new count, has none)
        self._listeners: list = []

    @property
    def latest(self):
        return self.state, self.snapshot

    @property
    def scene_messages(self):
        return ()

    def subscribe(self, fn):
        self._listeners.append(fn)
        return lambda: self._listeners.remove(fn)

    def commit(self, state: LabState) -> None:
        """The tab draws ``state`` (its own input): its listeners (the classroom's relay) hear it."""
        self.state, self.snapshot = state, compute(state)
        for fn in list(self._listeners):
            fn(self.state, self.snapshot)

    def mirror(self, state, snapshot, scene=(), shared=None):
        # In this order: a test that sees the new state (it polls for it) sees the rest too.
        self.mirrored.append((state, snapshot))
        self.snapshot = snapshot
        self.state = state

    def mirror_camera(self, *pose):
        self.cameras.append(pose)

    def mirror_labels(self, placed):
        self.placements.append(placed)

    def mirror_tab(self, label):
        self.tabs.append(label)

    def role_changed(self, role):
        self.role = role
        self.told = role.note or self.told


class Room:
    """A hub and ``n`` relayed classrooms, the hub fed by a thread as the supervising parent's loop."""

    def __init__(self, n: int = 2, clock=None) -> None:
        self.catalog = RobotCatalog([])
        self.hub = RoomHub(TOKEN, clock=clock) if clock else RoomHub(TOKEN)
        self.workers: dict[int, RelayedClassroom] = {}
        self.pipes = {}
        for w in range(1, n + 1):
            parent, child = multiprocessing.Pipe(duplex=True)
            channel = RoomChannel(child)
            self.workers[w] = RelayedClassroom(channel, self.catalog, address_of=lambda key: "10.0.0.7")
            channel.start()
            self.pipes[w] = parent
        self._stop = False
        self._lock = threading.Lock()
        for w in self.workers:
            self._send(self.hub.started(w))
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _send(self, out) -> None:
        for w, message in out:
            self.pipes[w].send_bytes(dumps(message))

    def _run(self) -> None:
        by_conn = {id(c): w for w, c in self.pipes.items()}
        while not self._stop:
            for conn in wait(list(self.pipes.values()), timeout=0.1):
                with self._lock:
                    self._send(self.hub.handle(by_conn[id(conn)], loads(conn.recv_bytes())))

    def close(self) -> None:
        self._stop = True
        self.thread.join(5)
        for conn in self.pipes.values():
            conn.close()

    def tab(self, worker: int, key: int, robot: str = "planar2") -> Tab:
        tab = Tab(LabState.initial(robot, self.catalog.load(robot)))
        self.workers[worker].join(key, tab)
        return tab


@pytest.fixture
def room():
    r = Room()
    yield r
    r.close()


def _moved(tab: Tab, q0: float) -> LabState:
    return tab.state.replace(q=np.array([q0, *tab.state.q[1:]]), configuration="")


def test_followers_in_every_worker_follow_and_each_worker_computes_once(room):
    presenter = room.tab(1, 1)
    near = [room.tab(1, k) for k in (2, 3)]
    far = [room.tab(2, k) for k in (10, 11, 12)]
    assert room.workers[1].claim(1, TOKEN) == ""
    poll(lambda: all(t.role is not None and t.role.following for t in near + far), what="all follow")
    # The presenter is shown the room's followers, not its worker's.
    poll(lambda: presenter.role.followers == 5, what="the room's count told to the presenter")
    poll(lambda: room.workers[1].followers() == 5 == room.workers[2].followers(), what="both workers count 5")
    assert presenter.role.presenting
    for i, q0 in enumerate((0.3, -0.7, 1.1)):
        presenter.commit(_moved(presenter, q0))
        poll(
            lambda q0=q0: all(t.state.q[0] == q0 and t.snapshot.q[0] == q0 for t in near + far),
            what="every follower at q0",
        )
        # The presenter's worker hands over its own snapshot; the other computes one for all its tabs.
        assert all(t.snapshot is presenter.snapshot for t in near)
        assert far[0].snapshot is far[1].snapshot is far[2].snapshot
        assert np.allclose(
            far[0].snapshot.J_base, presenter.snapshot.J_base
        )  # the same J, computed again there
        assert room.workers[2].computed <= i + 2  # once per change (and once for the claim's state)
    # Explore alone in worker 2: the room's count drops by one.
    room.workers[2].explore_alone(12)
    poll(lambda: presenter.role.followers == 4, what="the count after one explores alone")
    room.workers[1].camera(1, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    room.workers[1].tab(1, "Motion")
    poll(lambda: far[0].cameras and far[0].tabs == ["Motion"], what="camera and tab relayed")
    assert far[0].cameras[-1] == ((1.0, 2.0, 3.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)) and not far[2].cameras
    # A follower that drew for its worker's others places its labels again: its worker's other followers
    # are handed the placement (each replays it only if it shows that drawing), never itself nor a tab
    # exploring alone, nor another worker (which places its own for the relayed camera).
    placed = object()
    room.workers[2].labels(10, placed)
    assert far[1].placements == [placed] and not far[0].placements and not far[2].placements
    assert not any(t.placements for t in near)
    late = room.tab(2, 13)  # a tab arriving later, in the other worker, is shown where the room is
    poll(lambda: late.mirrored and late.state.q[0] == 1.1 and late.tabs == ["Motion"], what="a late tab")


def test_wrong_tokens_spend_only_their_own_connection_s_tries_in_any_worker(room):
    """Issue 26, point 3: every tab here has one address (10.0.0.7); on the old code five wrong tokens
    in worker 1 made the hub refuse the right one in worker 2 for a minute."""
    a, b, c = room.tab(1, 1), room.tab(2, 2), room.tab(1, 3)
    for i in range(TOKEN_TRIES):
        assert room.workers[1].claim(1, f"guess-{i}") == WRONG_TOKEN
    spent = room.workers[1].claim(1, TOKEN)
    assert spent.startswith(f"this tab has typed {TOKEN_TRIES} wrong tokens") and not a.role.presenting
    assert room.workers[2].claim(2, TOKEN) == ""  # the teacher, in the other worker
    poll(lambda: b.role is not None and b.role.presenting, what="the teacher presents")
    assert room.workers[1].claim(3, TOKEN) == WAITING  # and in the guessing tab's own worker (it asks)
    poll(lambda: b.role.asked, what="the teacher asked")
    room.workers[2].answer(2, accept=True)
    poll(lambda: c.role is not None and c.role.presenting and not b.role.presenting, what="handed over")


def test_a_robot_only_the_presenter_has_reaches_the_other_worker(room):
    presenter, far = room.tab(1, 1), room.tab(2, 2)
    assert room.workers[1].claim(1, TOKEN) == ""
    text = robots.dumps(room.catalog.load("puma560"), name="mine")
    mine = robots.loads(text, "mine.toml").robot  # built in the presenter's tab: in no catalogue
    presenter.commit(LabState.initial("Built robot", mine).replace(q=np.full(6, 0.4)))
    poll(lambda: far.state.robot_name == "Built robot", what="the built robot in worker 2")
    assert far.state.robot is not mine and far.state.robot.dof == 6
    assert np.allclose(far.snapshot.J_base, presenter.snapshot.J_base) and np.allclose(far.state.q, 0.4)
    presenter.commit(presenter.state.replace(q=np.full(6, 0.5)))
    poll(lambda: far.state.q[0] == 0.5, what="the next change")
    assert far.mirrored[-1][0].robot is far.mirrored[-2][0].robot  # read once: no scene rebuilt per change


def test_the_presenter_comes_back_in_another_worker_and_a_hand_over_and_a_takeover_are_told(room):
    clock_tabs = [room.tab(1, 1), room.tab(1, 2), room.tab(2, 3)]
    presenter, near, far = clock_tabs
    assert room.workers[1].claim(1, TOKEN) == ""
    key = room.workers[1].resume_key(1)
    presenter.commit(_moved(presenter, 0.9))
    poll(lambda: far.state.q[0] == 0.9, what="followed")
    room.workers[1].closed(1)  # the presenter's tab reloads ...
    poll(lambda: far.told == PRESENTER_AWAY and not far.role.following, what="told, in worker 2")
    assert near.told == PRESENTER_AWAY
    back = room.tab(2, 4)  # ... and lands on the other worker, with its page's key
    assert room.workers[2].resume(4, "not-the-key-0123456789") is False
    last = room.workers[2].resume(4, key)
    assert last and last[0].q[0] == 0.9 and back.state.q[0] == 0.9  # it takes over where it was
    poll(lambda: near.role.following and far.role.following, what="everyone follows it again")
    back.commit(_moved(back, -0.4))
    poll(lambda: near.state.q[0] == -0.4 and far.state.q[0] == -0.4, what="followed from worker 2")
    assert room.workers[1].claim(2, TOKEN) == WAITING  # a tab of worker 1 asks the presenter (worker 2)
    poll(lambda: back.role.asked and back.told == ASKED, what="the presenter asked")
    assert back.role.presenting and near.role.waiting and near.told == WAITING
    room.workers[2].answer(4, accept=True)
    poll(lambda: back.told == HANDED_OVER and back.role.following, what="the presenter told")
    poll(lambda: far.told == HANDED_OVER_ROOM and near.role.presenting, what="the room told")
    key = room.workers[1].resume_key(2)
    assert key == room.hub.resume_key and room.hub.presenter == (1, 2)
    again = room.tab(2, 5)  # the presenter's other tab (its browser has the key) takes over at once
    last = room.workers[2].resume(5, key)
    assert last and last[0].q[0] == -0.4 and again.state.q[0] == -0.4  # what the new presenter showed
    poll(lambda: near.told == TAKEN_OVER and near.role.following, what="the replaced presenter told")
    room.workers[2].resign(5)
    poll(lambda: not far.role.presenter and not back.role.following, what="resigned everywhere")


def test_the_codec_reads_only_what_it_wrote():
    catalog = RobotCatalog([])
    wire = RobotWire(catalog)
    state = LabState.initial("panda", catalog.load("panda"))
    data = loads(dumps(encode_state(state, wire.reference(state))))
    again = decode_state(data, wire)
    assert again.robot is state.robot and np.array_equal(again.q, state.q) and again.options == state.options
    assert not again.q.flags.writeable
    for bad in (
        {"state": {"$c": "Popen", "f": {}}, "robot": {"kind": "shared", "name": "panda"}},
        {"state": {"$c": "LabState", "f": {"q": {"$a": ["|O", [1], "AA=="]}}}, "robot": {}},
        {"state": {"$c": "LabState", "f": {"bogus": 1}}, "robot": {"kind": "shared", "name": "panda"}},
        [1, 2],
    ):
        with pytest.raises(CodecError):
            decode_state(bad, wire)


def test_a_worker_that_ends_leaves_the_room_and_its_presenter_may_come_back():
    clock = FakeClock(100.0)
    hub = RoomHub(TOKEN, clock=clock)
    hub.started(1), hub.started(2)
    out = hub.handle(1, {"op": "claim", "id": 1, "key": 5, "address": "a", "token": TOKEN})
    resume = out[0][1]["resume"]
    hub.handle(2, {"op": "count", "n": 3})
    assert hub.handle(1, {"op": "count", "n": 2}) == [(2, {"op": "others", "n": 2})]
    assert (1, {"op": "others", "n": 0}) in hub.gone(2) and hub.counts == {1: 2}
    assert (2, {"op": "away"}) not in hub.gone(1)  # worker 1 (the presenter's) ended: no one left to tell
    assert hub.presenter is None
    hub.started(1)
    clock.now += 119.0  # within the grace: the presenter's page comes back with its key
    assert hub.handle(1, {"op": "resume", "id": 2, "key": 7, "resume": resume})[0][1]["ok"]
    assert hub.presenter == (1, 7)
    hub.handle(1, {"op": "away", "key": 7})
    clock.now += 121.0  # too late now
    assert not hub.handle(1, {"op": "resume", "id": 3, "key": 8, "resume": resume})[0][1]["ok"]
    assert hub.handle(2, {"op": "state", "state": {}}) == []  # only the presenter's worker speaks for it
    for garbage in ([1], {"op": "claim", "id": 4}, {"op": "count", "n": "many"}, {"op": "nope"}, None):
        assert hub.handle(2, garbage) == []  # dropped, never raised into the parent's loop


# ---------------------------------------------------------------- issue 28, item 7: a hand-over
def _asked_room(room, claimant_worker: int):
    """Tab 1 of worker 1 presents; tab 2 of ``claimant_worker`` types the token and waits; tab 3 of
    worker 2 follows."""
    presenter, asking, other = room.tab(1, 1), room.tab(claimant_worker, 2), room.tab(2, 3)
    assert room.workers[1].claim(1, TOKEN) == ""
    poll(lambda: other.role is not None and other.role.following, what="followed")
    assert room.workers[claimant_worker].claim(2, TOKEN) == WAITING
    poll(lambda: presenter.role.asked and presenter.told == ASKED, what="the presenter asked")
    assert presenter.role.presenting and asking.role.waiting and room.hub.asking == (claimant_worker, 2)
    return presenter, asking, other


@pytest.mark.parametrize("claimant_worker", [1, 2], ids=["same worker", "other worker"])
def test_a_hand_over_across_workers_happens_only_when_the_presenter_agrees(room, claimant_worker):
    """On the old code the hub answered the claim with the presenter's role at once."""
    presenter, asking, other = _asked_room(room, claimant_worker)
    old_key = room.hub.resume_key
    room.workers[claimant_worker].answer(2, accept=True)  # forged: the asking tab's own worker and key
    room.workers[2].answer(3, accept=True)  # forged: a follower
    with room._lock:  # a worker that is not the presenter's speaks for it: the hub drops it
        assert room.hub.handle(2, {"op": "answer", "key": 1, "accept": True}) == []
    presenter.commit(_moved(presenter, 0.3))
    poll(lambda: other.state.q[0] == 0.3, what="the presenter still presents")
    assert presenter.role.presenting and asking.role.waiting and room.hub.presenter == (1, 1)
    room.workers[1].answer(1, accept=True)
    poll(lambda: asking.role.presenting and presenter.role.following, what="handed over")
    assert presenter.told == HANDED_OVER and not asking.role.waiting
    poll(lambda: other.told == HANDED_OVER_ROOM, what="the room told")
    new_key = room.workers[claimant_worker].resume_key(2)
    assert new_key == room.hub.resume_key != old_key and room.hub.asking is None
    asking.commit(_moved(asking, -0.6))
    poll(lambda: presenter.state.q[0] == -0.6 and other.state.q[0] == -0.6, what="the new presenter followed")


@pytest.mark.parametrize("claimant_worker", [1, 2], ids=["same worker", "other worker"])
def test_a_refused_hand_over_keeps_the_presenter_and_the_tab_may_ask_again(room, claimant_worker):
    presenter, asking, other = _asked_room(room, claimant_worker)
    room.workers[1].answer(1, accept=False)
    poll(lambda: asking.told == KEPT and not asking.role.waiting, what="the asking tab told")
    assert presenter.role.presenting and not presenter.role.asked and room.hub.asking is None
    assert room.workers[claimant_worker].claim(2, TOKEN) == WAITING
    poll(lambda: presenter.role.asked, what="asked again")


@pytest.mark.parametrize("claimant_worker", [1, 2], ids=["same worker", "other worker"])
def test_the_asking_tab_closing_withdraws_and_the_presenter_closing_drops_the_request(room, claimant_worker):
    presenter, asking, other = _asked_room(room, claimant_worker)
    room.workers[claimant_worker].closed(2)
    poll(lambda: not presenter.role.asked and room.hub.asking is None, what="withdrawn")
    room.workers[1].answer(1, accept=True)  # nothing to grant any more
    again = room.tab(claimant_worker, 4)
    assert room.workers[claimant_worker].claim(4, TOKEN) == WAITING
    poll(lambda: presenter.role.asked, what="asked by the new tab")
    room.workers[1].closed(1)  # the presenter's tab closes: the request is dropped ...
    poll(
        lambda: not again.role.waiting and not again.role.presenter and room.hub.asking is None,
        what="dropped",
    )
    assert room.workers[claimant_worker].claim(4, TOKEN) == ""  # ... and a right token presents at once
    poll(lambda: again.role.presenting and other.role.following, what="presents")


def test_the_hub_drops_hand_over_messages_out_of_turn():
    hub = RoomHub(TOKEN)
    hub.started(1), hub.started(2)
    assert hub.handle(1, {"op": "answer", "key": 5, "accept": True}) == []  # no presenter
    hub.handle(1, {"op": "claim", "id": 1, "key": 5, "token": TOKEN})
    assert hub.handle(1, {"op": "answer", "key": 5, "accept": True}) == []  # no request
    out = hub.handle(2, {"op": "claim", "id": 2, "key": 6, "token": TOKEN})
    assert out == [(2, {"op": "reply", "id": 2, "key": 6, "ok": True, "waiting": True}), (1, {"op": "ask"})]
    assert hub.handle(2, {"op": "answer", "key": 6, "accept": True}) == []  # not the presenter's worker
    assert hub.handle(1, {"op": "answer", "key": 4, "accept": True}) == []  # not the presenter's key
    assert hub.handle(1, {"op": "withdraw", "key": 6}) == []  # not the asking tab's worker
    for garbage in ({"op": "withdraw"}, {"op": "withdraw", "key": "six"}, {"op": "answer"}):
        assert hub.handle(2, garbage) == [] and hub.asking == (2, 6)
    assert hub.handle(1, {"op": "answer", "key": 5, "accept": "yes"}) == [(2, {"op": "refused", "key": 6})]
    assert hub.presenter == (1, 5)  # only a real true accepts
    hub.handle(2, {"op": "claim", "id": 3, "key": 6, "token": TOKEN})
    assert hub.gone(2)[0] == (1, {"op": "unask"}) and hub.asking is None  # its worker ended


def test_an_uploaded_urdf_robot_crosses_as_urdf_text():
    """An uploaded URDF (no DH table) travels as a URDF document and comes back with the same J."""
    from pathlib import Path

    from kinematics.urdf import robot_from_urdf_string

    text = (Path(__file__).parents[1] / "data" / "xarm7_like.urdf").read_bytes()
    uploaded = robot_from_urdf_string(text, name="xarm7_like")
    state = LabState.initial("xarm7_like (uploaded)", uploaded).replace(
        q=np.linspace(-0.5, 0.7, uploaded.dof)
    )
    sender, receiver = RobotWire(RobotCatalog([])), RobotWire(RobotCatalog([]))
    ref = sender.reference(state)
    assert ref["kind"] == ("urdf" if uploaded.dh is None else "toml")
    again = decode_state(loads(dumps(encode_state(state, ref))), receiver)
    assert again.robot_name == state.robot_name and again.robot.dof == uploaded.dof
    assert np.allclose(compute(again).J_base, compute(state).J_base, atol=1e-12)
    assert decode_state(loads(dumps(encode_state(state, ref))), receiver).robot is again.robot
