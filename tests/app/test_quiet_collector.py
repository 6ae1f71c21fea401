"""The full garbage collection run while the server is quiet (``app/services/quiet_collector.py``, issue
32): not while tabs join or are drawn, once they have settled; what it freezes is left out of later
collections, and a closed tab's objects held in a cycle are still freed at the next quiet moment."""

from __future__ import annotations

import gc
import weakref

import pytest
from app_helpers import running_lab
from fakes import poll

from app.services.later import Call
from app.services.quiet_collector import QuietCollector


class Clock:
    """Time that moves when the test says, and the calls due at it."""

    def __init__(self) -> None:
        self.now, self.calls = 100.0, []

    def schedule(self, delay: float, fn) -> Call:
        call = Call(fn)
        self.calls.append((self.now + delay, call))
        return call

    def advance(self, seconds: float, step: float = 0.5) -> None:
        end = self.now + seconds
        while self.now < end:
            self.now = min(self.now + step, end)
            due = [c for c in self.calls if c[0] <= self.now]
            self.calls = [c for c in self.calls if c[0] > self.now]
            for _, call in due:
                if not call.cancelled:
                    call.fn()


@pytest.fixture
def clock():
    yield Clock()
    gc.unfreeze()  # the test process's objects go back to the collector


class Cycle:
    def __init__(self) -> None:
        self.me = self  # freed only by a collection that sees it


def collector(clock: Clock, activity: list[int], every: float = 60.0) -> QuietCollector:
    return QuietCollector(
        lambda: activity[0], 0.5, 2.0, every, clock=lambda: clock.now, schedule=clock.schedule
    )


def test_it_waits_for_the_joins_and_the_drawing_to_settle(clock):
    activity = [0]
    quiet = collector(clock, activity)
    for _ in range(12):  # tabs joining every 0.25 s: never quiet for 0.5 s
        quiet.joined()
        clock.advance(0.25, step=0.25)
    assert quiet.collections == {"new": 0, "full": 0}
    for _ in range(12):  # then a presenter moving, and the room drawn, every 0.25 s
        activity[0] += 5
        clock.advance(0.25, step=0.25)
    assert quiet.collections == {"new": 0, "full": 0}
    clock.advance(1.0, step=0.25)  # quiet: the new tabs' objects collected and frozen, nothing else
    assert quiet.collections == {"new": 1, "full": 0} and gc.get_freeze_count() > 0
    clock.advance(30.0)  # nothing joined, nothing drawn: nothing to do
    assert quiet.collections == {"new": 1, "full": 0}


def test_a_join_freezes_only_what_is_new(clock):
    quiet = collector(clock, [0])
    quiet.joined()
    clock.advance(1.0)
    frozen = gc.get_freeze_count()
    tab = [Cycle() for _ in range(1000)]  # a new tab's objects
    quiet.joined()
    clock.advance(1.0)
    assert quiet.collections == {"new": 2, "full": 0}
    assert gc.get_freeze_count() >= frozen + 1000  # the old ones stayed frozen, the new joined them
    del tab


def test_a_closed_tab_s_cycle_is_freed_at_the_next_quiet_moment(clock):
    quiet = collector(clock, [0])
    tab = Cycle()
    gone = weakref.ref(tab)
    quiet.joined()
    clock.advance(1.0)
    assert quiet.collections["new"] == 1 and gone() is not None  # frozen with the open tabs
    del tab  # the tab closed: its objects hold each other
    gc.collect()
    assert gone() is not None  # frozen: an ordinary collection leaves it
    quiet.left()
    clock.advance(1.0)
    assert quiet.collections["full"] == 0 and gone() is not None  # a full one waits for 2 s of quiet
    clock.advance(1.5)
    assert quiet.collections["full"] == 1 and gone() is None


def test_drawing_alone_makes_a_full_collection_due_every_minute(clock):
    activity = [0]
    quiet = collector(clock, activity, every=60.0)
    for _ in range(70):  # a minute of a tab exploring on its own (it may have replaced its panel)
        activity[0] += 1
        clock.advance(1.0)
    assert quiet.collections == {"new": 0, "full": 0}
    clock.advance(3.0)
    assert quiet.collections == {"new": 0, "full": 1}


def test_close_gives_the_frozen_objects_back(clock):
    quiet = collector(clock, [0])
    quiet.joined()
    clock.advance(1.0)
    assert gc.get_freeze_count() > 0
    quiet.close()
    assert gc.get_freeze_count() == 0
    quiet.joined()
    clock.advance(10.0)
    assert quiet.collections == {"new": 1, "full": 0}  # closed: no more


def test_the_server_collects_once_its_tabs_have_settled():
    """``serve``'s Lab: a tab joins, the collector runs once things are quiet, the heap is frozen; the
    Lab's stop gives it back. (A notebook's Lab, the default, has none.)"""
    try:
        with running_lab(collect_quietly=True) as (lab, session, ws):
            assert lab.collector is not None
            poll(lambda: lab.collector.collections["new"] >= 1, what="a quiet collection after the join")
            assert gc.get_freeze_count() > 0
        assert gc.get_freeze_count() == 0
        with running_lab() as (lab, session, ws):
            assert lab.collector is None
    finally:
        gc.unfreeze()
