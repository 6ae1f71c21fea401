"""Rate limits for one browser tab's messages: a token bucket, and a queue that keeps only the latest state.

Used by :func:`app.viser_adapter.install_message_limits`. Pure bookkeeping (no viser,
no asyncio), so it is tested on its own with a fake clock.
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict, deque
from collections.abc import Callable, Hashable
from typing import Any

__all__ = ["TokenBucket", "LeakyCounter", "LatestFirstQueue", "TabLimiter", "RoomLimits"]


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

    def clear(self) -> None:
        """Forget every waiting message."""
        self._waiting.clear()


def state_key(message: Any) -> tuple | None:
    """What a viser client message sets, by its class name: messages with the same key are states
    (slider value, camera pose, gizmo pose) and only the latest matters; None for events."""
    kind = type(message).__name__
    if kind == "GuiUpdateMessage":
        return (kind, message.uuid, tuple(sorted(message.updates)))
    if kind == "ViewerCameraMessage":
        return (kind,)
    if kind == "TransformControlsUpdateMessage":
        return (kind, message.name)
    return None


class TabLimiter:
    """Every limit on one tab's messages: GUI updates (each may cost a redraw) at one rate, other
    messages at another, and a count of recent drops that decides when to close the tab.

    Args:
        rate, burst: Steady rate [1/s] and burst of all messages but GUI updates.
        gui_rate, gui_burst: The same for GUI updates (``GuiUpdateMessage``).
        close_after: Drops (forgiven at the lower of the two rates: a browser never has any) after
            which :meth:`offer` says ``"close"``.
        clock: Time source [s].
    """

    def __init__(
        self,
        rate: float,
        burst: int,
        gui_rate: float,
        gui_burst: int,
        close_after: int,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.gui = LatestFirstQueue(TokenBucket(gui_rate, gui_burst, clock), capacity=max(gui_burst, 16))
        self.other = LatestFirstQueue(TokenBucket(rate, burst, clock), capacity=max(burst, 16))
        self.strikes = LeakyCounter(min(rate, gui_rate), clock)
        self.close_after = close_after

    def offer(self, message: Any) -> str:
        """``"now"`` (pass it on), ``"queued"``, ``"dropped"`` (superseded or refused) or ``"close"``
        (dropped, and the tab keeps violating: close it)."""
        key = state_key(message)
        queue = self.gui if key is not None and key[0] == "GuiUpdateMessage" else self.other
        verdict = queue.offer(key, message)
        if verdict in ("now", "queued"):
            return verdict
        return "close" if self.strikes.add() >= self.close_after else "dropped"

    def wait_time(self) -> float:
        """Seconds until a waiting message may go [s] (``inf`` when none waits)."""
        return min(self.gui.wait_time(), self.other.wait_time())

    def pop_ready(self) -> list[Any]:
        """The waiting messages the rates allow now (at most one per queue)."""
        return [m for m in (self.other.pop_ready(), self.gui.pop_ready()) if m is not None]

    def clear(self) -> None:
        """Forget every waiting message (the tab left)."""
        self.gui.clear()
        self.other.clear()


class RoomLimits:
    """What every tab of one server may hold at once, and what was refused: one object, so that a
    server of several processes could keep it in one shared place.

    Uploads are counted from their start to their end (or their tab's): at most
    ``uploads_per_tab`` at once per tab and ``bytes_in_flight`` declared bytes over the server,
    each at most ``max_upload_bytes`` in parts of ``part_bytes``; a part that would take a transfer
    past its declared size ends it, and so does ``upload_stall_seconds`` without a part
    (:meth:`upload_idle` tells how long a transfer has waited; the viser adapter ends it).

    Args:
        max_upload_bytes: Largest file a tab may upload [bytes].
        part_bytes: Size of an upload's parts [bytes] (the browser's).
        uploads_per_tab: Uploads one tab may have in flight.
        bytes_in_flight: Declared bytes of every upload in flight, over the server [bytes].
        upload_stall_seconds: An upload in flight with no part for this long is dropped [s] (a
            browser sends its parts back to back: 512 KiB take 4 s at 1 Mbit/s).
        notices_per_second: Refusal notices a tab is shown per second (more are only logged).
        clock: Time source [s].

    Attributes:
        refusals: The last refusals, as (tab, text).
        refused: How many messages were refused.
    """

    def __init__(
        self,
        max_upload_bytes: int = 2 * 1024 * 1024,
        part_bytes: int = 512 * 1024,
        uploads_per_tab: int = 2,
        bytes_in_flight: int = 16 * 1024 * 1024,
        upload_stall_seconds: float = 30.0,
        notices_per_second: float = 4.0,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.max_upload_bytes, self.part_bytes = max_upload_bytes, part_bytes
        self.uploads_per_tab, self.bytes_in_flight = uploads_per_tab, bytes_in_flight
        self.upload_stall_seconds = upload_stall_seconds
        self.notices_per_second, self.clock = notices_per_second, clock
        self.refusals: deque[tuple[Hashable, str]] = deque(maxlen=200)
        self.refused = 0
        self._lock = threading.Lock()
        self._uploads: dict[Hashable, list] = {}  # transfer → [tab, declared, received, last part's time]
        self._notices: OrderedDict[Hashable, TokenBucket] = OrderedDict()

    # ---------------------------------------------------------------- uploads
    def start_upload(self, tab: Hashable, transfer: Hashable, declared: int, parts: int) -> str:
        """Count an upload in; ``""`` when it may go on, else why not."""
        if not (isinstance(declared, int) and isinstance(parts, int)) or declared < 0:
            return "its declared size is not a count of bytes"
        if declared > self.max_upload_bytes:
            return f"{declared} bytes is over the {self.max_upload_bytes} bytes a file may have"
        if parts != -(-declared // self.part_bytes):
            return f"{parts} parts for {declared} bytes (parts of {self.part_bytes} bytes)"
        with self._lock:
            if transfer in self._uploads:
                return "it was started already"
            mine = sum(1 for u in self._uploads.values() if u[0] == tab)
            if mine >= self.uploads_per_tab:
                return f"this tab already has {mine} uploads under way: wait for them to finish"
            total = sum(u[1] for u in self._uploads.values())
            if total + declared > self.bytes_in_flight:
                return "the server is receiving too many files right now: try again in a moment"
            self._uploads[transfer] = [tab, declared, 0, self.clock()]
        return ""

    def receive_part(self, transfer: Hashable, size: int) -> str:
        """Count ``size`` bytes of a part in; ``""`` when it fits the declared size, else why not."""
        with self._lock:
            upload = self._uploads.get(transfer)
            if upload is None:
                return "it was not started"
            if size > self.part_bytes or upload[2] + size > upload[1]:
                return f"its parts bring more than the {upload[1]} bytes it declared"
            upload[2] += size
            upload[3] = self.clock()
        return ""

    def upload_idle(self, transfer: Hashable) -> float | None:
        """Seconds since the upload's last part (or its start) [s]; ``None`` once it ended."""
        with self._lock:
            upload = self._uploads.get(transfer)
            return None if upload is None else self.clock() - upload[3]

    def end_upload(self, transfer: Hashable) -> None:
        """The upload finished or was dropped."""
        with self._lock:
            self._uploads.pop(transfer, None)

    def end_tab(self, tab: Hashable) -> None:
        """The tab went: its uploads end."""
        with self._lock:
            for transfer in [t for t, u in self._uploads.items() if u[0] == tab]:
                del self._uploads[transfer]
            self._notices.pop(tab, None)

    def uploads_in_flight(self, tab: Hashable | None = None) -> tuple[int, int]:
        """(uploads, declared bytes) in flight, of ``tab`` or of the whole server."""
        with self._lock:
            mine = [u for u in self._uploads.values() if tab is None or u[0] == tab]
            return len(mine), sum(u[1] for u in mine)

    # ---------------------------------------------------------------- refusals
    def refuse(self, tab: Hashable, text: str) -> bool:
        """Record a refusal; whether the tab should be told now (a few notices per second at most)."""
        with self._lock:
            self.refused += 1
            self.refusals.append((tab, text))
            bucket = self._notices.pop(tab, None)
            if bucket is None:
                rate = self.notices_per_second
                bucket = TokenBucket(rate, max(1, int(2 * rate)), self.clock)
            self._notices[tab] = bucket
            while len(self._notices) > 1000:
                self._notices.popitem(last=False)
            return bucket.take()
