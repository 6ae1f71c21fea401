"""Followers that show the same are sent one follower's draw (issue 32): the panel drawn once per worker.

A tab's GUI ids follow its panel's structure and its panel has a digest (app/viser_adapter/panel_ledger.py);
followers of one state, look, open tab and digest join a relayed state's slot, the first draws, the others
are sent its frame as it is (app/tab/session.py: ride_key, take_ride). Checked here: the ids and digests of
tabs built alike, one panel draw per move for a room, every browser ending with the same panel as the one
that drew (folded from the websocket messages each received), and a follower that differs drawing its own.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from typing import Any

import pytest
from fakes import poll
from test_classroom import room
from wsclient import ViserWsClient

import app.tab.screen as screen_module
from app.core.actions import SetJoint
from app.core.commands import ExploreAlone
from app.services.scene_slot import SceneSlot
from app.viser_adapter import gui_digest, handle_uuid


@contextlib.contextmanager
def hall(n: int) -> Iterator[tuple[Any, Any, list, list[ViserWsClient]]]:
    """A lab with a presenter and ``n`` followers: (lab, presenter, followers, their websockets)."""
    clients: list[ViserWsClient] = []
    with room(n, clients) as (lab, first, others):
        by_key = {s.key: s for s in others}
        followers = [by_key[k] for k in sorted(by_key)]
        poll(lambda: all(f.role.following for f in followers))
        for s in (first, *followers):
            s.settle()
        for c, f in zip(clients, followers, strict=True):  # tabs are numbered in the order they came
            c.client_id = f.key  # type: ignore[attr-defined]
            mark, was = f"<p>tab {f.key}</p>", f.panel.source.content
            f.panel.source.content = mark  # which browser is whose: it shows this tab's mark
            poll(lambda c=c, mark=mark: any(p.get("content") == mark for p in panel_of(c).values()))
            f.panel.source.content = was
        yield lab, first, followers, clients


def panel_of(ws: ViserWsClient) -> dict[str, dict]:
    """What a browser's panel ends with: every element it was told of, by id, with its props and value
    as the messages it received left them (viser's numbering of ``order`` left out: see panel_ledger)."""
    panel: dict[str, dict] = {}
    with ws._cond:
        messages = [m for _, m in ws.messages]
    for m in messages:
        kind = m.get("type", "")
        if kind == "GuiUpdateMessage" and m["uuid"] in panel:
            panel[m["uuid"]].update(m["updates"])
        elif kind == "GuiRemoveMessage":
            panel.pop(m["uuid"], None)
        elif kind.startswith("Gui") and "uuid" in m and "props" in m:
            panel[m["uuid"]] = {**m["props"], "value": m.get("value")}
    for props in panel.values():
        props.pop("order", None)
    return panel


def panel_draws(monkeypatch: pytest.MonkeyPatch) -> list:
    """The panels drawn from now on (one entry per draw: the panel's tab's client id)."""
    drawn: list = []
    original = screen_module.PanelView.draw

    def draw(self, *args, **kwargs):
        drawn.append(self.client.client_id)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(screen_module.PanelView, "draw", draw)
    return drawn


def test_tabs_that_build_the_same_panel_hold_the_same_ids_and_digest():
    with hall(3) as (lab, presenter, tabs, sockets):
        ledgers = [t.client.gui.__dict__["_jl_ledger"] for t in (presenter, *tabs)]
        assert len(ledgers[0].live) > 100  # the whole panel
        assert all(set(x.live) == set(ledgers[0].live) for x in ledgers)  # the presenter's too
        ids = [handle_uuid(t.panel.joints.sliders[1]) for t in tabs]
        assert ids[0] == ids[1] == ids[2] and all(c.isalnum() or c in "-_" for c in ids[0])
        assert len({gui_digest(t.client) for t in tabs}) == 1
        # A prop of one tab changes its digest; back as it was, the digest is the others' again.
        a, b = tabs[1], tabs[2]
        status = a.panel.source
        was = status.content
        status.content = "<p>something else</p>"
        assert gui_digest(a.client) != gui_digest(b.client)
        status.content = was
        assert gui_digest(a.client) == gui_digest(b.client)
        # A value a browser sends changes that tab's digest too (the input gate tells the ledger): a tab
        # exploring on its own, whose input is not undone as a follower's is.
        a.dispatch(ExploreAlone())
        a.settle()
        poll(lambda: not a.role.following)
        a.settle()
        before, slider = gui_digest(a.client), a.panel.joints.sliders[0]
        moved = float(slider.value) + 5.0
        sockets[1].set_value(handle_uuid(slider), moved)
        poll(lambda: abs(float(slider.value) - moved) < 1e-9 and gui_digest(a.client) != before)


def test_followers_showing_the_same_are_sent_one_draw_and_end_with_its_panel(monkeypatch):
    n = 5
    with hall(n) as (lab, presenter, followers, sockets):
        for value in (0.3, -0.2):  # the first moves: each follower draws until they show the same
            presenter.dispatch(SetJoint(1, value))
            presenter.settle()
            poll(lambda: all(f.state is presenter.state for f in followers))
        drawn = panel_draws(monkeypatch)
        rides = sum(f.rides for f in followers)
        for i, value in enumerate((0.5, -0.4, 0.1)):
            del drawn[:]
            presenter.dispatch(SetJoint(1, value))
            presenter.settle()
            poll(lambda: all(f.state is presenter.state for f in followers))
            for f in followers:
                f.settle()
            follower_draws = [k for k in drawn if k != presenter.key]
            assert len(follower_draws) == 1, follower_draws  # one follower drew; the others took its frame
            assert sum(f.rides for f in followers) - rides == (n - 1) * (i + 1)
            assert all(f.snapshot is presenter.snapshot for f in followers)
            # Every follower's handles hold what the drawing follower's hold: one digest.
            assert len({gui_digest(f.client) for f in followers}) == 1
            # Every browser ends with the drawing follower's panel, the joint's slider at the new value.
            slider = handle_uuid(followers[0].panel.joints.sliders[1])
            degrees = round(math.degrees(value), 1)
            for ws in sockets:
                poll(
                    lambda ws=ws, slider=slider, degrees=degrees: (
                        abs(panel_of(ws).get(slider, {}).get("value", 1e9) - degrees) < 0.06
                    )
                )
            lead_key = follower_draws[0]
            lead_ws = next(ws for ws in sockets if ws.client_id == lead_key)
            want = panel_of(lead_ws)
            for ws in sockets:
                poll(lambda ws=ws, want=want: panel_of(ws) == want)


def test_a_follower_that_differs_draws_its_own(monkeypatch):
    """A follower whose panel shows something else (a prop of its own), one that explores, and one whose
    queue holds a message when the frame is ready are not sent the others' frame."""
    with hall(4) as (lab, presenter, followers, sockets):
        for value in (0.3, -0.2):
            presenter.dispatch(SetJoint(1, value))
            presenter.settle()
            poll(lambda: all(f.state is presenter.state for f in followers))
        own, alone = followers[1], followers[2]
        own.panel.source.content = "<p>only mine</p>"  # this tab's panel differs from the others'
        alone.dispatch(ExploreAlone())
        alone.settle()
        poll(lambda: not alone.role.following)
        drawn = panel_draws(monkeypatch)
        rides = {f.key: f.rides for f in followers}
        following = [f for f in followers if f is not alone]
        for value in (0.45, 0.5):  # the room told everyone that one explores: alike again after a move
            rides = {f.key: f.rides for f in followers}
            presenter.dispatch(SetJoint(1, value))
            presenter.settle()
            poll(lambda: all(f.state is presenter.state for f in following))
            for f in followers:
                f.settle()
        assert own.key in drawn and own.rides == rides[own.key]  # drew its own
        assert alone.state is not presenter.state and alone.rides == rides[alone.key]
        assert own.panel.source.content == "<p>only mine</p>"
        riders = [f for f in following if f is not own]
        assert sum(f.rides - rides[f.key] for f in riders) == 1  # of the two alike: one drew, one rode
        slider = handle_uuid(own.panel.joints.sliders[1])
        own_ws = next(ws for ws in sockets if ws.client_id == own.key)
        poll(lambda: abs(panel_of(own_ws)[slider]["value"] - round(math.degrees(0.5), 1)) < 0.06)


def test_a_rider_that_changed_after_joining_draws_its_own():
    """A follower that joined a slot under one key and shows something else when the frame is ready is
    queued the state instead (its own draw), never sent a frame drawn over another base."""
    with hall(3) as (lab, presenter, followers, sockets):
        for value in (0.3, -0.2):
            presenter.dispatch(SetJoint(1, value))
            presenter.settle()
            poll(lambda: all(f.state is presenter.state for f in followers))
        lead, rider, _ = followers
        from app.core.reducer import reduce
        from app.core.snapshot import compute

        state = reduce(presenter.state, SetJoint(1, 0.6))
        snap, slot = compute(state), SceneSlot()
        rides = rider.rides
        with lead.lock:  # the lead is held while the rider changes
            lead.following.mirror(state, snap, (), slot)
            rider.following.mirror(state, snap, (), slot)
            assert rider.state is not state  # it waits for the lead's frame
            rider.panel.source.content = "<p>changed meanwhile</p>"
        poll(lambda: lead.state is state and rider.state is state)
        rider.settle()
        assert rider.rides == rides  # it drew its own
        assert rider.panel.source.content == "<p>changed meanwhile</p>"


def test_a_tab_never_gives_one_id_twice():
    """An element removed and made again (a panel rebuilt in another language, another robot's joints)
    gets a new id: viser's page may drop an element removed and added under one id in one batch."""
    from app.viser_adapter.panel_ledger import PanelLedger

    ledger = PanelLedger()
    first = ledger.new_id("root")
    assert first == "root-0"
    assert ledger.new_id("root") == "root-0_1"  # nothing was made there yet, but root-0 was given
    other = PanelLedger()  # another tab with the same history gives the same ids
    assert [other.new_id("root"), other.new_id("root")] == ["root-0", "root-0_1"]
