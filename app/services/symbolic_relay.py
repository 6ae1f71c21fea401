"""A worker's end of the one symbolic pool of ``jacobian-lab serve --workers N``.

:class:`RemotePools` is what a worker's :class:`~app.services.symbolic_service.SymbolicService` sends
its computations to: a ``multiprocessing`` pipe to the parent's
:class:`~app.services.symbolic_hub.SymbolicHub` (which computes a key once for every worker, see
there). A request is a kind of :data:`~app.services.symbolic_requests.REQUESTS` with its arguments;
a cancellation waits for the hub's answer, as ``Future.cancel`` answers at once in one process; the
hub's restart notices reach the service's listeners. When the pipe closes (the server stops), what
is pending fails with :data:`GONE`.
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import logging
import pickle
import queue
import threading
from collections.abc import Callable
from concurrent.futures import Future, InvalidStateError
from typing import Any

from .symbolic_requests import SymbolicUnavailable
from .symbolic_service import SymbolicFuture, SymbolicService

__all__ = ["RemotePools", "RemoteFuture", "remote_pools", "remote_service", "CANCEL_TIMEOUT", "GONE"]

log = logging.getLogger(__name__)

CANCEL_TIMEOUT = 5.0
"""Seconds a worker waits for the hub's answer to a cancellation (or a list of process ids)."""

GONE = "the server's symbolic pool is gone (the server is stopping)"
"""The error of a worker's pending computations when its pipe to the parent closed."""


class RemoteFuture(SymbolicFuture):
    """A computation asked of the parent's hub; :meth:`cancel` asks the hub (see
    :class:`~app.services.symbolic_hub.SymbolicHub`)."""

    def __init__(self, pools: RemotePools, rid: int) -> None:
        super().__init__()
        self._pools, self._rid = pools, rid

    def cancel(self) -> bool:
        """Cancel unless the computation already runs for this worker (then it is left to finish)."""
        if self.cancelled():
            return True
        if self.done() or not self._pools._cancel(self._rid):
            return False
        return super().cancel()


class RemotePools:
    """A worker's end of its pipe to the parent's :class:`~app.services.symbolic_hub.SymbolicHub` (the
    :class:`~app.services.symbolic_service.Pools` of a worker of ``serve --workers N``).

    A reader thread takes the hub's messages (answers to a cancellation wake their caller at once);
    results and restart notices are handed on by a second thread, so a future's callbacks may ask the
    hub again.

    Args:
        conn: The worker's end of a duplex ``multiprocessing`` pipe.
        on_restart: Called with the notice when the hub restarted a symbolic process.
    """

    def __init__(self, conn: Any, on_restart: Callable[[str], None]) -> None:
        self.conn = conn
        self.restarts = 0
        self.closed = False
        self._on_restart = on_restart
        self._ids = itertools.count(1)
        self._lock = threading.Lock()
        self._send_lock = threading.Lock()
        self._futures: dict[int, RemoteFuture] = {}
        self._answers: dict[int, tuple[threading.Event, list[Any]]] = {}
        self._deliveries: queue.SimpleQueue[Callable[[], None] | None] = queue.SimpleQueue()
        self._reader = threading.Thread(target=self._read, name="symbolic-channel", daemon=True)
        self._reader.start()
        threading.Thread(target=self._deliver, name="symbolic-results", daemon=True).start()

    def want(self, key: tuple, kind: str, args: tuple) -> SymbolicFuture:
        return self._submit(kind, args)

    def export(self, args: tuple) -> SymbolicFuture:
        return self._submit("export", args)

    def pids(self) -> list[int]:
        """The hub's symbolic processes (asked of the parent)."""
        answer = self._ask("pids")
        return list(answer[0]) if answer else []

    def close(self) -> None:
        """Leave the hub (what this worker asked for and nobody else wants is dropped there)."""
        with self._lock:
            if self.closed:
                return
            self.closed = True
        self._send(("bye",))
        self._reader.join(CANCEL_TIMEOUT)
        with contextlib.suppress(OSError):
            self.conn.close()

    def _submit(self, kind: str, args: tuple) -> SymbolicFuture:
        with self._lock:
            if self.closed:
                raise RuntimeError("the symbolic worker pool was closed")
            rid = next(self._ids)
            future = self._futures[rid] = RemoteFuture(self, rid)
        if not self._send(("want", rid, kind, args)):
            with self._lock:
                self._futures.pop(rid, None)
            future.set_exception(SymbolicUnavailable(GONE))
        return future

    def _cancel(self, rid: int) -> bool:
        answer = self._ask("cancel", rid)
        ok = bool(answer[0]) if answer is not None else True  # no hub: nothing will come
        if ok:
            with self._lock:
                self._futures.pop(rid, None)
        return ok

    def _ask(self, op: str, rid: int | None = None) -> tuple[Any] | None:
        """Send ``(op, rid)`` and wait for the hub's answer: ``(value,)``, or None without one."""
        event, box = threading.Event(), list[Any]()
        with self._lock:
            if rid is None:
                rid = next(self._ids)
            self._answers[rid] = (event, box)
        if self._send((op, rid)):
            event.wait(CANCEL_TIMEOUT)
        with self._lock:
            self._answers.pop(rid, None)
        return (box[0],) if box else None

    def _send(self, message: tuple) -> bool:
        try:
            with self._send_lock:
                self.conn.send(message)
            return True
        except (OSError, ValueError, EOFError):
            return False

    def _read(self) -> None:
        while True:
            try:
                message = self.conn.recv()
            except (OSError, EOFError, ValueError, pickle.UnpicklingError):
                break
            op = message[0]
            if op == "bye":
                break
            if op == "restarted":
                self.restarts += 1
                notice = message[1]
                self._deliveries.put(functools.partial(self._on_restart, notice))
                continue
            with self._lock:
                if op in ("cancelled", "pids"):
                    waiting = self._answers.get(message[1])
                    future = None
                else:
                    waiting, future = None, self._futures.pop(message[1], None)
            if waiting is not None:
                waiting[1].append(message[2])
                waiting[0].set()
            elif future is not None:
                self._deliveries.put(functools.partial(_settle, future, message))
        with self._lock:
            self.closed = True
            futures, self._futures = list(self._futures.values()), {}
            answers = list(self._answers.values())
        for event, _ in answers:
            event.set()
        for future in futures:
            gone = ("done", 0, False, SymbolicUnavailable(GONE), None)
            self._deliveries.put(functools.partial(_settle, future, gone))
        self._deliveries.put(None)

    def _deliver(self) -> None:
        while (job := self._deliveries.get()) is not None:
            try:
                job()
            except Exception:
                log.exception("a symbolic result's listener failed")


def _settle(future: RemoteFuture, message: tuple) -> None:
    """Complete ``future`` with the hub's message ("done" with its outcome, or "dropped")."""
    if message[0] == "dropped":
        Future.cancel(future)
        return
    with contextlib.suppress(InvalidStateError):  # cancelled meanwhile by its last interested tab
        _, _, restarted, exc, *value = message
        future.restarted = bool(restarted)
        if exc is not None:
            future.set_exception(exc)
        else:
            future.set_result(value[0])


def remote_pools(conn: Any) -> Callable[[Callable[[str], None]], RemotePools]:
    """The ``pools`` of a worker's :class:`~app.services.symbolic_service.SymbolicService`: the parent's
    hub over ``conn``."""
    return lambda on_restart: RemotePools(conn, on_restart)


def remote_service(conn: Any, timeout: float = 60.0) -> SymbolicService:
    """A worker's symbolic service whose computations go to the parent's hub over ``conn``."""
    return SymbolicService(timeout, pools=remote_pools(conn))
