"""The parent's one symbolic pool (``serve --workers N``), asked by several workers over real pipes.

Here the "workers" are :class:`SymbolicService` objects of this process, each over its own
``multiprocessing`` pipe to a :class:`SymbolicHub` whose symbolic process is real (spawned): the same
key asked by two workers is computed once and both get the single-process service's result; a key
released by every asker before it started is cancelled (never runs), a running one is left to finish
and still delivered; a killed symbolic process is restarted, its computation run again and every
worker told; only the kinds of the fixed table run, with arguments of their types; a worker that
leaves drops what only it wanted; a hub that closes fails what is pending.
(The whole server with real worker processes: tests/app/test_workers.py.)
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import time
from collections.abc import Iterator
from concurrent.futures import CancelledError
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

import pytest
from fakes import poll

import robots
from app.services.symbolic_hub import SymbolicHub
from app.services.symbolic_relay import RemotePools, remote_pools
from app.services.symbolic_service import (
    REQUESTS,
    WORKER_RESTARTED,
    Request,
    SymbolicService,
    SymbolicUnavailable,
)


# Run in the symbolic process (imported there by name).
def _wait_for(flag: str, started: str) -> int:
    """Leave the file ``started``, wait until the file ``flag`` exists; this process's id."""
    Path(started).touch()
    while not os.path.exists(flag):
        time.sleep(0.01)
    return os.getpid()


def _mark(path: str, text: str) -> str:
    """Leave a file ``path`` (this computation ran); ``text`` back."""
    Path(path).write_text(text)
    return text


TEST_REQUESTS = {
    **REQUESTS,
    "block": Request(_wait_for, (str, str), -1),
    "mark": Request(_mark, (str, str), -1),
}


@pytest.fixture
def hub() -> Iterator[SymbolicHub]:
    h = SymbolicHub(TEST_REQUESTS)
    try:
        yield h
    finally:
        h.close()


def _worker(hub: SymbolicHub, index: int) -> SymbolicService:
    """A worker's service, attached to ``hub`` over a pipe of its own."""
    ours, theirs = multiprocessing.get_context("spawn").Pipe(duplex=True)
    hub.attach(index, theirs)
    return SymbolicService(timeout=60.0, pools=remote_pools(ours))


def _pools(service: SymbolicService) -> RemotePools:
    pools = service._pools
    assert isinstance(pools, RemotePools)
    return pools


def _occupy(hub: SymbolicHub, pools: RemotePools, tmp_path: Path) -> tuple[object, str]:
    """A computation that runs until the file returned exists, and two behind it: the process pool has
    taken those two (a pool of one process holds two calls ready for it; a call taken can no longer be
    cancelled), so what is asked next waits in the hub's pool and can be."""
    flag, started = str(tmp_path / "go"), tmp_path / "started"
    busy = pools.want(("busy",), "block", (flag, str(started)))
    poll(started.exists, what="the first computation running")
    for i in range(2):
        pools.want((i,), "mark", (str(tmp_path / f"filler{i}"), str(i)))
    poll(lambda: hub.computed == 3, what="the hub took them")  # before any other worker's request
    return busy, flag


@pytest.mark.slow
def test_the_same_key_from_two_workers_is_computed_once_and_equals_the_single_process_result(hub):
    robot = robots.load("planar2")
    one, two = _worker(hub, 1), _worker(hub, 2)
    local = SymbolicService(timeout=60.0)
    try:
        futures = [one.mathml(robot, "tool"), two.mathml(robot, "tool")]
        expected = local.mathml(robot, "tool").result(120)
        assert [f.result(120) for f in futures] == [expected, expected]
        assert "<math" in expected and hub.computed == 1
        # A later ask (another tab, another worker) is answered from the hub's result.
        assert _worker(hub, 3).mathml(robot, "tool").result(60) == expected and hub.computed == 1
        assert one.inverse(robot).result(120) == local.inverse(robot).result(120)
        assert hub.computed == 2
        (pid,) = one.worker_pids()
        assert pid in hub.pids() and os.getpid() != pid
    finally:
        local.close()
        one.close()
        two.close()


def test_a_key_released_by_every_asker_before_it_started_never_runs(hub, tmp_path):
    ran = tmp_path / "ran"
    one, two = _pools(_worker(hub, 1)), _pools(_worker(hub, 2))
    flag = str(tmp_path / "go")
    try:
        busy, flag = _occupy(hub, one, tmp_path)
        waiting = [p.want(("m",), "mark", (str(ran), "x")) for p in (one, two)]
        poll(lambda: len(hub._asks) == 5, what="both requests taken")
        assert hub.computed == 4  # one computation for both
        assert waiting[0].cancel()  # the other worker still wants it
        assert not waiting[1].done()
        assert waiting[1].cancel()  # the last asker: cancelled before it started
        assert all(f.cancelled() for f in waiting)
        later = two.want(("later",), "mark", (str(tmp_path / "later"), "y"))
        Path(flag).touch()
        assert busy.result(60) in hub.pids() and later.result(60) == "y"
        assert not ran.exists()  # the released computation never ran
        assert hub.computed == 5
    finally:
        Path(flag).touch()
        one.close()
        two.close()


def test_a_running_computation_released_by_its_asker_is_left_to_finish_and_delivered(hub, tmp_path):
    flag, started = str(tmp_path / "go"), tmp_path / "started"
    pools = _pools(_worker(hub, 1))
    try:
        running = pools.want(("busy",), "block", (flag, str(started)))
        poll(started.exists, what="it runs")
        assert not running.cancel()  # it runs: left to finish, as Future.cancel answers in one process
        Path(flag).touch()
        assert running.result(60) in hub.pids()
    finally:
        Path(flag).touch()
        pools.close()


def test_a_killed_symbolic_process_is_restarted_the_askers_get_the_result_and_every_worker_is_told(
    hub, tmp_path
):
    flag, started = str(tmp_path / "go"), tmp_path / "started"
    services = [_worker(hub, 1), _worker(hub, 2)]
    told: list[list[str]] = [[], []]
    for service, notices in zip(services, told, strict=True):
        service.on_restart(notices.append)
    one, two = (_pools(s) for s in services)
    try:
        futures = [p.want(("b",), "block", (flag, str(started))) for p in (one, two)]
        poll(lambda: started.exists() and hub.computed == 1, what="one computation running")
        (pid,) = hub.pids()
        os.kill(pid, signal.SIGKILL)
        poll(lambda: hub.restarts == 1, what="the symbolic process restarted")
        Path(flag).touch()
        results = [f.result(60) for f in futures]
        assert results[0] == results[1] != pid and all(f.restarted for f in futures)
        assert hub.computed == 1  # run again for both, not once per asker
        poll(lambda: told == [[WORKER_RESTARTED], [WORKER_RESTARTED]], what="both workers told")
        assert [s.restarts for s in services] == [1, 1] and services[0].last_notice == WORKER_RESTARTED
    finally:
        Path(flag).touch()
        for service in services:
            service.close()


def test_only_the_table_s_kinds_run_and_only_with_their_argument_types(tmp_path):
    hub = SymbolicHub()  # the app's table only
    pools = _pools(_worker(hub, 1))
    try:
        for kind, args in [
            ("mark", (str(tmp_path / "ran"), "x")),  # a test kind: not in the app's table
            ("os.system", ("true",)),
            ("mathml", ("planar2", "base", 60.0, False)),  # a name where a robot belongs
            ("mathml", (robots.load("planar2"), "base", 60.0, "yes")),  # a string for a bool
            ("inverse", (robots.load("planar2"), False)),  # an argument short
        ]:
            with pytest.raises((TypeError, ValueError)):
                pools.want((kind,), kind, args).result(30)
        assert hub.computed == 0 and hub.pids() == [] and not (tmp_path / "ran").exists()
    finally:
        pools.close()
        hub.close()


def test_a_worker_that_leaves_drops_what_only_it_wanted(hub, tmp_path):
    ran, kept = tmp_path / "ran", tmp_path / "kept"
    one, two = _pools(_worker(hub, 1)), _pools(_worker(hub, 2))
    flag = str(tmp_path / "go")
    try:
        _, flag = _occupy(hub, two, tmp_path)
        mine = one.want(("only",), "mark", (str(ran), "x"))
        shared = [p.want(("both",), "mark", (str(kept), "y")) for p in (one, two)]
        poll(lambda: len(hub._asks) == 6, what="the requests taken")
        assert hub.computed == 5
        one.close()
        with pytest.raises(SymbolicUnavailable, match="gone"):
            mine.result(10)
        poll(lambda: 1 not in hub._links, what="the hub let the worker go")
        Path(flag).touch()
        assert shared[1].result(60) == "y" and kept.exists()
        assert not ran.exists()
    finally:
        Path(flag).touch()
        two.close()


def test_a_closing_hub_fails_what_is_pending_and_a_closed_worker_refuses_more(tmp_path):
    hub = SymbolicHub(TEST_REQUESTS)
    service = _worker(hub, 1)
    pools = _pools(service)
    pending = pools.want(("b",), "block", (str(tmp_path / "never"), str(tmp_path / "started")))
    poll((tmp_path / "started").exists, what="the computation running")
    hub.close()
    with pytest.raises((SymbolicUnavailable, CancelledError, BrokenProcessPool)):
        pending.result(30)
    poll(lambda: pools.closed, what="the worker saw the hub go")
    with pytest.raises(RuntimeError, match="closed"):
        service.mathml(robots.load("planar2"), "base")
    service.close()
