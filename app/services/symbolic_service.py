"""Symbolic J(q) and exports for the panel, computed off the event path and shared by all clients.

Simplifying a 6×6 symbolic Jacobian can take seconds of pure-Python work,
which in a thread would hold the interpreter lock and stall every client's
sliders. :class:`SymbolicService` therefore runs
:func:`kinematics.symbolic.jacobian_mathml` and :func:`kinematics.symbolic.typeset.export.export`
in worker processes (one for the panel's MathML, one for downloads, so a
download never waits behind a long simplification). A worker that dies is
restarted and its computations are retried once; a worker whose server is
gone exits by itself. MathML is cached per (robot, frame, letters) and
the symbolic J⁻¹ per (robot, letters) — a class of students asking for the
Puma's J triggers one computation — and a request nobody waits for any more (every client moved
on to another robot) is cancelled before it starts. The symbolic modules are
imported lazily in the workers and may be missing; then the panel shows a
plain note.

Every computation is bounded by the operating system (:mod:`app.services.symbolic_process`: a
time and memory limit per computation, its process killed and replaced at either), and an arm with
more than :data:`~app.services.symbolic_requests.MAX_SYMBOLIC_JOINTS` joints is not attempted at all:
its future fails at once with :class:`SymbolicNotAttempted` (measured in
``bench/bench_symbolic_size.py``: such a J does not finish within the limits).

Where the computations run is the service's :class:`Pools`: :class:`LocalPools`, its own worker
processes (one server process), or, in a worker of ``jacobian-lab serve --workers N``,
:class:`~app.services.symbolic_relay.RemotePools`, the parent's one pool for every worker. Either way a
computation is named by its kind in :data:`REQUESTS`, never by a function the caller passes.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any, Protocol

from kinematics import Robot

from ..core.downloads import EXPORT_FORMATS
from .symbolic_process import WORKER_RESTARTED, Limits, SymbolicFuture, WorkerPool
from .symbolic_requests import (
    MAX_SYMBOLIC_JOINTS,
    REQUESTS,
    Request,
    SymbolicNotAttempted,
    SymbolicStopped,
    SymbolicUnavailable,
    _export,
)

__all__ = [
    "SymbolicService",
    "SymbolicUnavailable",
    "SymbolicStopped",
    "SymbolicNotAttempted",
    "SymbolicFuture",
    "Limits",
    "WorkerPool",
    "WORKER_RESTARTED",
    "LocalPools",
    "Pools",
    "REQUESTS",
    "Request",
]

log = logging.getLogger(__name__)


class Pools(Protocol):
    """Where :class:`SymbolicService` sends its computations: :class:`LocalPools` (its own worker
    processes) or, in a worker of ``serve --workers N``, :class:`~app.services.symbolic_relay.RemotePools`
    (the one pool of the whole server, in the parent)."""

    @property
    def restarts(self) -> int: ...

    def want(self, key: tuple, kind: str, args: tuple) -> SymbolicFuture:
        """A future of the request ``kind`` (a name of :data:`REQUESTS`) for ``key``."""
        ...

    def export(self, args: tuple) -> SymbolicFuture: ...

    def pids(self) -> list[int]: ...

    def close(self) -> None: ...


class LocalPools:
    """This process's own worker processes: one for the panel's MathML, one for downloads.

    Args:
        on_restart: Called with :data:`WORKER_RESTARTED` after a worker was restarted.
    """

    def __init__(self, on_restart: Callable[[str], None]) -> None:
        self.panel = WorkerPool(on_restart)
        self.downloads = WorkerPool(on_restart)

    @property
    def restarts(self) -> int:
        return self.panel.restarts + self.downloads.restarts

    def want(self, key: tuple, kind: str, args: tuple) -> SymbolicFuture:
        return self.panel.submit(REQUESTS[kind].fn, *args)

    def export(self, args: tuple) -> SymbolicFuture:
        return self.downloads.submit(_export, *args)

    def pids(self) -> list[int]:
        return self.panel.pids() + self.downloads.pids()

    def close(self) -> None:
        self.panel.close()
        self.downloads.close()


class SymbolicService:
    """MathML of J(q) and text exports, computed in worker processes.

    Args:
        timeout: Time limit passed to the symbolic module [s].
        pools: Builds where the computations go from the restart listener (default: :class:`LocalPools`,
            worker processes of this process; a worker of ``serve --workers N`` passes
            :func:`app.services.symbolic_relay.remote_pools`, the parent's one pool).
    """

    def __init__(
        self, timeout: float = 60.0, pools: Callable[[Callable[[str], None]], Pools] | None = None
    ) -> None:
        self.timeout = timeout
        self._lock = threading.Lock()
        self._mathml: dict[tuple, SymbolicFuture] = {}
        self._interest: dict[tuple, int] = {}
        self._listeners: list[Callable[[str], None]] = []
        self.last_notice: str | None = None
        self._pools: Pools = (pools or LocalPools)(self._restarted)

    @property
    def restarts(self) -> int:
        """How many times a worker process died and was restarted."""
        return self._pools.restarts

    def on_restart(self, callback: Callable[[str], None]) -> None:
        """Call ``callback(WORKER_RESTARTED)`` (in a background thread) whenever a worker is restarted."""
        with self._lock:
            self._listeners.append(callback)

    def _restarted(self, notice: str) -> None:
        with self._lock:
            self.last_notice = notice
            listeners = list(self._listeners)
        for callback in listeners:
            callback(notice)

    def worker_pids(self) -> list[int]:
        """Process ids of the running worker processes (for diagnostics and tests)."""
        return self._pools.pids()

    def mathml(self, robot: Robot, frame: str, letters: bool = False) -> SymbolicFuture:
        """A future of the ``<math>`` element of J(q) for ``robot`` in ``frame`` ("base" or "tool").

        ``letters``: the DH lengths and offsets as the course's letters (l₁, a₂, d₄ …), with det J,
        its factors and singular sets under J (``kinematics.symbolic`` with ``symbolic_params=True``).

        Call :meth:`release` with the same arguments when no longer interested. The future
        fails with :class:`SymbolicUnavailable` when the symbolic module is missing, or with
        the module's own error; it is cancelled if every interested client released it
        before it started. If the worker dies, the computation is run once more on a new
        worker (``future.restarted`` is then True).
        """
        key = (robot.fingerprint(), frame, bool(letters))
        return self._want(key, "mathml", robot, frame, float(self.timeout), bool(letters))

    def inverse(self, robot: Robot, letters: bool = False) -> SymbolicFuture:
        """A future of the MathML of J⁻¹ = adj(J) / det J of ``robot``'s square task J (base axes);
        release with :meth:`release_inverse`. Fails with the symbolic module's error for a J that is
        not square or too large."""
        key = (robot.fingerprint(), "inverse", bool(letters))
        return self._want(key, "inverse", robot, bool(letters), float(self.timeout))

    def steps(self, robot: Robot, method: str, letters: bool = False) -> SymbolicFuture:
        """A future of the steps of one derivation of J (``method``: "whitney", "differentiation",
        "propagation" or "force") as (joint, key, caption HTML, MathML) tuples, for the Derive tab
        (``letters``: the DH lengths and offsets as the course's letters, every step, ⁰Tᵢ and the
        tool's included); release with :meth:`release_steps`."""
        key = (robot.fingerprint(), "steps", method, bool(letters))
        return self._want(key, "steps", robot, method, float(self.timeout), bool(letters))

    def release_steps(self, robot: Robot, method: str, letters: bool = False) -> None:
        """One client no longer waits for the steps of ``method`` for ``robot``."""
        self._release((robot.fingerprint(), "steps", method, bool(letters)))

    def _want(self, key: tuple, kind: str, *args: Any) -> SymbolicFuture:
        refused = _not_attempted(args[0])
        if refused is not None:
            return refused
        with self._lock:
            self._interest[key] = self._interest.get(key, 0) + 1
            future = self._mathml.get(key)
            if future is None or future.cancelled() or (future.done() and future.exception() is not None):
                future = self._pools.want(key, kind, args)
                self._mathml[key] = future
            return future

    def release(self, robot: Robot, frame: str, letters: bool = False) -> None:
        """One client no longer waits for J(q) of ``robot`` in ``frame`` (unwanted work is dropped)."""
        self._release((robot.fingerprint(), frame, bool(letters)))

    def release_inverse(self, robot: Robot, letters: bool = False) -> None:
        """One client no longer waits for the symbolic J⁻¹ of ``robot``."""
        self._release((robot.fingerprint(), "inverse", bool(letters)))

    def _release(self, key: tuple) -> None:
        with self._lock:
            left = self._interest.get(key, 0) - 1
            if left > 0:
                self._interest[key] = left
                return
            self._interest.pop(key, None)
            future = self._mathml.get(key)
            if future is not None and not future.done() and future.cancel():
                del self._mathml[key]

    def export(self, robot: Robot, label: str, frame: str) -> SymbolicFuture:
        """A future of (file name, content) of J(q) exported as ``label`` ("LaTeX", "Python" or "JSON")."""
        fmt, ext = EXPORT_FORMATS[label]
        name = f"{robot.name or 'robot'}_J_{frame}.{ext}"
        refused = _not_attempted(robot)
        if refused is not None:
            return refused
        return self._pools.export((robot, fmt, frame, float(self.timeout), name))

    def close(self) -> None:
        """Stop the worker processes (pending computations are abandoned)."""
        self._pools.close()


def _not_attempted(robot: Robot) -> SymbolicFuture | None:
    """A future already failed with :class:`SymbolicNotAttempted` when ``robot`` has more joints than
    are worked out symbolically (nothing is started), else None."""
    if robot.dof <= MAX_SYMBOLIC_JOINTS:
        return None
    future = SymbolicFuture()
    future.set_exception(SymbolicNotAttempted(robot.dof, MAX_SYMBOLIC_JOINTS))
    return future
