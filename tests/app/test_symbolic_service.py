"""The symbolic worker survives its own death: restarted, the request retried once, the restart reported."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import pytest
from fakes import poll

import robots
from app.services.symbolic_service import WORKER_RESTARTED, SymbolicService, SymbolicUnavailable, WorkerPool


def _gone(pid: int) -> bool:
    """The process has exited (a zombie waiting to be reaped counts as gone)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state in ("Z", "X")


# Run in the worker process (imported there by name).
def _pid_once(flag: str) -> int:
    """Wait until the file ``flag`` exists, then return this worker's process id."""
    while not os.path.exists(flag):
        time.sleep(0.01)
    return os.getpid()


def _die() -> None:
    os.kill(os.getpid(), signal.SIGKILL)


@pytest.fixture
def service():
    svc = SymbolicService(timeout=60.0)
    try:
        yield svc
    finally:
        svc.close()


@pytest.mark.slow
def test_a_killed_worker_is_restarted_and_the_next_request_succeeds(service):
    from kinematics.symbolic import jacobian_mathml

    robot = robots.load("planar2")
    notices: list[str] = []
    service.on_restart(notices.append)
    first = service.mathml(robot, "base")
    assert "<math" in first.result(120)
    (pid,) = service.worker_pids()
    os.kill(pid, signal.SIGKILL)
    poll(lambda: _gone(pid))
    second = service.mathml(robot, "tool")
    assert second.result(120) == jacobian_mathml(robot, frame="tool", timeout=60.0)
    assert second.restarted and not first.restarted
    assert service.restarts == 1
    poll(lambda: notices == [WORKER_RESTARTED])  # announced from a thread of its own
    assert service.last_notice == WORKER_RESTARTED
    (new_pid,) = service.worker_pids()
    assert new_pid != pid


def test_a_worker_killed_mid_computation_runs_it_again_once(tmp_path):
    notices: list[str] = []
    pool = WorkerPool(on_restart=notices.append)
    try:
        flag = str(tmp_path / "go")
        future = pool.submit(_pid_once, flag)
        poll(lambda: len(pool.pids()) == 1)
        (pid,) = pool.pids()
        os.kill(pid, signal.SIGKILL)
        poll(lambda: future.restarted)
        Path(flag).touch()
        new_pid = future.result(60)
        assert new_pid != pid and not _gone(new_pid)
        assert pool.restarts == 1
        poll(lambda: notices == [WORKER_RESTARTED])
    finally:
        pool.close()


@pytest.mark.slow
def test_a_computation_that_kills_every_worker_fails_clearly_and_the_pool_recovers():
    pool = WorkerPool()
    try:
        future = pool.submit(_die)
        with pytest.raises(SymbolicUnavailable, match="stopped twice"):
            future.result(60)
        assert future.restarted and pool.restarts == 1
        after = pool.submit(os.getpid)
        assert after.result(60) in pool.pids()
        assert pool.restarts == 2  # the pool the second death broke was replaced for this request
    finally:
        pool.close()


def test_close_ends_the_worker_and_refuses_more_work():
    pool = WorkerPool()
    pid = pool.submit(os.getpid).result(60)
    pool.close()
    poll(lambda: _gone(pid))
    with pytest.raises(RuntimeError, match="closed"):
        pool.submit(os.getpid)
