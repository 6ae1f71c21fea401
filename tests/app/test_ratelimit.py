"""The per-tab rate limiting bookkeeping, on a fake clock."""

from __future__ import annotations

import pytest
from fakes import FakeClock

from app.services.ratelimit import LatestFirstQueue, LeakyCounter, TabLimiter, TokenBucket, state_key


def test_token_bucket_allows_the_burst_then_the_rate():
    clock = FakeClock(100.0)
    bucket = TokenBucket(rate=10.0, burst=3, clock=clock)
    assert [bucket.take() for _ in range(4)] == [True, True, True, False]
    assert bucket.wait_time() == pytest.approx(0.1)
    clock.now += 0.25  # 2.5 tokens back
    assert [bucket.take() for _ in range(3)] == [True, True, False]
    clock.now += 10.0  # refills to the burst, not beyond
    assert sum(bucket.take() for _ in range(10)) == 3


def test_leaky_counter_forgets_at_its_rate():
    clock = FakeClock(100.0)
    counter = LeakyCounter(rate=2.0, clock=clock)
    assert [counter.add() for _ in range(3)] == [1.0, 2.0, 3.0]
    clock.now += 1.0  # two forgiven
    assert counter.add() == pytest.approx(2.0)
    clock.now += 60.0
    assert counter.add() == 1.0


def test_latest_first_queue_keeps_the_newest_state_in_the_place_of_the_first():
    clock = FakeClock(100.0)
    queue = LatestFirstQueue(TokenBucket(rate=1.0, burst=1, clock=clock), capacity=3)
    assert queue.offer("a", "a1") == "now"
    assert queue.offer("a", "a2") == "queued"
    assert queue.offer("b", "b1") == "queued"
    assert queue.offer("a", "a3") == "replaced"
    assert queue.offer(None, "click1") == "queued"
    assert queue.offer(None, "click2") == "refused"  # capacity 3
    assert queue.pop_ready() is None and queue.wait_time() == pytest.approx(1.0)
    got = []
    for _ in range(3):
        clock.now += 1.0
        got.append(queue.pop_ready())
    assert got == ["a3", "b1", "click1"]
    assert len(queue) == 0 and queue.wait_time() == float("inf")


def test_a_message_waits_while_others_wait_even_if_a_token_is_back():
    clock = FakeClock(100.0)
    queue = LatestFirstQueue(TokenBucket(rate=1.0, burst=1, clock=clock), capacity=10)
    queue.offer("a", 1)
    queue.offer("a", 2)
    clock.now += 1.0
    assert queue.offer("b", 3) == "queued"  # order kept: "a" goes first
    assert queue.pop_ready() == 2


class GuiUpdateMessage:  # what the limiter reads of viser's messages: the class name and the key fields
    def __init__(self, uuid: str, value: float) -> None:
        self.uuid, self.updates = uuid, {"value": value}


class ViewerCameraMessage:
    pass


class GuiButtonHoldMessage:
    pass


def test_state_keys_tell_states_from_events():
    assert state_key(GuiUpdateMessage("s1", 1.0)) == state_key(GuiUpdateMessage("s1", 2.0))
    assert state_key(GuiUpdateMessage("s1", 1.0)) != state_key(GuiUpdateMessage("s2", 1.0))
    assert state_key(ViewerCameraMessage()) == ("ViewerCameraMessage",)
    assert state_key(GuiButtonHoldMessage()) is None


def test_tab_limiter_holds_gui_updates_to_their_rate_and_closes_a_flood():
    clock = FakeClock(100.0)
    tab = TabLimiter(rate=100.0, burst=10, gui_rate=5.0, gui_burst=2, close_after=50, clock=clock)
    verdicts = [tab.offer(GuiUpdateMessage("s", float(i))) for i in range(5)]
    assert verdicts == ["now", "now", "queued", "dropped", "dropped"]
    # The camera has its own budget: not held up by the slider's.
    assert [tab.offer(ViewerCameraMessage()) for _ in range(3)] == ["now"] * 3
    assert tab.wait_time() == pytest.approx(0.2)
    clock.now += 0.2
    (latest,) = tab.pop_ready()
    assert latest.updates == {"value": 4.0}
    verdicts = [tab.offer(GuiUpdateMessage("s", float(i))) for i in range(100)]
    assert verdicts[-1] == "close" and "close" not in verdicts[:48]
