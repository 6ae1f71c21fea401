"""The process's one thread of calls made later (app.services.later): order, cancelling, failures."""

from __future__ import annotations

import threading

from fakes import poll

from app.services.later import Later


def test_calls_run_in_the_order_they_are_due_on_one_thread_and_a_cancelled_one_never():
    later = Later()
    ran: list[tuple[str, str]] = []

    def record(name: str) -> None:
        ran.append((name, threading.current_thread().name))

    later.call(0.06, lambda: record("third"))
    dropped = later.call(0.03, lambda: record("cancelled"))
    later.call(0.0, lambda: record("first"))
    later.call(0.02, lambda: 1 / 0)  # fails: logged, the others still run
    later.call(0.04, lambda: record("second"))
    dropped.cancel()
    poll(lambda: len(ran) == 3, what="three calls")
    assert [name for name, _ in ran] == ["first", "second", "third"]
    assert {thread for _, thread in ran} == {"jacobian-lab-later"}
    assert len([t for t in threading.enumerate() if t.name == "jacobian-lab-later"]) >= 1


def test_a_call_made_from_a_call_runs_too():
    later = Later()
    ran: list[int] = []

    def first() -> None:
        ran.append(1)
        later.call(0.01, lambda: ran.append(2))

    later.call(0.0, first)
    poll(lambda: ran == [1, 2], what="both calls")
