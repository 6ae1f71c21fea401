"""Symbolic J(q) and exports for the panel, computed off the event path and shared by all clients.

Simplifying a 6×6 symbolic Jacobian can take seconds of pure-Python work,
which in a thread would hold the interpreter lock and stall every client's
sliders. :class:`SymbolicService` therefore runs
:func:`kinematics.symbolic.jacobian_mathml` and :func:`kinematics.export.export`
in worker processes (one for the panel's MathML, one for downloads, so a
download never waits behind a long simplification). MathML is cached per
(robot, frame) — a class of students asking for the Puma's J triggers one
computation — and a request nobody waits for any more (every client moved
on to another robot) is cancelled before it starts. The symbolic modules are
imported lazily in the workers and may be missing; then the panel shows a
plain note.
"""

from __future__ import annotations

import logging
import multiprocessing
import threading
from concurrent.futures import Future, ProcessPoolExecutor

from kinematics import Robot

__all__ = ["SymbolicService", "SymbolicUnavailable", "EXPORT_FORMATS"]

log = logging.getLogger(__name__)

EXPORT_FORMATS = {"LaTeX": ("latex", "tex"), "Python": ("python", "py"), "JSON": ("json", "json")}
"""Download button label → (kinematics.export format, file extension)."""


class SymbolicUnavailable(RuntimeError):
    """The symbolic module (or the export module) is not installed in this build."""


class _Worker:
    """One worker process, started on first use with "spawn" (the server's threads make forking unsafe)."""

    def __init__(self) -> None:
        self._pool: ProcessPoolExecutor | None = None
        self._lock = threading.Lock()

    def submit(self, fn, *args) -> Future:
        with self._lock:
            if self._pool is None:
                self._pool = ProcessPoolExecutor(
                    max_workers=1, mp_context=multiprocessing.get_context("spawn")
                )
            return self._pool.submit(fn, *args)

    def close(self) -> None:
        with self._lock:
            pool, self._pool = self._pool, None
        if pool is not None:
            # A running simplification would hold up interpreter exit: end the worker now.
            for process in list((pool._processes or {}).values()):
                process.terminate()
            pool.shutdown(wait=False, cancel_futures=True)


class SymbolicService:
    """MathML of J(q) and text exports, computed in worker processes.

    Args:
        timeout: Time limit passed to the symbolic module [s].
    """

    def __init__(self, timeout: float = 60.0) -> None:
        self.timeout = timeout
        self._lock = threading.Lock()
        self._mathml: dict[tuple[str, str], Future[str]] = {}
        self._interest: dict[tuple[str, str], int] = {}
        self._panel_worker = _Worker()
        self._export_worker = _Worker()

    def mathml(self, robot: Robot, frame: str) -> Future[str]:
        """A future of the ``<math>`` element of J(q) for ``robot`` in ``frame`` ("base" or "tool").

        Call :meth:`release` with the same arguments when no longer interested. The future
        fails with :class:`SymbolicUnavailable` when the symbolic module is missing, or with
        the module's own error; it is cancelled if every interested client released it
        before it started.
        """
        key = (robot.fingerprint(), frame)
        with self._lock:
            self._interest[key] = self._interest.get(key, 0) + 1
            future = self._mathml.get(key)
            if future is None or future.cancelled() or (future.done() and future.exception() is not None):
                future = self._panel_worker.submit(_mathml, robot, frame, self.timeout)
                self._mathml[key] = future
            return future

    def release(self, robot: Robot, frame: str) -> None:
        """One client no longer waits for J(q) of ``robot`` in ``frame`` (unwanted work is dropped)."""
        key = (robot.fingerprint(), frame)
        with self._lock:
            left = self._interest.get(key, 0) - 1
            if left > 0:
                self._interest[key] = left
                return
            self._interest.pop(key, None)
            future = self._mathml.get(key)
            if future is not None and not future.done() and future.cancel():
                del self._mathml[key]

    def export(self, robot: Robot, label: str, frame: str) -> Future[tuple[str, bytes]]:
        """A future of (file name, content) of J(q) exported as ``label`` ("LaTeX", "Python" or "JSON")."""
        fmt, ext = EXPORT_FORMATS[label]
        name = f"{robot.name or 'robot'}_J_{frame}.{ext}"
        return self._export_worker.submit(_export, robot, fmt, frame, self.timeout, name)

    def close(self) -> None:
        """Stop the worker processes (pending computations are abandoned)."""
        self._panel_worker.close()
        self._export_worker.close()


def _mathml(robot: Robot, frame: str, timeout: float) -> str:
    """In the worker process: the MathML of J(q)."""
    try:
        from kinematics.symbolic import jacobian_mathml
    except ImportError as exc:
        raise SymbolicUnavailable("symbolic form not available (kinematics.symbolic is missing)") from exc
    return jacobian_mathml(robot, frame=frame, timeout=timeout)


def _export(robot: Robot, fmt: str, frame: str, timeout: float, name: str) -> tuple[str, bytes]:
    """In the worker process: J(q) exported by kinematics.export."""
    try:
        from kinematics.export import export
    except ImportError as exc:
        raise SymbolicUnavailable("export not available (kinematics.export is missing)") from exc
    return name, export(robot, fmt, frame=frame, timeout=timeout).encode("utf-8")
