"""The server process and its children end together: on SIGTERM, SIGHUP, kill -9 of the server; a killed
symbolic worker is replaced.

Each test starts the app in its own process and session (``app.server.serve``), connects one tab so
that the symbolic worker starts, then ends things from outside and polls /proc (no sleeps) until
no process of that session is left.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from wsclient import ViserWsClient

ROOT = Path(__file__).resolve().parents[1]
ROBOT = "planar2"  # its symbolic J takes a second


def _stat(pid: int) -> list[str] | None:
    """Fields of /proc/PID/stat after the command name (state, ppid, pgrp, session, ...), or None."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (FileNotFoundError, ProcessLookupError):
        return None


def _alive(pid: int) -> bool:
    fields = _stat(pid)
    return fields is not None and fields[0] not in ("Z", "X")


def session_processes(sid: int) -> list[int]:
    """Live processes of session ``sid`` (the server and every descendant, even re-parented ones)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            fields = _stat(int(entry.name))
            if fields is not None and fields[0] not in ("Z", "X") and int(fields[3]) == sid:
                found.append(int(entry.name))
    return found


def children(pid: int) -> list[int]:
    """Live direct children of ``pid``."""
    return [
        p for p in session_processes(os.getsid(pid)) if p != pid and (_stat(p) or ["", "0"])[1] == str(pid)
    ]


def _poll(predicate, timeout: float = 30.0, what: str = "condition"):
    end = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > end:
            raise AssertionError(f"{what} not reached within {timeout} s")
        time.sleep(0.02)


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except FileNotFoundError:
        return ""


class Server:
    """The app in a subprocess of its own session, with its log in a file."""

    def __init__(self, tmp_path: Path, code: str) -> None:
        self.log = tmp_path / "server.log"
        with open(self.log, "wb") as log:
            self.proc = subprocess.Popen(
                [sys.executable, "-u", "-c", code],
                stdout=subprocess.PIPE,
                stderr=log,
                text=True,
                cwd=ROOT,
                env=dict(os.environ, PYTHONPATH=str(ROOT)),
                start_new_session=True,
            )
        self.out: list[str] = []
        assert self.proc.stdout is not None
        match = None
        for line in self.proc.stdout:  # until the URL is printed (or the process ends)
            self.out.append(line)
            match = re.search(r"open http://127\.0\.0\.1:(\d+)", line)
            if match:
                break
        if not match:
            self.proc.kill()
            raise AssertionError(f"no URL printed: {self.out}; log: {self.log.read_text()[-2000:]}")
        self.port = int(match.group(1))
        self.pid = self.proc.pid
        # Keep reading what it prints (a full pipe would block the server).
        threading.Thread(target=lambda: self.out.extend(self.proc.stdout), daemon=True).start()

    def url(self) -> str:
        return f"ws://127.0.0.1:{self.port}"

    def workers(self) -> list[int]:
        return [p for p in children(self.pid) if "spawn_main" in _cmdline(p)]

    def cleanup(self) -> None:
        for pid in session_processes(self.pid):
            os.kill(pid, signal.SIGKILL)
        self.proc.wait(10)


def _has_mathml(m: dict) -> bool:
    content = m.get("updates", m.get("props", {})).get("content")
    return isinstance(content, str) and "<math" in content


def _start_with_tab(tmp_path: Path, code: str) -> tuple[Server, list[int]]:
    """A server with one tab that received the symbolic J, and the server's children then."""
    server = Server(tmp_path, code)
    with ViserWsClient(server.url()) as ws:
        ws.wait_for(_has_mathml, timeout=120)
    kids = children(server.pid)
    assert any("spawn_main" in _cmdline(p) for p in kids), [_cmdline(p) for p in kids]
    assert any("resource_tracker" in _cmdline(p) for p in kids), [_cmdline(p) for p in kids]
    return server, kids


SERVE = f"from app.server import serve; serve(robot={ROBOT!r}, host='127.0.0.1', port=0, block=True)"
SERVE_WIRED = (
    "from app.server import serve; from app.lifecycle import wait_for_stop\n"
    f"lab = serve(robot={ROBOT!r}, host='127.0.0.1', port=0, block=False)\n"
    "print('stopped by', wait_for_stop(lab.stop), flush=True)"
)


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_stop_signal_leaves_no_process_behind(tmp_path, sig):
    server, kids = _start_with_tab(tmp_path, SERVE)
    try:
        os.kill(server.pid, sig)
        server.proc.wait(30)
        _poll(lambda: not session_processes(server.pid), 10, "no process of the server's session left")
        assert not any(_alive(p) for p in kids)
    finally:
        server.cleanup()


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT], ids=["TERM", "HUP", "INT"])
def test_wait_for_stop_stops_the_lab_cleanly(tmp_path, sig):
    server, kids = _start_with_tab(tmp_path, SERVE_WIRED)
    try:
        os.kill(server.pid, sig)
        assert server.proc.wait(30) == 0, server.log.read_text()[-2000:]
        _poll(lambda: any(f"stopped by {sig.name}" in line for line in server.out), 5, "the reason printed")
        _poll(lambda: not session_processes(server.pid), 10, "no process of the server's session left")
    finally:
        server.cleanup()


def test_the_worker_exits_by_itself_when_the_server_is_killed(tmp_path):
    server, kids = _start_with_tab(tmp_path, SERVE)
    try:
        os.kill(server.pid, signal.SIGKILL)
        server.proc.wait(10)
        start = time.monotonic()
        _poll(lambda: not session_processes(server.pid), 10, "the orphaned worker and tracker gone")
        assert time.monotonic() - start < 5.0
    finally:
        server.cleanup()


def test_a_killed_worker_is_replaced_for_the_next_request(tmp_path):
    server, _ = _start_with_tab(tmp_path, SERVE)
    try:
        (worker,) = server.workers()
        os.kill(worker, signal.SIGKILL)
        _poll(lambda: not _alive(worker), 10, "the worker gone")
        with ViserWsClient(server.url()) as ws:  # a later tab starts, and asks for a new J
            _, frame = ws.wait_for(
                lambda m: m["type"] == "GuiDropdownMessage" and "tool" in m["props"]["options"], timeout=60
            )
            ws.wait_for(_has_mathml, timeout=60)
            mark = ws.mark()
            ws.set_value(frame["uuid"], "tool")
            _, msg = ws.wait_for(_has_mathml, after=mark, timeout=120)
            assert "could not start" not in str(ws.messages)
        (new_worker,) = server.workers()
        assert new_worker != worker
        assert "the symbolic worker stopped and was restarted" in server.log.read_text()
    finally:
        server.cleanup()
