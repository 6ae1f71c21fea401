"""How the server's processes end: on a stop signal, and never after their parent.

A server stopped with ``kill`` (SIGTERM), by closing its terminal (SIGHUP), by a
service manager or with Ctrl-C (SIGINT) calls its ``stop`` once through
:func:`wait_for_stop` (or :func:`install_stop_signals`), which ends the symbolic
workers. A worker started with :func:`watch_parent` as its initializer also ends
by itself when its parent is gone without stopping it (``kill -9``), and with it
multiprocessing's resource tracker, which exits when the last process holding its
pipe does.

Example (the blocking path of :func:`app.server.serve`)::

    lab = Lab(...)
    wait_for_stop(lab.stop)   # returns "SIGTERM", "SIGHUP" or "SIGINT" once lab.stop() has run
"""

from __future__ import annotations

import dataclasses
import faulthandler
import logging
import multiprocessing
import os
import signal
import socket
import threading
import time
from collections.abc import Callable
from multiprocessing.connection import wait as wait_for_handles
from types import FrameType

__all__ = [
    "STOP_SIGNALS",
    "StopSignals",
    "install_stop_signals",
    "wait_for_stop",
    "wait_in_main_thread",
    "dump_stacks_on_sigusr1",
    "terminate_children",
    "end_resource_tracker",
    "check_listen_address",
]

log = logging.getLogger(__name__)

STOP_SIGNALS: tuple[str, ...] = ("SIGTERM", "SIGHUP", "SIGINT")
"""Signals that stop the server cleanly (those this platform lacks are skipped)."""


@dataclasses.dataclass
class StopSignals:
    """Handlers installed by :func:`install_stop_signals`.

    Attributes:
        received: Name of the first stop signal received (``"SIGTERM"``, ...), or ``None``.
    """

    received: str | None = None
    _previous: dict[int, object] = dataclasses.field(default_factory=dict)

    def restore(self) -> None:
        """Put back the handlers that were there before."""
        for number, handler in self._previous.items():
            signal.signal(number, handler)  # type: ignore[arg-type]
        self._previous.clear()


def install_stop_signals(stop: Callable[[], None]) -> StopSignals:
    """On the first SIGTERM, SIGHUP or SIGINT call ``stop()``; on a second one, end the process now.

    ``stop`` runs in the main thread, inside the signal handler: keep it short (e.g. set an
    event, as :func:`wait_for_stop` does). A second stop signal while the first is being handled
    (a stuck shutdown, Ctrl-C pressed twice) terminates the child processes and exits with status
    128 + the signal's number.

    Must be called from the main thread (Python delivers signals there).

    Returns:
        The installed handlers: which signal came, and :meth:`StopSignals.restore`.
    """
    state = StopSignals()

    def handler(number: int, frame: FrameType | None) -> None:
        name = signal.Signals(number).name
        if state.received is not None:
            log.warning("%s while stopping: ending now", name)
            terminate_children(timeout=1.0)
            os._exit(128 + number)
        state.received = name
        log.info("%s: stopping", name)
        stop()

    for name in STOP_SIGNALS:
        number = getattr(signal, name, None)
        if number is not None:
            state._previous[number] = signal.signal(number, handler)
    return state


def wait_for_stop(stop: Callable[[], None], timeout: float | None = None) -> str | None:
    """Block the main thread until a stop signal (or ``timeout`` [s]), then call ``stop()`` once.

    Returns:
        The signal's name (``"SIGTERM"``, ``"SIGHUP"``, ``"SIGINT"``), or ``None`` after ``timeout``.
    """
    stopped = threading.Event()
    signals = install_stop_signals(stopped.set)
    dump_stacks_on_sigusr1()
    try:
        wait_in_main_thread(stopped, timeout)
    finally:
        signals.restore()
        stop()
    return signals.received


WAKE_EVERY = 0.2
"""Seconds between the main thread's wake-ups while it waits for a stop signal."""


def wait_in_main_thread(event: threading.Event, timeout: float | None = None) -> bool:
    """Wait for ``event`` in short slices, so that a signal's Python handler runs within WAKE_EVERY s.

    A signal sent to the process may be taken by any of its threads. Python then only flags it, and
    runs the handler when the main thread next runs Python code: a main thread blocked in one long
    ``event.wait()`` would never run it (a SIGTERM ignored until something else wakes it).

    Returns:
        Whether the event was set (``False`` after ``timeout`` seconds).
    """
    end = None if timeout is None else time.monotonic() + timeout
    while True:
        left = WAKE_EVERY if end is None else min(WAKE_EVERY, end - time.monotonic())
        if left <= 0:
            return event.is_set()
        if event.wait(left):
            return True


def dump_stacks_on_sigusr1() -> None:
    """``kill -USR1 PID`` prints every thread's stack to standard error (for a server that seems stuck).

    No-op where the platform has no SIGUSR1 (Windows).
    """
    number = getattr(signal, "SIGUSR1", None)
    if number is not None and threading.current_thread() is threading.main_thread():
        faulthandler.register(number, all_threads=True, chain=False)


def check_listen_address(host: str, port: int) -> None:
    """Fail at once, in words, for an address the server could never listen on (viser would hang).

    Args:
        host: Name or address to listen on (``127.0.0.1``, ``0.0.0.0``, ``::``, a host name; ``""``: all).
        port: TCP port, 0 (a free one) to 65535.

    Raises:
        ValueError: The port is out of range, or the host does not resolve to an address of this machine.
    """
    if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
        raise ValueError(f"port must be an integer from 0 to 65535 (0: any free port), got {port!r}")
    try:
        infos = socket.getaddrinfo(host or None, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except (socket.gaierror, UnicodeError) as exc:
        raise ValueError(f"cannot listen on host {host!r}: the name does not resolve ({exc})") from exc
    errors = []
    for family, kind, proto, _, address in infos:
        with socket.socket(family, kind, proto) as probe:
            try:
                probe.bind((address[0], 0))  # the address is ours (the port itself is viser's business)
                return
            except OSError as exc:
                errors.append(f"({address[0]}): {exc.strerror or exc}")
    raise ValueError(
        f"cannot listen on host {host!r} {'; '.join(errors)}; use an address of this machine, "
        "e.g. 127.0.0.1 or 0.0.0.0"
    )


def terminate_children(timeout: float = 2.0) -> None:
    """Terminate this process's multiprocessing children; kill those still alive after ``timeout`` [s]."""
    children = multiprocessing.active_children()
    for child in children:
        child.terminate()
    for child in children:
        child.join(timeout)
        if child.is_alive():
            child.kill()
            child.join(timeout)


def end_resource_tracker(timeout: float = 0.5) -> None:
    """End multiprocessing's resource tracker of this process now, once its children are gone, instead of
    leaving it to outlive the process (it exits when every holder of its pipe has closed it, which a
    stray descendant may never do): close this process's end, wait up to ``timeout`` [s], kill it then.

    The tracker (started by the first semaphore or queue of a "spawn" context: a process pool's) unlinks
    what its processes leaked as it ends. Nothing happens if this process has none.
    """
    from multiprocessing import resource_tracker

    tracker = getattr(resource_tracker, "_resource_tracker", None)
    lock = getattr(tracker, "_lock", None)
    if tracker is None or lock is None:
        return
    with lock:
        fd, pid = getattr(tracker, "_fd", None), getattr(tracker, "_pid", None)
        if fd is None or pid is None:
            return
        tracker._fd = tracker._pid = None  # a later use starts a new one, as the standard library does
    os.close(fd)
    end = time.monotonic() + timeout
    while True:
        try:
            if os.waitpid(pid, os.WNOHANG)[0] == pid:
                return
        except ChildProcessError:
            return
        if time.monotonic() > end:
            log.warning("multiprocessing's resource tracker (pid %d) did not end: killing it", pid)
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return
        time.sleep(0.01)


def watch_parent(parent_pid: int) -> None:
    """Worker initializer: exit this process as soon as its parent ``parent_pid`` is gone.

    A daemon thread waits on multiprocessing's parent sentinel (a pipe that closes when the
    parent dies) and checks ``os.getppid()`` every second; when the parent is gone it ends
    the worker with ``os._exit`` (a running computation is abandoned). Ctrl-C in the server's
    terminal reaches the workers too: they ignore it and let the server stop them.
    """
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    parent = multiprocessing.parent_process()
    sentinel = parent.sentinel if parent is not None else None

    def watch() -> None:
        while os.getppid() == parent_pid:
            if sentinel is not None:
                if wait_for_handles([sentinel], timeout=1.0):
                    break
            else:
                threading.Event().wait(1.0)
        os._exit(0)

    threading.Thread(target=watch, name="watch-parent", daemon=True).start()
