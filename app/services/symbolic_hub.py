"""One symbolic pool for every worker of ``jacobian-lab serve --workers N``, in the parent.

The parent keeps a :class:`SymbolicHub`: the server's only symbolic worker processes (one for the
panel's MathML, J⁻¹ and Derive steps, one for downloads, each started on first use, restarted when it
dies, ended when the parent is gone, and stopped at its time and memory limits, as
:class:`~app.services.symbolic_process.WorkerPool` does in a single process). Each worker's
:class:`~app.services.symbolic_service.SymbolicService` keeps its own
bookkeeping (one request per key for its tabs, release, the restart listeners) and sends its
computations to the hub through :class:`~app.services.symbolic_relay.RemotePools`, over a
``multiprocessing`` pipe of its own:

* a request names its kind in :data:`~app.services.symbolic_requests.REQUESTS` ("mathml", "inverse",
  "steps", "export") with its arguments (checked against the kind's types); a worker never sends a
  function, so the parent only ever runs those four;
* requests of the same kind, robot and options from several workers are computed **once**: every
  asker gets the result, and the parent keeps it for later askers (as each worker keeps its own);
  exports are computed per request, as before;
* a worker that no longer wants a result asks the hub to cancel it and waits for the answer (as
  ``Future.cancel`` answers at once in one process): the hub drops that asker, and cancels the
  computation when it was the last one and the computation has not started (a started one is left to
  finish, and the asker still gets it); a worker that ends drops all its askers the same way;
* a symbolic process that dies is restarted by the hub, its computations run once more, and every
  worker is told (``on_restart`` listeners, so every tab sees the notice); the time limit of each
  computation is the worker's, passed with the request.

The messages are tuples pickled by ``multiprocessing`` between the server's own processes (robots
and exceptions are pickled as the process pool pickles them); the parent reads what a worker sends
and a worker reads what the parent sends, nothing else writes to these pipes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import logging
import os
import pickle
import queue
import socket
import threading
from typing import Any

from kinematics import Robot

from .symbolic_relay import GONE
from .symbolic_requests import REQUESTS, Request, SymbolicUnavailable
from .symbolic_service import SymbolicFuture, WorkerPool

__all__ = ["SymbolicHub", "NOT_SHARED"]

log = logging.getLogger(__name__)

NOT_SHARED = ("export",)
"""Kinds computed once per request (a download is asked for once and not kept)."""


class _Link:
    """The parent's end of one worker's pipe: a thread reads its requests, another sends the answers (a
    busy worker never holds up the hub, nor the other workers)."""

    def __init__(self, index: int, conn: Any, hub: SymbolicHub) -> None:
        self.index, self.conn, self.hub = index, conn, hub
        self._outbox: queue.SimpleQueue[tuple | None] = queue.SimpleQueue()
        self.ended = False
        threading.Thread(target=self._read, name=f"symbolic-link-{index}", daemon=True).start()
        threading.Thread(target=self._send, name=f"symbolic-outbox-{index}", daemon=True).start()

    def put(self, message: tuple) -> None:
        self._outbox.put(message)

    def close(self) -> None:
        """Send what is queued, then close the pipe."""
        self._outbox.put(None)

    def _read(self) -> None:
        while True:
            try:
                message = self.conn.recv()
            except (OSError, EOFError, ValueError, pickle.UnpicklingError, AttributeError, ImportError):
                break  # the worker ended (or sent what is not ours to read): it is dropped
            if message == ("bye",):
                self.put(("bye",))
                break
            try:
                self.hub._handle(self, message)
            except Exception:  # one bad message never stops the hub
                log.exception("worker %d: a symbolic request could not be taken", self.index)
        self.hub._gone(self)
        self.close()

    def _send(self) -> None:
        while (message := self._outbox.get()) is not None:
            try:
                self.conn.send(message)
            except (pickle.PicklingError, TypeError, AttributeError) as exc:  # an unpicklable result
                if message[0] == "done":
                    error = SymbolicUnavailable(f"the result could not be sent: {exc}")
                    with contextlib.suppress(OSError, ValueError):
                        self.conn.send(("done", message[1], message[2], error, None))
            except (OSError, ValueError):
                break
        self.ended = True
        _shut(self.conn)
        with contextlib.suppress(OSError):
            self.conn.close()


@dataclasses.dataclass(eq=False)
class _Entry:
    """One computation of the hub and who waits for it: (link, request id) pairs."""

    key: tuple | None
    kind: str
    future: SymbolicFuture
    askers: set[tuple[_Link, int]] = dataclasses.field(default_factory=set)


class SymbolicHub:
    """The parent's symbolic pool, shared by the workers attached to it.

    Args:
        requests: The kinds of computation the workers may ask for (default
            :data:`~app.services.symbolic_requests.REQUESTS`; tests add their own).

    Attributes:
        computed: Computations started so far (a key asked by several workers counts once).
    """

    def __init__(self, requests: dict[str, Request] | None = None) -> None:
        self.requests = dict(REQUESTS if requests is None else requests)
        self.computed = 0
        self._lock = threading.RLock()  # a cancelled future calls back into the hub in the same thread
        self._panel = WorkerPool(self._restarted)
        self._downloads = WorkerPool(self._restarted)
        self._entries: dict[tuple, _Entry] = {}
        self._asks: dict[tuple[_Link, int], _Entry] = {}
        self._links: dict[int, _Link] = {}
        self._closed = False

    @property
    def restarts(self) -> int:
        """How many times a symbolic process died and was restarted."""
        return self._panel.restarts + self._downloads.restarts

    def pids(self) -> list[int]:
        """Process ids of the running symbolic processes."""
        return self._panel.pids() + self._downloads.pids()

    def attach(self, index: int, conn: Any) -> None:
        """Serve worker ``index`` over ``conn`` (the parent's end of its duplex pipe); a worker started
        again replaces its predecessor's link."""
        old = self._links.get(index)
        if old is not None:
            self._gone(old)
            old.close()
        self._links[index] = _Link(index, conn, self)

    def detach(self, index: int) -> None:
        """Worker ``index`` ended: drop what it asked for (computations nobody else wants are cancelled
        if they have not started)."""
        link = self._links.get(index)
        if link is not None:
            self._gone(link)
            link.close()

    def close(self) -> None:
        """End the symbolic processes (running computations are abandoned) and the workers' links."""
        with self._lock:
            self._closed = True
            links = list(self._links.values())
            self._links.clear()
        self._panel.close()
        self._downloads.close()
        for link in links:
            link.close()

    # ------------------------------------------------------------------ what a link hands over
    def _handle(self, link: _Link, message: tuple) -> None:
        op, rid = message[0], message[1]
        if op == "want":
            self._want(link, rid, message[2], message[3])
        elif op == "cancel":
            link.put(("cancelled", rid, self._cancel(link, rid)))
        elif op == "pids":
            link.put(("pids", rid, self.pids()))
        else:
            raise ValueError(f"unknown symbolic request {op!r}")

    def _want(self, link: _Link, rid: int, kind: str, args: tuple) -> None:
        request = self.requests.get(kind) if isinstance(kind, str) else None
        try:
            if request is None:
                raise ValueError(f"unknown kind of symbolic computation {kind!r}")
            if not isinstance(args, tuple):
                raise TypeError("the arguments of a symbolic request are a tuple")
            request.check(args)
        except (TypeError, ValueError) as exc:
            link.put(("done", rid, False, exc, None))
            return
        key = None if kind in NOT_SHARED else _key(kind, request, args)
        started = None
        with self._lock:
            entry = self._entries.get(key) if key is not None else None
            if entry is None or entry.future.cancelled() or _failed(entry.future):
                if self._closed:
                    link.put(("done", rid, False, SymbolicUnavailable(GONE), None))
                    return
                pool = self._downloads if kind in NOT_SHARED else self._panel
                entry = _Entry(key, kind, pool.submit(request.fn, *args))
                if key is not None:
                    self._entries[key] = entry
                self.computed += 1
                started = self.computed
            entry.askers.add((link, rid))
            self._asks[(link, rid)] = entry
            answered = entry.future.done()  # else the callback below (or the first asker's) answers
        if started is not None:
            log.info(
                "symbolic: computing %s of %s for worker %d (computation %d)",
                kind,
                getattr(args[0], "name", "?"),
                link.index,
                started,
            )
            entry.future.add_done_callback(functools.partial(self._settled_future, entry))
        elif answered:
            self._settled(entry)

    def _settled_future(self, entry: _Entry, _: Any) -> None:
        self._settled(entry)

    def _settled(self, entry: _Entry) -> None:
        """Hand ``entry``'s outcome to everyone still waiting for it."""
        with self._lock:
            askers, entry.askers = entry.askers, set()
            for asker in askers:
                self._asks.pop(asker, None)
        future = entry.future
        for link, rid in askers:
            if future.cancelled():
                link.put(("dropped", rid))
            elif (exc := future.exception()) is not None:
                link.put(("done", rid, future.restarted, exc, None))
            else:
                link.put(("done", rid, future.restarted, None, future.result()))

    def _cancel(self, link: _Link, rid: int) -> bool:
        """``link``'s request ``rid`` is no longer wanted: True when the asker is dropped (the computation
        goes on for others, or was cancelled before it started), False when it goes on for this asker
        (it runs, and the result will come)."""
        with self._lock:
            entry = self._asks.pop((link, rid), None)
            if entry is None:
                return False  # answered already (the answer is on its way)
            entry.askers.discard((link, rid))
            if entry.askers:
                return True
            if entry.future.cancel():
                if entry.key is not None and self._entries.get(entry.key) is entry:
                    del self._entries[entry.key]
                return True
            entry.askers.add((link, rid))  # it runs: the asker still gets it
            self._asks[(link, rid)] = entry
            return False

    def _gone(self, link: _Link) -> None:
        with self._lock:
            if self._links.get(link.index) is link:
                del self._links[link.index]
            mine = [asker for asker in self._asks if asker[0] is link]
            for asker in mine:
                entry = self._asks.pop(asker)
                entry.askers.discard(asker)
                if not entry.askers and entry.future.cancel():
                    if entry.key is not None and self._entries.get(entry.key) is entry:
                        del self._entries[entry.key]

    def _restarted(self, notice: str) -> None:
        with self._lock:
            links = list(self._links.values())
        for link in links:
            link.put(("restarted", notice))


def _shut(conn: Any) -> None:
    """Shut the socket under ``conn`` down, so that both ends see it closed at once (closing the
    descriptor alone does not wake a thread of this process blocked reading it); nothing for a
    connection that is no socket (Windows' pipes)."""
    with contextlib.suppress(OSError, ValueError):
        sock = socket.socket(fileno=os.dup(conn.fileno()))
        try:
            sock.shutdown(socket.SHUT_RDWR)
        finally:
            sock.close()


def _key(kind: str, request: Request, args: tuple) -> tuple:
    """What makes two requests the same computation: the kind, the robot's fingerprint and the options
    (not the time limit)."""
    rest = tuple(a for i, a in enumerate(args[1:], 1) if i != request.timeout_at)
    first = args[0].fingerprint() if isinstance(args[0], Robot) else args[0]
    return (kind, first, *rest)


def _failed(future: SymbolicFuture) -> bool:
    return future.done() and not future.cancelled() and future.exception() is not None
