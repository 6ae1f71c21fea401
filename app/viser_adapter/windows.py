"""viser's private API, part 13: a socket's windows, with one pause per window sent.

viser's window loop (``AsyncMessageBuffer._window_loop``) pauses for a window's length
(``window_duration_sec``, 1/60 s, cut short by a flush) each time its window came out empty *and* each
time it drained the buffer, and it clears the buffer's event only after waiting on it. A follower of a
presenter gets one frame per move, queued in one atomic block: the loop woke, paused with nothing to
send, sent, paused again, woke again on the event set a second time by the same push (viser sets it on
the pushing thread and again through ``call_soon_threadsafe``) and paused a third time: three or four
``asyncio.wait`` calls with a timer each, per socket per move. Measured in a room of 40 followers
(``bench/profile_change.py --loop``): 4 loop passes and 4 ``asyncio.wait`` per window sent.

:func:`windows` yields the same windows in the same order (viser's backlog marker, consumption cursor,
atomic blocks, ``excluded_self_client``, ``max_window_size``, persistent or popped messages) and paces
the same way after a window that drained the buffer (at most one such window per
``window_duration_sec`` unless flushed; the pause is only waited out when a push comes within it, so a
socket sent one window a move sets no timer), but takes a woken socket's messages at once: the event is
cleared before the buffer is read, so a push after that read wakes it again, and an empty read inside
an atomic block pauses like viser's instead of spinning.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator, Sequence
from typing import Any

from .core import ViserApiChanged
from .events import LoopSafeEvent

__all__ = ["windows", "check_buffer"]

_FIELDS = (
    "message_counter", "message_from_id", "message_event", "flush_event", "buffer_lock", "max_window_size",
    "window_duration_sec", "done", "atomic_counter", "generator_cursors", "persistent_messages", "event_loop",
)  # fmt: skip
"""What :func:`windows` reads of viser's ``AsyncMessageBuffer`` (its dataclass fields)."""


def windows(
    buffer: Any, client_id: int, backlog_done_message: Any = None
) -> AsyncGenerator[Sequence[Any], None]:
    """The windows of ``buffer`` for ``client_id`` (viser's ``window_generator``, paced once per window).

    The end of the backlog is read now, as viser reads it, so a live message pushed before the first
    window cannot precede ``backlog_done_message``.
    """
    return _loop(buffer, client_id, buffer.message_counter - 1, backlog_done_message)


def check_buffer() -> None:
    """Raise :class:`~.core.ViserApiChanged` unless viser's buffer has what :func:`windows` reads."""
    from viser.infra._async_message_buffer import AsyncMessageBuffer

    fields = getattr(AsyncMessageBuffer, "__dataclass_fields__", {})
    missing = [name for name in _FIELDS if name not in fields]
    if missing or not callable(getattr(AsyncMessageBuffer, "pop_message_locked", None)):
        raise ViserApiChanged("windows", f"AsyncMessageBuffer lacks {missing or 'pop_message_locked'}")


def _take(buffer: Any, client_id: int, last_sent: int, upto: int) -> tuple[list[Any], int]:
    """The messages after ``last_sent`` up to ``upto`` (at most a window's worth) and the new cursor."""
    window: list[Any] = []
    while last_sent < upto and len(window) < buffer.max_window_size and buffer.atomic_counter == 0:
        last_sent += 1
        if buffer.persistent_messages:
            message = buffer.message_from_id.get(last_sent, None)
        else:
            with buffer.buffer_lock:
                message = buffer.pop_message_locked(last_sent)
        if message is not None and message.excluded_self_client != client_id:
            window.append(message)
    return window, last_sent


async def _loop(
    buffer: Any, client_id: int, backlog_last_id: int, backlog_done_message: Any
) -> AsyncGenerator[Sequence[Any], None]:
    loop = buffer.event_loop
    last_sent = -1
    backlog_pending = backlog_done_message is not None
    flush_wait = loop.create_task(buffer.flush_event.wait())
    buffer.generator_cursors[client_id] = last_sent
    event = buffer.message_event
    next_window = 0.0  # the loop's time before which a window only goes out if flushed
    try:
        while not buffer.done:
            pause = next_window - loop.time()
            if pause > 0:  # the pause after a window that drained the buffer, as viser's: a flush cuts it
                done, _pending = await asyncio.wait([flush_wait], timeout=pause)
                if flush_wait in done and not buffer.done:
                    buffer.flush_event.clear()
                    flush_wait = loop.create_task(buffer.flush_event.wait())
            event.clear()  # before the read: a push after it wakes the wait below again
            upto = buffer.message_counter - 1
            if backlog_pending:  # the backlog's windows stop at its end: the marker follows it
                upto = min(upto, backlog_last_id)
            window, last_sent = _take(buffer, client_id, last_sent, upto)
            buffer.generator_cursors[client_id] = last_sent  # the collector may drop what it read
            if backlog_pending and last_sent >= backlog_last_id and buffer.atomic_counter == 0:
                backlog_pending = False
                window.append(backlog_done_message)
            if window:
                yield window
                more = buffer.atomic_counter == 0 and last_sent < buffer.message_counter - 1
                next_window = 0.0 if more else loop.time() + buffer.window_duration_sec
                # Nothing waits: sleep until a push, and pause (what is left of the window) only then. A
                # wake by a push already read (viser sets the event again through the loop) sleeps on: a
                # follower sent one window a move sets no timer.
                while not more and not buffer.done and last_sent >= buffer.message_counter - 1:
                    await event.wait()
                    event.clear()
            elif buffer.atomic_counter and isinstance(event, LoopSafeEvent):
                await event.set_on_loop()  # the block's end, not its pushes (they only raise the flag)
            elif buffer.atomic_counter:
                next_window = loop.time() + buffer.window_duration_sec  # viser's own pause
            else:
                await event.wait()  # nothing left: sleep until a push (or the end) sets the event
    finally:
        buffer.generator_cursors.pop(client_id, None)
        flush_wait.cancel()
        try:
            await flush_wait
        except asyncio.CancelledError:
            pass
