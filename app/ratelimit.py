"""Rate limits for one browser tab's messages: a token bucket, and a queue that keeps only the latest state.

Used by :func:`app.viser_adapter.install_message_limits`. Pure bookkeeping (no viser,
no asyncio), so it is tested on its own with a fake clock.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any

__all__ = ["TokenBucket", "LeakyCounter", "LatestFirstQueue"]


class TokenBucket:
    """``burst`` tokens, refilled at ``rate`` per second; each message takes one.

    Args:
        rate: Steady rate [1/s].
        burst: Capacity (also the initial number of tokens).
        clock: Time source [s] (``time.monotonic`` by default).
    """

    def __init__(self, rate: float, burst: int, clock: Callable[[], float] = time.monotonic) -> None:
        self.rate, self.burst, self.clock = rate, float(burst), clock
        self.tokens, self.stamp = float(burst), clock()

    def _refill(self) -> None:
        now = self.clock()
        self.tokens = min(self.burst, self.tokens + (now - self.stamp) * self.rate)
        self.stamp = now

    def take(self) -> bool:
        """Take one token if there is one."""
        self._refill()
        if self.tokens >= 1.0:
            self.tokens -= 1.0
            return True
        return False

    def wait_time(self) -> float:
        """Seconds until a token is available (0 if one is) [s]."""
        self._refill()
        return max(0.0, (1.0 - self.tokens) / self.rate)


class LeakyCounter:
    """A count that leaks away at ``rate`` per second (how many recent violations)."""

    def __init__(self, rate: float, clock: Callable[[], float] = time.monotonic) -> None:
        self.rate, self.clock, self.level, self.stamp = rate, clock, 0.0, clock()

    def add(self) -> float:
        """Count one; return the level after it."""
        now = self.clock()
        self.level = max(0.0, self.level - (now - self.stamp) * self.rate) + 1.0
        self.stamp = now
        return self.level


class LatestFirstQueue:
    """Messages over a rate wait here; a newer message with the same key replaces the waiting one.

    Slider values, camera poses and gizmo poses are states: only the latest matters, so a
    flood of them costs one computation per key at the steady rate, and the last value sent
    is never lost. Messages without a key (clicks, file parts) wait in order, up to ``capacity``.

    Args:
        bucket: The rate messages are let through at.
        capacity: Most messages waiting; more are refused.
    """

    def __init__(self, bucket: TokenBucket, capacity: int) -> None:
        self.bucket = bucket
        self.capacity = capacity
        self._waiting: OrderedDict[Hashable, Any] = OrderedDict()
        self._serial = 0

    def __len__(self) -> int:
        return len(self._waiting)

    def offer(self, key: Hashable | None, message: Any) -> str:
        """Offer ``message``: ``"now"`` (pass it on at once), ``"queued"``, ``"replaced"`` (it replaced
        a waiting message with the same key) or ``"refused"`` (the queue is full)."""
        if not self._waiting and self.bucket.take():
            return "now"
        if key is not None and key in self._waiting:
            self._waiting[key] = message  # keeps its place in line
            return "replaced"
        if len(self._waiting) >= self.capacity:
            return "refused"
        if key is None:
            self._serial += 1
            key = ("unkeyed", self._serial)
        self._waiting[key] = message
        return "queued"

    def wait_time(self) -> float:
        """Seconds until the next waiting message may go [s] (``inf`` when none waits)."""
        return self.bucket.wait_time() if self._waiting else float("inf")

    def pop_ready(self) -> Any | None:
        """The oldest waiting message if the rate allows it now, else ``None``."""
        if self._waiting and self.bucket.take():
            return self._waiting.popitem(last=False)[1]
        return None
