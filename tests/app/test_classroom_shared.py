"""A room of followers drawn from one computation: the presenter's snapshot computed once, its readouts
formatted once (app/views/shared.py), whoever shows them; a follower that explores on its own computes
and formats its own. Counted by wrapping compute() and the J readout's formatter of a running lab."""

from __future__ import annotations

import asyncio
import socket

import numpy as np
import pytest
import websockets
from app_helpers import running_lab, scene_node, scene_update_to
from fakes import poll
from test_classroom import room
from wsclient import ViserWsClient, decode_frame

import app.tab.session as session_module
import app.views.panel.matrix as matrix_module
from app.core.actions import SetJoint
from app.core.commands import ExploreAlone


class Counted:
    """A function that counts its calls (and which snapshot's J it formatted)."""

    def __init__(self, fn):
        self.fn, self.calls, self.args = fn, 0, []

    def __call__(self, *args, **kwargs):
        self.calls += 1
        self.args.append(args)
        return self.fn(*args, **kwargs)

    def of(self, first) -> int:
        """Calls whose first argument was ``first`` (that very object: one snapshot's J)."""
        return sum(args[0] is first for args in self.args)


@pytest.fixture
def counted(monkeypatch):
    compute, matrix_html = Counted(session_module.compute), Counted(matrix_module.matrix_html)
    monkeypatch.setattr(session_module, "compute", compute)
    monkeypatch.setattr(matrix_module, "matrix_html", matrix_html)
    return compute, matrix_html


def open_matrix(*sessions):
    for s in sessions:  # the J tab's readouts are filled (a tab fills only the one it has open)
        s.panel.open_tab = ""


def test_followers_of_one_state_share_one_computation_and_one_formatting(counted):
    compute, matrix_html = counted
    with room(3) as (lab, presenter, followers):
        poll(lambda: all(f.role.following for f in followers))
        for s in (presenter, *followers):
            s.settle()
        before_compute, shown = compute.calls, []
        for value in (-0.6, 0.2, 0.5):
            presenter.dispatch(SetJoint(2, value))
            presenter.settle()
            assert presenter.state.q[2] == pytest.approx(value)
            poll(lambda: all(f.state is presenter.state for f in followers))
            for f in followers:
                f.settle()
            for f in followers:  # what each follower shows is the presenter's, to the character
                assert f.snapshot is presenter.snapshot
                assert (
                    f.panel.parts["matrix"].numeric.content == presenter.panel.parts["matrix"].numeric.content
                )
            shown.append(presenter.snapshot)
        # Three moves, four tabs: three snapshots, and each one's J readout made once, not four times.
        assert compute.calls - before_compute == 3
        assert [matrix_html.of(snap.J_shown) for snap in shown] == [1, 1, 1]


def test_a_follower_that_explores_draws_its_own(counted):
    compute, matrix_html = counted
    with room(2) as (lab, presenter, (alone, follower)):
        poll(lambda: alone.role.following and follower.role.following)
        alone.dispatch(ExploreAlone())
        alone.settle()
        poll(lambda: not alone.role.following)
        before_compute = compute.calls
        alone.dispatch(SetJoint(1, 0.4))
        alone.settle()
        # Its own state, its own snapshot (a redraw the role change forced may compute it again); nobody
        # else computed anything.
        assert compute.of(alone.state) >= 1
        assert all(args[0] is alone.state for args in compute.args[before_compute:])
        assert alone.snapshot is not presenter.snapshot
        assert matrix_html.of(alone.snapshot.J_shown) == 1  # and its own readout
        assert alone.panel.parts["matrix"].numeric.content != presenter.panel.parts["matrix"].numeric.content
        presenter.dispatch(SetJoint(1, -0.3))  # the room moves on; the explorer stays where it is
        presenter.settle()
        poll(lambda: follower.state is presenter.state)
        follower.settle()
        assert follower.snapshot is presenter.snapshot
        assert alone.state.q[1] == pytest.approx(0.4)


def test_a_relayed_state_s_scene_is_drawn_by_one_follower_and_replayed_to_the_others(monkeypatch):
    """In a worker without the presenter (serve --workers N), a state arrives as data with one SceneSlot:
    the first follower to draw it draws the scene, the others (showing the same state before) replay its
    messages; every browser gets the arm where the drawing put it."""
    import app.views.scene as scene_module
    from app.core.reducer import reduce
    from app.core.snapshot import compute
    from app.services.scene_slot import SceneSlot

    updates = Counted(scene_module.SceneView.update)
    monkeypatch.setattr(scene_module.SceneView, "update", lambda self, *a: updates(self, *a))
    with running_lab(presenter_token="a-long-enough-token-for-the-room") as (lab, first, first_ws):
        others = [ViserWsClient(f"ws://127.0.0.1:{lab.port}") for _ in range(2)]
        try:
            for c in others:
                c.start()
            poll(lambda: len(lab.sessions) == 3)
            tabs = list(lab.sessions.values())
            sockets = [first_ws, *others]
            state = tabs[0].state
            for round_, value in enumerate((0.3, -0.5, 0.6)):
                state = reduce(state, SetJoint(1, value))
                snap, slot = compute(state), SceneSlot()
                before, marks = updates.calls, [ws.mark() for ws in sockets]
                for tab in tabs:
                    tab.following.mirror(state, snap, (), slot)
                poll(lambda state=state: all(t.state is state for t in tabs))
                for tab in tabs:
                    tab.settle()
                drawn = updates.calls - before
                # The first round: each tab showed its own state before, so each draws its own scene.
                assert drawn == (3 if round_ == 0 else 1)
                want = None
                for tab in tabs:
                    if tab.screen.scene is not None and not tab.screen._foreign:
                        want = np.asarray(scene_node(tab, "/lab/arm/cylinders").batched_positions).ravel()
                assert want is not None
                for ws, mark in zip(sockets, marks, strict=True):
                    ws.wait_for(scene_update_to("/lab/arm/cylinders", want), after=mark)
        finally:
            for c in others:
                c.close()


class StalledClient(ViserWsClient):
    """A follower whose page has stopped reading its websocket (a phone asleep, a saturated link): it
    reads the first frame, then nothing, through a 4 KiB receive window. (On loopback the kernel and
    viser's buffers still absorb 40 moves: the server's send to it has not been seen to block here.)"""

    async def _connect(self) -> None:
        real = websockets.connect

        def small_window(url, **kwargs):  # a receive window of 4 KiB: the server's writes back up at once
            sock = socket.socket()
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            sock.connect(("127.0.0.1", int(url.rsplit(":", 1)[1])))
            return real(url, sock=sock, max_queue=1, **kwargs)

        websockets.connect = small_window
        try:
            await super()._connect()
        finally:
            websockets.connect = real

    async def _receive(self) -> None:
        frame = await self._ws.recv()
        with self._cond:
            self.messages.extend((0.0, m) for m in decode_frame(frame))
            self._cond.notify_all()
        await asyncio.Event().wait()  # never reads again


def test_a_follower_that_stops_reading_holds_nobody_back():
    with room(1) as (lab, presenter, (follower,)):
        stalled = StalledClient(f"ws://127.0.0.1:{lab.port}")
        try:
            stalled.start()
            poll(lambda: len(lab.sessions) == 3)
            slow = next(s for s in lab.sessions.values() if s not in (presenter, follower))
            poll(lambda: slow.role.following and follower.role.following)
            watcher = ViserWsClient(f"ws://127.0.0.1:{lab.port}")  # a third follower that reads
            with watcher:
                poll(lambda: len(lab.sessions) == 4)
                for i in range(40):
                    mark = watcher.mark()
                    presenter.dispatch(SetJoint(1, -0.5 + 0.02 * i))
                    presenter.settle()
                    want = presenter.state

                    def arm(m):
                        return m["type"] == "SceneNodeUpdateMessage" and m["name"] == "/lab/arm/cylinders"

                    watcher.wait_for(arm, after=mark)  # the reading follower gets every move
                    poll(lambda want=want: slow.state is want)  # the stalled one's session keeps up too
                    slow.settle()
        finally:
            stalled.close()


def test_a_follower_draws_its_closed_motion_and_derive_tabs_only_once_it_opens_them_or_explores(monkeypatch):
    """The Motion and Derive tabs are drawn even when closed in a tab of one's own (their buttons act on
    their last draw); a follower's buttons are refused, so its closed ones wait until it opens them or
    explores on its own (a room of 300 drew them 300 times a move for nobody)."""
    from app.views.panel.derive import DerivePanel
    from app.views.panel.motion import MotionPanel

    drawn: list[tuple[str, object]] = []
    for cls, name in ((MotionPanel, "motion"), (DerivePanel, "derive")):
        original = cls.draw

        def counting(self, state, snap, _original=original, _name=name):
            drawn.append((_name, state))
            return _original(self, state, snap)

        monkeypatch.setattr(cls, "draw", counting)
    with room(1) as (lab, presenter, (follower,)):
        poll(lambda: follower.role.following)
        for s in (presenter, follower):  # as the page reports: loaded, the J tab open
            s.panel.report.value = '{"kind": "load", "address": "", "resume": "", "tab": ""}'
            s.settle()
            poll(lambda s=s: s.panel.open_tab == "J(q)")
        drawn.clear()
        presenter.dispatch(SetJoint(1, 0.3))
        presenter.settle()
        poll(lambda: follower.state is presenter.state)
        follower.settle()
        want = presenter.state
        # the presenter's own closed tabs drawn (its buttons act on them), not the follower's
        assert sorted(n for n, s in drawn if s is want) == ["derive", "motion"]
        assert len([1 for n, s in drawn if s is want]) == 2  # once each: by the presenter only
        drawn.clear()
        follower.panel.report.value = '{"kind": "tab", "tab": "Motion"}'  # the follower opens Motion
        poll(lambda: ("motion", follower.state) in drawn)  # drawn at once, with the state on screen
        assert ("derive", follower.state) not in drawn
        follower.panel.report.value = '{"kind": "tab", "tab": "J(q)"}'
        poll(lambda: follower.panel.open_tab == "J(q)")
        drawn.clear()
        follower.dispatch(ExploreAlone())
        follower.settle()
        poll(lambda: not follower.role.following)
        follower.dispatch(SetJoint(2, 0.2))
        follower.settle()
        mine = follower.state
        assert sorted(n for n, s in drawn if s is mine) == ["derive", "motion"]  # its own tab: both again
