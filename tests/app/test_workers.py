"""``jacobian-lab serve --workers N``: one address served by N processes under a supervising parent.

Each test starts the command line in its own process session and checks, through websocket clients
and /proc: every tab is served and each worker serves tabs; a worker killed with SIGKILL is started
again and new tabs are served meanwhile; SIGTERM stops every process of the tree; a parent killed
outright leaves nothing behind. Linux only (it reads /proc).
"""

from __future__ import annotations

import os
import re
import signal
import socket
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from fakes import POLL_TIMEOUT, poll
from server_process import ROOT, alive, session_processes
from wsclient import ViserWsClient

from app.cli.main import main
from app.cli.workers import WORKER_CAP, WorkerPool, default_workers, listening_socket

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc (Linux)")


class Pool:
    """``jacobian-lab serve --workers N`` in a process session of its own, its log in a file."""

    def __init__(self, tmp_path: Path, workers: int) -> None:
        self.log = tmp_path / "pool.log"
        self._log = open(self.log, "wb")
        self.proc = subprocess.Popen(
            [sys.executable, "-u", "-m", "app.cli.main", "serve", "--robot", "planar2", "--port", "0"]
            + ["--workers", str(workers)],
            stdout=subprocess.PIPE,
            stderr=self._log,
            text=True,
            cwd=ROOT,
            env=dict(os.environ, PYTHONPATH=str(ROOT)),
            start_new_session=True,
        )
        self.out: list[str] = []
        assert self.proc.stdout is not None
        match = None
        for line in self.proc.stdout:
            self.out.append(line)
            match = re.search(r"open http://[^:]+:(\d+) .*worker processes: ([\d ]+)\)", line)
            if match:
                break
        if not match:
            self.cleanup()
            raise AssertionError(f"no address printed: {self.out}; log: {self.log.read_text()[-3000:]}")
        self.port = int(match.group(1))
        self.workers = [int(p) for p in match.group(2).split()]
        threading.Thread(target=lambda: self.out.extend(self.proc.stdout or ()), daemon=True).start()

    def url(self) -> str:
        return f"ws://127.0.0.1:{self.port}"

    def served_by(self) -> dict[int, int]:
        """How many tabs each process has reported connected (from the workers' log lines)."""
        counts: dict[int, int] = {}
        for pid in re.findall(r"tab \d+ connected \(\d+ open in process (\d+)\)", self.log.read_text()):
            counts[int(pid)] = counts.get(int(pid), 0) + 1
        return counts

    def cleanup(self) -> None:
        for pid in session_processes(self.proc.pid):
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        self.proc.wait(POLL_TIMEOUT)
        self._log.close()


@pytest.fixture
def pool2(tmp_path):
    pool = Pool(tmp_path, 2)
    yield pool
    pool.cleanup()


def _tab_served(url: str) -> None:
    """One tab connects and receives its robot's GUI (a slider), then closes."""
    with ViserWsClient(url) as ws:
        ws.wait_for(lambda m: m["type"] == "GuiSliderMessage")


@pytest.mark.slow
def test_every_tab_is_served_and_both_workers_serve(pool2):
    assert len(pool2.workers) == 2 and all(alive(p) for p in pool2.workers)
    clients = [ViserWsClient(pool2.url()).__enter__() for _ in range(8)]
    try:
        for ws in clients:
            ws.wait_for(lambda m: m["type"] == "GuiSliderMessage")
        counts = poll(lambda: (c := pool2.served_by()) and sum(c.values()) >= 8 and c, what="8 tabs logged")
        assert set(counts) <= set(pool2.workers)
    finally:
        for ws in clients:
            ws.__exit__(None, None, None)
    # The operating system decides who accepts; a worker that is not busy wins, so more tabs spread over both.
    extra = []
    try:
        for _ in range(24):
            if len(pool2.served_by()) == 2:
                break
            extra.append(ViserWsClient(pool2.url()).__enter__())
            extra[-1].wait_for(lambda m: m["type"] == "GuiSliderMessage")
        assert set(pool2.served_by()) == set(pool2.workers), pool2.served_by()
    finally:
        for ws in extra:
            ws.__exit__(None, None, None)


@pytest.mark.slow
def test_a_killed_worker_is_started_again_and_the_room_keeps_working(pool2):
    victim, other = pool2.workers
    os.kill(victim, signal.SIGKILL)
    _tab_served(pool2.url())  # served meanwhile, by whichever worker is alive
    index = pool2.workers.index(victim) + 1

    def restarted() -> int | None:
        pids = [int(p) for p in re.findall(rf"worker {index} \(pid (\d+)\) serving", pool2.log.read_text())]
        return next((p for p in pids if p != victim), None)

    new_pid = poll(restarted, what="the dead worker started again")
    assert new_pid != victim and alive(new_pid) and alive(other)
    for _ in range(4):
        _tab_served(pool2.url())


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_stop_signal_ends_every_process(pool2, sig):
    _tab_served(pool2.url())
    assert len(session_processes(pool2.proc.pid)) >= 3  # the parent, two workers (and their helpers)
    os.kill(pool2.proc.pid, sig)
    assert pool2.proc.wait(POLL_TIMEOUT) == 0, pool2.log.read_text()[-3000:]
    poll(lambda: not session_processes(pool2.proc.pid), what="no process of the pool's session left")


@pytest.mark.slow
def test_workers_exit_by_themselves_when_the_parent_is_killed(pool2):
    _tab_served(pool2.url())
    os.kill(pool2.proc.pid, signal.SIGKILL)
    pool2.proc.wait(POLL_TIMEOUT)
    poll(lambda: not session_processes(pool2.proc.pid), what="the orphaned workers (and their helpers) gone")


def test_listening_socket_takes_the_next_free_port():
    busy = listening_socket("127.0.0.1", 0)
    try:
        port = busy.getsockname()[1]
        nxt = listening_socket("127.0.0.1", port)
        try:
            assert nxt.getsockname()[1] > port
        finally:
            nxt.close()
    finally:
        busy.close()
    with pytest.raises(ValueError, match="does not resolve"):
        listening_socket("no-such-host.invalid", 0)


def test_worker_counts_are_checked(capsys):
    assert 1 <= default_workers() <= WORKER_CAP
    for bad in ("0", "17", "two", "-1"):
        assert main(["serve", "--workers", bad, "--port", "0"]) == 2
        assert "--workers" in capsys.readouterr().err
    sock = socket.socket()
    try:
        with pytest.raises(ValueError, match="workers must be 1 to"):
            WorkerPool(sock, 0, {})
    finally:
        sock.close()


def test_serve_chooses_one_process_or_the_pool(monkeypatch, capsys):
    import app.cli.workers
    import app.server

    single, pooled = [], []
    monkeypatch.setattr(app.server, "serve", lambda **kwargs: single.append(kwargs))
    monkeypatch.setattr(
        app.cli.workers,
        "serve_workers",
        lambda n, options, host, port, presenter_token=None: pooled.append((n, presenter_token)) or 0,
    )
    assert main(["serve", "--workers", "1", "--port", "8124"]) == 0 and len(single) == 1
    assert main(["serve", "--workers", "3", "--port", "8124"]) == 0 and pooled == [(3, None)]
    # Classroom mode spans the workers: the pool gets the token (only its parent keeps it).
    assert main(["serve", "--workers", "3", "--presenter-token", "Xq7-vR2pLw9sKd4TzY", "--port", "8124"]) == 0
    assert len(single) == 1 and pooled[-1] == (3, "Xq7-vR2pLw9sKd4TzY")
    assert "ignored" not in capsys.readouterr().err
