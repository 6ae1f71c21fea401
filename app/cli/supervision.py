"""The supervising parent of ``jacobian-lab serve --workers N``: it starts the worker processes, hands
each its listening socket (:mod:`app.cli.sockets`), restarts a worker that dies, relays the room's
messages (classroom mode), keeps the one symbolic pool of every worker and stops them all
(see :mod:`app.cli.workers` for the whole picture)."""

from __future__ import annotations

import dataclasses
import logging
import multiprocessing
import os
import queue
import socket
import sys
import threading
import time
from multiprocessing.connection import Connection
from multiprocessing.connection import wait as wait_for_handles
from typing import Any

from app.services.lifecycle import (
    dump_stacks_on_sigusr1,
    end_resource_tracker,
    install_stop_signals,
    wait_in_main_thread,
    watch_parent,
)
from app.services.room import RoomHub
from app.services.state_codec import dumps, loads
from app.services.symbolic_hub import SymbolicHub
from app.services.symbolic_relay import remote_service

from .sockets import worker_socket

__all__ = ["WORKER_CAP", "READY_TIMEOUT", "STOP_GRACE", "KILL_WAIT", "WorkerPool"]

log = logging.getLogger("app.cli.workers")  # the name the server's log has always shown

WORKER_CAP = 16
"""Most worker processes ``--workers`` starts (each holds the app and viser; the symbolic pool is shared)."""

READY_TIMEOUT = 60.0
"""Seconds a worker may take to import the app and start serving before the start is given up."""

STOP_GRACE = 2.0
"""Seconds the workers and the symbolic processes get to end after SIGTERM, all together, before those
left are killed (the whole stop stays under 3 s)."""

KILL_WAIT = 0.5
"""Seconds to wait for a killed process (or the resource tracker) to be gone."""


class _Outbox:
    """The parent's messages to one worker's room pipe, sent by a thread of their own (a busy worker
    never holds up the parent's loop, nor the other workers)."""

    def __init__(self, conn: Connection) -> None:
        self.conn = conn
        self._queue: queue.SimpleQueue[bytes | None] = queue.SimpleQueue()
        threading.Thread(target=self._send, name="room-outbox", daemon=True).start()

    def put(self, raw: bytes) -> None:
        self._queue.put(raw)

    def close(self) -> None:
        self._queue.put(None)

    def _send(self) -> None:
        while (raw := self._queue.get()) is not None:
            try:
                self.conn.send_bytes(raw)
            except (OSError, ValueError):
                break
        self.conn.close()


@dataclasses.dataclass
class _Worker:
    index: int
    process: Any  # multiprocessing.Process (spawn context)
    ready: Connection
    started: float
    port: int = 0
    room: Connection | None = None  # the parent's end of the worker's room pipe (classroom mode)
    outbox: _Outbox | None = None


def _worker_main(
    index: int,
    sock: socket.socket,
    lab_options: dict[str, Any],
    ready: Connection,
    parent_pid: int,
    symbolic: Connection,
    room: Connection | None = None,
) -> None:
    """One worker: a whole Lab accepting on its own socket in ``sock``'s group (or on ``sock``, shared:
    :func:`~app.cli.sockets.worker_socket`), until SIGTERM or its parent is gone."""
    watch_parent(parent_pid)  # ends this worker if the parent is killed outright; ignores Ctrl-C
    logging.basicConfig(level=logging.INFO, format=f"%(levelname)s worker {index} %(name)s: %(message)s")
    logging.getLogger("websockets").setLevel(logging.WARNING)
    sys.setswitchinterval(0.001)
    from app.server import Lab  # the worker's own import: the parent never builds a Lab

    # Its own socket, made only now; it listens once viser's server serves (tabs that come before the
    # Lab is built are told to try again), and its share goes to the other workers once it is gone.
    own = worker_socket(sock)
    if own is not sock:
        sock.close()
    lab = Lab(listen_socket=own, room_pipe=room, symbolic=remote_service(symbolic), **lab_options)
    stop = threading.Event()
    signals = install_stop_signals(stop.set)
    ready.send(("ready", os.getpid(), lab.port))
    ready.close()
    dump_stacks_on_sigusr1()
    try:
        wait_in_main_thread(stop)
    finally:
        signals.restore()
        lab.stop()
    # Stopped: end now. The interpreter's own shutdown (its daemon threads and a heap of 60 tabs) took
    # about a second more, longer on a busy machine, and nothing of it is needed.
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


class WorkerPool:
    """N worker processes serving one address, restarted when they die.

    Args:
        sock: The parent's socket on the address (see :func:`~app.cli.sockets.port_socket`).
        workers: How many worker processes.
        lab_options: Keyword arguments of :class:`app.server.Lab` (robot, urdf, host, chain …).
        presenter_token: Classroom mode across the workers (the parent's :class:`RoomHub` keeps it).
    """

    def __init__(
        self,
        sock: socket.socket,
        workers: int,
        lab_options: dict[str, Any],
        presenter_token: str | None = None,
    ) -> None:
        if not 1 <= workers <= WORKER_CAP:
            raise ValueError(f"workers must be 1 to {WORKER_CAP}, got {workers}")
        self.sock = sock
        self.count = workers
        self.lab_options = dict(lab_options)
        self.context = multiprocessing.get_context("spawn")
        self.workers: dict[int, _Worker] = {}
        self.restarts = 0
        self.hub = RoomHub(presenter_token) if presenter_token else None
        self.symbolic = SymbolicHub()  # one symbolic pool for every worker

    @property
    def port(self) -> int:
        return int(self.sock.getsockname()[1])

    def start(self) -> None:
        """Start every worker and wait until each serves (or raise, stopping those started)."""
        for index in range(1, self.count + 1):
            self._spawn(index)
        try:
            for worker in list(self.workers.values()):
                self._wait_ready(worker)
            for worker in list(self.workers.values()):
                self._room_started(worker)
        except BaseException:
            self.stop()
            raise

    def _spawn(self, index: int) -> _Worker:
        mine, theirs = self.context.Pipe(duplex=False)
        room, their_room = self.context.Pipe(duplex=True) if self.hub is not None else (None, None)
        symbolic, their_symbolic = self.context.Pipe(duplex=True)
        process = self.context.Process(
            target=_worker_main,
            args=(index, self.sock, self.lab_options, theirs, os.getpid(), their_symbolic, their_room),
            name=f"jacobian-lab-worker-{index}",
        )
        process.start()
        for end in filter(None, (theirs, their_symbolic, their_room)):
            end.close()
        self.symbolic.attach(index, symbolic)
        worker = _Worker(index, process, mine, time.monotonic(), room=room)
        if room is not None:
            worker.outbox = _Outbox(room)
        self.workers[index] = worker
        return worker

    def _wait_ready(self, worker: _Worker) -> None:
        ready = wait_for_handles([worker.ready, worker.process.sentinel], timeout=READY_TIMEOUT)
        if worker.ready in ready:
            try:
                self._take_ready(worker)
                return
            except EOFError:
                pass
        code = worker.process.exitcode
        raise RuntimeError(
            f"worker {worker.index} did not start (exit status {code}); its error is printed above"
            if code is not None
            else f"worker {worker.index} did not start within {READY_TIMEOUT:.0f} s"
        )

    def _take_ready(self, worker: _Worker) -> None:
        _, pid, port = worker.ready.recv()
        worker.port = int(port)
        log.info("worker %d (pid %d) serving", worker.index, pid)

    def pids(self) -> list[int]:
        return [w.process.pid for w in self.workers.values() if w.process.pid is not None]

    # ------------------------------------------------------------------ the room (classroom mode)
    def _room_started(self, worker: _Worker) -> None:
        if self.hub is not None:
            self._send(self.hub.started(worker.index))

    def _send(self, outgoing: list[tuple[int, dict[str, Any]]]) -> None:
        encoded: dict[int, bytes] = {}  # a message for several workers is encoded once
        for index, message in outgoing:
            worker = self.workers.get(index)
            if worker is not None and worker.outbox is not None:
                raw = encoded.get(id(message))
                if raw is None:
                    raw = encoded[id(message)] = dumps(message)
                worker.outbox.put(raw)

    def _room_message(self, worker: _Worker) -> None:
        """Take what ``worker`` said to the room (all it has sent); a closed pipe is left to the
        sentinel (the worker is ending)."""
        assert self.hub is not None and worker.room is not None
        try:
            while worker.room.poll():
                raw = worker.room.recv_bytes()
                try:
                    self._send(self.hub.handle(worker.index, loads(raw)))
                except Exception:  # one bad message never stops the parent
                    log.exception("worker %d: a room message could not be taken", worker.index)
        except (OSError, EOFError):
            worker.room = None

    def supervise(self, stop_requested: Any) -> None:
        """Until ``stop_requested()``: relay the room's messages (classroom mode) and restart every
        worker that dies (one restart a second at most). Nothing here waits for one worker: a worker
        starting again is watched like the others, so the room goes on meanwhile."""
        starting: set[int] = set()  # restarted, not serving yet
        while not stop_requested():
            handles: dict[int, tuple[str, _Worker, Any]] = {}
            for worker in self.workers.values():
                handles[id(worker.process.sentinel)] = ("ended", worker, worker.process.sentinel)
                if worker.index in starting:
                    handles[id(worker.ready)] = ("ready", worker, worker.ready)
                elif worker.room is not None:
                    handles[id(worker.room)] = ("room", worker, worker.room)
            for handle in wait_for_handles([h for _, _, h in handles.values()], timeout=0.25):
                kind, worker, _ = handles[id(handle)]
                if kind == "room":
                    self._room_message(worker)
                elif kind == "ready" and worker.process.is_alive():
                    starting.discard(worker.index)
                    try:
                        self._take_ready(worker)
                        self._room_started(worker)
                    except (EOFError, OSError, ValueError):
                        pass  # it is ending: its sentinel says so
            now = time.monotonic()
            for index, worker in list(self.workers.items()):
                if worker.index in starting and now - worker.started > READY_TIMEOUT:
                    log.error("worker %d did not start within %.0f s: killing it", index, READY_TIMEOUT)
                    worker.process.kill()
                if worker.process.is_alive() or stop_requested():
                    continue
                log.warning(
                    "worker %d (pid %s) ended with status %s: starting it again; its tabs reconnect",
                    index,
                    worker.process.pid,
                    worker.process.exitcode,
                )
                worker.process.join(0)
                worker.ready.close()
                self._close_room(worker)
                self.symbolic.detach(index)
                # A worker that dies at once, again and again, must not spin the parent.
                if now - worker.started < 1.0:
                    time.sleep(1.0)
                self.restarts += 1
                self._spawn(index)
                starting.add(index)

    def _close_room(self, worker: _Worker) -> None:
        """``worker`` ended: the hub forgets its followers (and its presenter, who may come back)."""
        if worker.outbox is not None:
            worker.outbox.close()
            worker.outbox = None
        worker.room = None
        if self.hub is not None:
            self._send(self.hub.gone(worker.index))

    def stop(self) -> None:
        """End the workers and the symbolic processes together: SIGTERM to each, one deadline of
        :data:`STOP_GRACE` s for all, a kill for those left; then the resource tracker."""
        end = time.monotonic() + STOP_GRACE
        workers = list(self.workers.values())
        for worker in workers:
            if worker.process.is_alive():
                worker.process.terminate()
        # The symbolic processes end meanwhile (the hub refuses work first: nothing is started again).
        closing = threading.Thread(target=self.symbolic.close, name="symbolic-close", daemon=True)
        closing.start()
        waiting = [w.process.sentinel for w in workers if w.process.is_alive()]
        while waiting and (left := end - time.monotonic()) > 0:
            done = wait_for_handles(waiting, timeout=left)
            waiting = [h for h in waiting if h not in done]
        closing.join(max(0.0, end - time.monotonic()))
        children = multiprocessing.active_children()  # the workers and the symbolic processes
        ending = wait_for_handles([c.sentinel for c in children], timeout=0)  # exiting, not reaped yet
        for child in children:
            if child.sentinel not in ending:
                log.warning("%s did not stop in %.0f s: killing it", child.name, STOP_GRACE)
                child.kill()
        for child in children:
            child.join(KILL_WAIT)
        for worker in workers:
            worker.ready.close()
            if worker.outbox is not None:
                worker.outbox.close()
        self.workers.clear()
        closing.join(KILL_WAIT)
        self.sock.close()
        end_resource_tracker(KILL_WAIT)
