"""The server process and its children end together: on SIGTERM, SIGHUP, kill -9 of the server; a killed
symbolic worker is replaced.

Each test starts the app in its own process and session (``app.server.serve``), connects one tab so
that the symbolic worker starts, then ends things from outside and polls /proc (no sleeps) until
no process of that session is left.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import pytest
from fakes import POLL_TIMEOUT, poll
from server_process import Server, alive, children, cmdline, session_processes
from wsclient import ViserWsClient

from app.services.lifecycle import check_listen_address, wait_in_main_thread

ROBOT = "planar2"  # its symbolic J takes a second


def _has_mathml(m: dict) -> bool:
    content = m.get("updates", m.get("props", {})).get("content")
    return isinstance(content, str) and "<math" in content


def _start_with_tab(tmp_path: Path, code: str) -> tuple[Server, list[int]]:
    """A server with one tab that received the symbolic J, and the server's children then."""
    server = Server(tmp_path, code)
    with ViserWsClient(server.url()) as ws:
        ws.wait_for(_has_mathml)
    kids = children(server.pid)
    assert any("spawn_main" in cmdline(p) for p in kids), [cmdline(p) for p in kids]
    assert any("resource_tracker" in cmdline(p) for p in kids), [cmdline(p) for p in kids]
    return server, kids


SERVE = f"from app.server import serve; serve(robot={ROBOT!r}, host='127.0.0.1', port=0, block=True)"
SERVE_WIRED = (
    "from app.server import serve; from app.services.lifecycle import wait_for_stop\n"
    f"lab = serve(robot={ROBOT!r}, host='127.0.0.1', port=0, block=False)\n"
    "print('stopped by', wait_for_stop(lab.stop), flush=True)"
)


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_stop_signal_leaves_no_process_behind(tmp_path, sig):
    server, kids = _start_with_tab(tmp_path, SERVE)
    try:
        os.kill(server.pid, sig)
        server.proc.wait(POLL_TIMEOUT)
        poll(lambda: not session_processes(server.pid), what="no process of the server's session left")
        assert not any(alive(p) for p in kids)
    finally:
        server.cleanup()


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT], ids=["TERM", "HUP", "INT"])
def test_wait_for_stop_stops_the_lab_cleanly(tmp_path, sig):
    server, kids = _start_with_tab(tmp_path, SERVE_WIRED)
    try:
        os.kill(server.pid, sig)
        assert server.proc.wait(POLL_TIMEOUT) == 0, server.log.read_text()[-2000:]
        poll(lambda: any(f"stopped by {sig.name}" in line for line in server.out), what="the reason printed")
        poll(lambda: not session_processes(server.pid), what="no process of the server's session left")
    finally:
        server.cleanup()


@pytest.mark.slow
def test_the_worker_exits_by_itself_when_the_server_is_killed(tmp_path):
    server, kids = _start_with_tab(tmp_path, SERVE)
    try:
        os.kill(server.pid, signal.SIGKILL)
        server.proc.wait(POLL_TIMEOUT)
        start = time.monotonic()
        poll(lambda: not session_processes(server.pid), what="the orphaned worker and tracker gone")
        assert time.monotonic() - start < 5.0
    finally:
        server.cleanup()


@pytest.mark.slow
def test_a_killed_worker_is_replaced_for_the_next_request(tmp_path):
    server, _ = _start_with_tab(tmp_path, SERVE)
    try:
        (worker,) = server.workers()
        os.kill(worker, signal.SIGKILL)
        poll(lambda: not alive(worker), what="the worker gone")
        with ViserWsClient(server.url()) as ws:  # a later tab starts, and asks for a new J
            _, frame = ws.wait_for(
                lambda m: m["type"] == "GuiDropdownMessage" and m["props"]["label"] == "Frame of J",
                timeout=60,
            )
            ws.wait_for(_has_mathml)
            mark = ws.mark()
            ws.set_value(frame["uuid"], "tool")
            # The tool-frame J, which only a new worker can compute (the first one was killed).
            _, msg = ws.wait_for(lambda m: _has_mathml(m) and "in tool axes" in str(m), after=mark)
            assert "could not start" not in str(ws.messages)
        poll(lambda: len(server.workers()) == 1, what="one new worker")
        (new_worker,) = server.workers()
        assert new_worker != worker
        assert "the symbolic worker stopped and was restarted" in server.log.read_text()
    finally:
        server.cleanup()


@pytest.mark.parametrize("host", ["127.0.0.1", "localhost", "0.0.0.0", ""])
def test_addresses_of_this_machine_are_accepted(host):
    check_listen_address(host, 0)
    check_listen_address(host, 65535)


@pytest.mark.parametrize(
    ("host", "port", "message"),
    [
        ("127.0.0.1", 99999, "port must be an integer from 0 to 65535 (0: any free port), got 99999"),
        ("127.0.0.1", -1, "got -1"),
        ("127.0.0.1", 80.5, "got 80.5"),
        (
            "no-such-host.invalid",
            0,
            "cannot listen on host 'no-such-host.invalid': the name does not resolve",
        ),
        ("192.0.2.1", 0, "cannot listen on host '192.0.2.1' (192.0.2.1): "),  # TEST-NET-1: never ours
    ],
)
def test_impossible_addresses_fail_at_once_in_words(host, port, message):
    start = time.monotonic()
    with pytest.raises(ValueError) as info:
        check_listen_address(host, port)
    assert message in str(info.value)
    assert time.monotonic() - start < 5.0


def test_a_stop_signal_taken_by_another_thread_still_wakes_the_waiting_main_thread():
    """The CI hang of a busy server: the kernel gave SIGTERM to a viser thread, Python flagged it, and a
    main thread blocked in one long ``Event.wait()`` never ran the handler. Sent here to a thread of
    our own (``pthread_kill``), so that it is never the main thread that takes it."""
    stopped = threading.Event()
    previous = signal.signal(signal.SIGUSR2, lambda number, frame: stopped.set())
    try:
        # Sent once the main thread is (most likely) blocked waiting; if it comes earlier, the test
        # passes trivially; it never fails when waking works.
        other = threading.Timer(0.3, lambda: signal.pthread_kill(threading.get_ident(), signal.SIGUSR2))
        other.start()
        assert wait_in_main_thread(stopped, timeout=60.0)
        other.join()
    finally:
        signal.signal(signal.SIGUSR2, previous)


def test_wait_in_main_thread_returns_false_after_its_timeout():
    assert not wait_in_main_thread(threading.Event(), timeout=0.05)
