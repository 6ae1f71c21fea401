"""One symbolic worker process that the server can always stop: a time and memory limit on every
computation, enforced by the operating system and a watchdog, not by the computation's cooperation.

SymPy checks its time limit between steps, and one step (a ``simplify`` of a 24-joint arm's J) can
run for minutes while its memory grows by gigabytes. :class:`WorkerPool` therefore runs one
computation at a time in a process of its own ("spawn") and, from a watchdog thread of the server:

* kills the process when the computation has run longer than :attr:`Limits.seconds`, or when the
  process's resident memory (``/proc/PID/statm``) is more than :attr:`Limits.memory_mb` above what
  it held before the computation; the computation fails with :class:`SymbolicStopped` (which says
  which limit and its figure), and a new process takes the next computation;
* sets the process's address space limit (``RLIMIT_AS``, Linux and macOS) to what it has after
  importing the symbolic modules plus :attr:`Limits.address_mb`: an allocation past it fails inside
  the process (``MemoryError``, reported as :class:`SymbolicStopped` too) even between two polls.

A process that dies by itself (killed from outside, out of memory) is restarted and the computation
it was running is run once more; ``on_restart(WORKER_RESTARTED)`` is called. A process stopped at a
limit is replaced without that notice (only the asker is told, by the future's error). The worker
exits by itself when its server is gone (:func:`app.services.lifecycle.watch_parent`).

The limits come from :meth:`Limits.from_env` (``JACOBIAN_LAB_SYMBOLIC_SECONDS``,
``JACOBIAN_LAB_SYMBOLIC_MEMORY_MB``: tests and small machines set them), else the defaults.
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import logging
import multiprocessing
import os
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future, InvalidStateError
from typing import Any

from .lifecycle import watch_parent
from .symbolic_requests import SymbolicStopped, SymbolicUnavailable

__all__ = ["Limits", "SymbolicFuture", "WorkerPool", "WORKER_RESTARTED", "resident_bytes"]

log = logging.getLogger(__name__)

WORKER_RESTARTED = "the symbolic worker stopped and was restarted"
"""The notice given to restart listeners when a worker died and was restarted."""

_POLL = 0.1
"""How often the watchdog reads the process's memory [s] (the 24-joint J grew ~25 MB/s)."""

_READY_SECONDS = 120.0
"""How long a new process may take to import the symbolic modules [s] (a few on an idle machine)."""


class _Died(Exception):
    """The worker process died (or never became ready)."""


@dataclasses.dataclass(frozen=True)
class Limits:
    """What one symbolic computation may use before its process is stopped.

    Attributes:
        seconds: Wall-clock time of one computation [s] (the tab's own 60 s limit plus a margin for
            the step SymPy was in when it ran out).
        memory_mb: Resident memory the process may gain during one computation [MB].
        address_mb: Address space the process may gain after its imports (``RLIMIT_AS``) [MB]:
            the backstop between two polls (Python's allocator reserves more than it touches).
    """

    seconds: float = 75.0
    memory_mb: float = 110.0
    address_mb: float = 600.0

    @classmethod
    def from_env(cls) -> Limits:
        """The defaults, overridden by ``JACOBIAN_LAB_SYMBOLIC_SECONDS`` and
        ``JACOBIAN_LAB_SYMBOLIC_MEMORY_MB`` (the address limit scales with the memory limit)."""
        seconds = float(os.environ.get("JACOBIAN_LAB_SYMBOLIC_SECONDS", cls.seconds))
        memory = float(os.environ.get("JACOBIAN_LAB_SYMBOLIC_MEMORY_MB", cls.memory_mb))
        return cls(seconds, memory, cls.address_mb * memory / cls.memory_mb)


def resident_bytes(pid: int) -> int | None:
    """Resident memory of process ``pid`` [bytes] from ``/proc`` (None where there is none)."""
    try:
        with open(f"/proc/{pid}/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return None


class SymbolicFuture(Future[Any]):
    """A future of a worker computation, run once more on a new worker if its worker died.

    Attributes:
        restarted: True when this computation's first worker stopped (e.g. was killed) and the
            computation was run again on a restarted worker.
    """

    def __init__(self) -> None:
        super().__init__()
        self.restarted = False


# ---------------------------------------------------------------------------- in the worker process
def _serve(conn: Any, parent_pid: int, address_bytes: int) -> None:
    """The worker's loop: import the symbolic modules, limit the address space, then run what comes."""
    watch_parent(parent_pid)
    with contextlib.suppress(ImportError):
        import kinematics.symbolic  # noqa: F401  (the limit counts from what the imports take)
    _limit_address_space(address_bytes)
    conn.send(("ready",))
    while True:
        try:
            task, fn, args = conn.recv()
        except (EOFError, OSError):
            return
        try:
            answer: tuple = (task, True, fn(*args))
        except MemoryError:
            answer = (task, False, MemoryError())
        except BaseException as exc:  # noqa: BLE001  (sent to the asker, as a process pool does)
            answer = (task, False, exc)
        try:
            conn.send(answer)
        except Exception as exc:  # an unpicklable result or error
            conn.send((task, False, SymbolicUnavailable(f"the result could not be sent: {exc}")))
        if isinstance(answer[2], MemoryError):
            return  # the heap may be in pieces: a new process takes the next computation


def _limit_address_space(extra: int) -> None:
    try:
        import resource
    except ImportError:  # Windows: the watchdog's time and memory polls only
        return
    size = _address_bytes()
    if size is None or extra <= 0:
        return
    with contextlib.suppress(ValueError, OSError):
        _, hard = resource.getrlimit(resource.RLIMIT_AS)
        soft = size + extra
        resource.setrlimit(resource.RLIMIT_AS, (soft if hard < 0 else min(soft, hard), hard))


def _address_bytes() -> int | None:
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return None


# ---------------------------------------------------------------------------- in the server
@dataclasses.dataclass(eq=False)
class _Task:
    future: SymbolicFuture
    fn: Callable[..., Any]
    args: tuple
    retry: bool = True


class _Process:
    """One running worker process and the server's end of its pipe."""

    def __init__(self, limits: Limits) -> None:
        ctx = multiprocessing.get_context("spawn")
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(
            target=_serve, args=(child, os.getpid(), int(limits.address_mb * 1e6)), daemon=True
        )
        self.process.start()
        child.close()
        self.ready_bytes: int | None = None

    def wait_ready(self, seconds: float) -> bool:
        """Wait until the process has imported the symbolic modules (its resident memory then is the
        base its limit counts from); False if it died or took longer than ``seconds``."""
        end = time.monotonic() + seconds
        try:
            while not self.conn.poll(_POLL):
                if not self.process.is_alive() or time.monotonic() > end:
                    return False
            self.conn.recv()
        except (EOFError, OSError):
            return False
        self.ready_bytes = resident_bytes(self.process.pid or 0)
        return True

    def end(self) -> None:
        with contextlib.suppress(Exception):
            self.process.kill()
        self.process.join(5.0)
        with contextlib.suppress(OSError):
            self.conn.close()


class WorkerPool:
    """One worker process, started on first use, whose computations are bounded (see the module).

    Args:
        on_restart: Called with :data:`WORKER_RESTARTED` after the process died and was restarted, in
            a new thread (so it may take any lock).
        limits: The limits of each computation (default :meth:`Limits.from_env`).

    Attributes:
        restarts: How many times a process that died was replaced.
        stopped: How many computations were stopped at a limit (their process replaced).
    """

    def __init__(self, on_restart: Callable[[str], None] | None = None, limits: Limits | None = None) -> None:
        self.limits = limits or Limits.from_env()
        self.restarts = 0
        self.stopped = 0
        self._on_restart = on_restart
        self._queue: collections.deque[_Task] = collections.deque()
        self._cond = threading.Condition()
        self._process: _Process | None = None
        self._died = False
        self._closed = False
        self._thread: threading.Thread | None = None

    def submit(self, fn: Callable[..., Any], *args: Any) -> SymbolicFuture:
        """``fn(*args)`` in the worker; ``fn`` must be importable by name (a module-level function).
        Cancelling the future before the computation started drops it."""
        future = SymbolicFuture()
        with self._cond:
            if self._closed:
                raise RuntimeError("the symbolic worker pool was closed")
            self._queue.append(_Task(future, fn, args))
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="symbolic-watchdog", daemon=True)
                self._thread.start()
            self._cond.notify()
        return future

    def pids(self) -> list[int]:
        """Process id of the running worker (none before the first computation)."""
        with self._cond:
            process = self._process
        pid = process.process.pid if process is not None else None
        return [pid] if pid is not None else []

    def close(self) -> None:
        """End the worker now (a running computation fails) and refuse further work."""
        with self._cond:
            self._closed = True
            process, self._process = self._process, None
            pending = list(self._queue)
            self._queue.clear()
            self._cond.notify_all()
        if process is not None:
            process.end()
        for task in pending:
            task.future.cancel()

    # ------------------------------------------------------------------ the watchdog thread
    def _run(self) -> None:
        while True:
            with self._cond:
                while not self._queue and not self._closed:
                    self._cond.wait()
                if self._closed:
                    return
                task = self._queue.popleft()
            if task.retry and not task.future.set_running_or_notify_cancel():
                continue  # cancelled before it started
            try:
                self._one(task)
            except Exception as exc:  # never leave an asker waiting
                log.exception("the symbolic watchdog failed")
                _fail(task.future, SymbolicUnavailable(f"the symbolic worker failed: {exc}"))

    def _started(self, task: _Task) -> _Process | None:
        """The running process, started (or restarted after a death: then ``task`` is marked
        ``restarted``) if need be; None once closed."""
        with self._cond:
            if self._closed:
                return None
            if self._process is not None and self._process.process.is_alive():
                return self._process
            old, self._process = self._process, None
        restarted = old is not None or self._died
        if old is not None:
            old.end()
        process = _Process(self.limits)
        if not process.wait_ready(_READY_SECONDS):
            process.end()
            raise _Died
        with self._cond:
            if self._closed:
                process.end()
                return None
            self._process, self._died = process, False
            if restarted:
                self.restarts += 1
                task.future.restarted = True
        if restarted:
            log.warning("%s (restart %d)", WORKER_RESTARTED, self.restarts)
            if self._on_restart is not None:  # in a thread of its own: the listener may take any lock
                threading.Thread(target=self._notify, name="symbolic-restart", daemon=True).start()
        return process

    def _one(self, task: _Task) -> None:
        """Run ``task`` in the process and watch it until it answers, dies or passes a limit."""
        try:
            process = self._started(task)
        except _Died:
            self._lost(None, task)
            return
        if process is None:
            _fail(task.future, SymbolicUnavailable("the symbolic worker pool was closed"))
            return
        pid, limits = process.process.pid or 0, self.limits
        allowed = None if process.ready_bytes is None else process.ready_bytes + limits.memory_mb * 1e6
        start = time.monotonic()
        try:
            process.conn.send((id(task), task.fn, task.args))
            while not process.conn.poll(_POLL):
                if not process.process.is_alive():
                    raise EOFError
                resident = resident_bytes(pid)
                if allowed is not None and resident is not None and resident > allowed:
                    self._stop(process, task, SymbolicStopped("memory", limits.seconds, limits.memory_mb))
                    return
                if time.monotonic() - start > limits.seconds:
                    self._stop(process, task, SymbolicStopped("time", limits.seconds, limits.memory_mb))
                    return
            _, ok, value = process.conn.recv()
        except (EOFError, OSError):
            self._lost(process, task)
            return
        if isinstance(value, MemoryError):  # the address space limit, inside the process
            self._stop(process, task, SymbolicStopped("memory", limits.seconds, limits.memory_mb))
            return
        resident = resident_bytes(pid)
        if allowed is not None and resident is not None and resident > allowed - limits.memory_mb * 5e5:
            self._recycle(process)  # its caches took half the allowance: the next computation starts afresh
        if ok:
            with contextlib.suppress(InvalidStateError):
                task.future.set_result(value)
        else:
            _fail(task.future, value)

    def _recycle(self, process: _Process) -> None:
        with self._cond:
            if self._process is process:
                self._process = None
        process.end()

    def _stop(self, process: _Process, task: _Task, error: SymbolicStopped) -> None:
        """``task`` passed a limit: end its process (the next computation gets a new one) and say so."""
        with self._cond:
            if self._process is process:
                self._process = None
            self.stopped += 1
        process.end()
        log.warning("symbolic computation stopped: %s", error)
        _fail(task.future, error)

    def _lost(self, process: _Process | None, task: _Task) -> None:
        """The process died under ``task``: run it once more on a new process, or fail the second time."""
        with self._cond:
            closed = self._closed
            self._died = True
            if process is not None and self._process is process:
                self._process = None
        if process is not None:
            process.end()
        if closed:
            _fail(task.future, SymbolicUnavailable("the symbolic worker pool was closed"))
        elif task.retry:
            task.future.restarted, task.retry = True, False
            with self._cond:
                self._queue.appendleft(task)
        else:
            twice = "the symbolic worker stopped twice during this computation"
            _fail(task.future, SymbolicUnavailable(twice))

    def _notify(self) -> None:
        try:
            self._on_restart(WORKER_RESTARTED)  # type: ignore[misc]
        except Exception:
            log.exception("a restart listener failed")


def _fail(future: Future, exc: BaseException) -> None:
    with contextlib.suppress(InvalidStateError):  # cancelled by its last interested client
        future.set_exception(exc)
