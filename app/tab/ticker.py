"""Time for one tab: a ticker that dispatches :class:`~app.core.actions.Step` at a steady rate.

The reducer never reads a clock; this object is the only thing that does.
It runs while the tab's state says ``playing`` (the session starts and
stops it after every change) and is stopped for good when the tab closes.
A test drives the same object without threads through :meth:`Ticker.tick`
with a fake clock.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from ..core.actions import Action, Step

__all__ = ["Ticker"]


class Ticker:
    """Dispatch ``Step(dt)`` every ``1/rate`` seconds while running.

    Args:
        dispatch: Where the steps go (the tab's session).
        rate: Steps per second [Hz].
        clock: Monotonic clock [s] (a fake one in tests).
    """

    def __init__(
        self,
        dispatch: Callable[[Action], None],
        rate: float = 30.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.dispatch = dispatch
        self.period = 1.0 / rate
        self.clock = clock
        self._lock = threading.Lock()
        self._wake = threading.Event()
        self._thread: threading.Thread | None = None
        self._running = False
        self._closed = False
        self._last = 0.0
        self.steps = 0

    @property
    def running(self) -> bool:
        """Whether steps are being dispatched."""
        return self._running

    def start(self) -> None:
        """Start dispatching steps (no-op when running or closed)."""
        with self._lock:
            if self._running or self._closed:
                return
            self._running = True
            self._last = self.clock()
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="jacobian-lab-ticker", daemon=True)
                self._thread.start()
            self._wake.set()

    def stop(self) -> None:
        """Stop dispatching steps (the thread waits, idle)."""
        with self._lock:
            self._running = False

    def close(self) -> None:
        """Stop for good and end the thread (the tab has gone)."""
        with self._lock:
            self._running = False
            self._closed = True
            self._wake.set()

    def tick(self) -> float:
        """Dispatch one step of the time elapsed since the last one (capped at 4 periods); returns dt."""
        now = self.clock()
        dt = min(max(now - self._last, 0.0), 4 * self.period)
        self._last = now
        if dt > 0.0:
            self.steps += 1
            self.dispatch(Step(dt))
        return dt

    def _run(self) -> None:
        while True:
            self._wake.wait()
            with self._lock:
                if self._closed:
                    return
                if not self._running:
                    self._wake.clear()
                    continue
            started = time.monotonic()
            self.tick()
            time.sleep(max(self.period - (time.monotonic() - started), 0.001))
