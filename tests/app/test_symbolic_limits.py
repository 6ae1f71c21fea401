"""Issue 26 item 1: a symbolic computation is bounded by the operating system, not by its cooperation.

The worker process is killed at the time limit or when its resident memory passes the limit (a
watchdog in the server), an allocation past its address space limit fails inside it (RLIMIT_AS), the
asker is told which limit, and the next computation runs on a new process. Small limits keep these
tests fast; the functions run in the worker are imported there by name.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest
from fakes import poll

import robots
from app.services.symbolic_process import Limits, WorkerPool, resident_bytes
from app.services.symbolic_requests import MAX_SYMBOLIC_JOINTS, SymbolicNotAttempted, SymbolicStopped
from app.services.symbolic_service import SymbolicService
from app.tab.symbolic_words import told

pytestmark = pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="reads /proc (Linux)")
MB = 1e6


# Run in the worker process (imported there by name).
def _hog(step_mb: int) -> None:
    """Take ``step_mb`` more of touched memory every 20 ms, without end (a SymPy step that never ends)."""
    kept = []
    while True:
        kept.append(bytearray(b"\1") * (step_mb * 1_000_000))
        time.sleep(0.02)


def _forever() -> None:
    while True:
        time.sleep(0.05)


def _gone(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state in ("Z", "X")


def test_a_computation_that_eats_memory_is_stopped_at_the_limit_and_the_next_one_runs():
    """The resident memory watchdog: killed within the limit (polled while it grows), and the process
    never held much more than its limit; a computation queued behind it is served by a new process."""
    pool = WorkerPool(limits=Limits(seconds=300, memory_mb=60, address_mb=4000))
    try:
        pool.submit(os.getpid).result(120)  # started, its modules imported
        (pid,) = pool.pids()
        ready = resident_bytes(pid)
        assert ready is not None
        hog = pool.submit(_hog, 2)  # 100 MB/s: a poll every 0.1 s overshoots by about 10 MB
        after = pool.submit(os.getpid)
        peak = 0
        while not hog.done() and not _gone(pid):  # the process's memory over time
            peak = max(peak, resident_bytes(pid) or 0)
            time.sleep(0.02)
        with pytest.raises(SymbolicStopped) as stopped:
            hog.result(120)
        assert stopped.value.limit == "memory" and stopped.value.memory_mb == 60
        assert str(stopped.value) == "stopped at 60 MB"
        poll(lambda: _gone(pid), what="the stopped process gone")
        assert (peak - ready) / MB < 60 + 30, f"grew {(peak - ready) / MB:.0f} MB over a 60 MB limit"
        new_pid = after.result(120)
        assert new_pid != pid and not _gone(new_pid)
        assert pool.stopped == 1 and pool.restarts == 0  # stopped at a limit: not a crash, no notice
    finally:
        pool.close()


def test_an_allocation_past_the_address_space_limit_fails_inside_the_process():
    """RLIMIT_AS: the backstop between two polls (the watchdog's resident limit is out of reach here)."""
    pool = WorkerPool(limits=Limits(seconds=300, memory_mb=100_000, address_mb=150))
    try:
        hog = pool.submit(_hog, 40)
        with pytest.raises(SymbolicStopped) as stopped:
            hog.result(120)
        assert stopped.value.limit == "memory"
        assert pool.submit(os.getpid).result(120) in pool.pids()
    finally:
        pool.close()


def test_a_computation_that_never_ends_is_stopped_at_the_time_limit():
    pool = WorkerPool(limits=Limits(seconds=1.5, memory_mb=500, address_mb=4000))
    try:
        forever = pool.submit(_forever)
        after = pool.submit(os.getpid)
        with pytest.raises(SymbolicStopped) as stopped:
            forever.result(120)
        assert stopped.value.limit == "time" and str(stopped.value) == "stopped after 2 s"
        assert not _gone(after.result(120))
        assert pool.stopped == 1
    finally:
        pool.close()


def test_the_limits_come_from_the_environment(monkeypatch):
    monkeypatch.setenv("JACOBIAN_LAB_SYMBOLIC_SECONDS", "4")
    monkeypatch.setenv("JACOBIAN_LAB_SYMBOLIC_MEMORY_MB", "60")
    limits = Limits.from_env()
    assert (limits.seconds, limits.memory_mb) == (4.0, 60.0)
    assert limits.address_mb == pytest.approx(Limits.address_mb * 60 / Limits.memory_mb)


def test_an_arm_past_the_measured_rule_is_not_attempted_and_the_tab_is_told_so_at_once():
    """Nothing is started (no worker process), the future has failed already, and the words name the
    arm's joints and the rule."""
    from hostile_helpers import chain_urdf

    from kinematics.urdf import robot_from_urdf_string

    arm = robot_from_urdf_string(chain_urdf(24), name="long")
    service = SymbolicService()
    try:
        for future in (
            service.mathml(arm, "base"),
            service.steps(arm, "whitney"),
            service.export(arm, "LaTeX", "base"),
        ):
            assert future.done()
            assert isinstance(future.exception(), SymbolicNotAttempted)
        assert service.worker_pids() == []
        title, body = told("matrix", service.mathml(arm, "base").exception(), arm.dof)
        assert title == "Symbolic form not attempted"
        assert body.startswith(
            f"The symbolic J of this 24-joint arm is not worked out: the server works out "
            f"arms of up to {MAX_SYMBOLIC_JOINTS} joints"
        )
        assert body.endswith("The numeric J above is live.")
        small = service.mathml(robots.load("planar2"), "base")  # within the rule: computed
        assert "<math" in small.result(120)
    finally:
        service.close()
