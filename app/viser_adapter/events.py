"""viser's private API, part 8: a message buffer's wake-up event safe to set from the drawing thread.

viser 1.1's ``AsyncMessageBuffer.push`` (every message a handle sends) calls ``message_event.set()`` on
an ``asyncio.Event`` from whatever thread pushes: here the renderer thread. ``asyncio.Event.set`` wakes
its waiters by iterating their deque, which the event loop's thread changes as a sender task starts
and stops waiting: under load this raised ``RuntimeError: deque mutated during iteration`` in a redraw
(issue 18, point 10), and it completes the loop's futures from the wrong thread. ``push`` then also
calls ``event_loop.call_soon_threadsafe(message_event.set)``: the thread-safe path that must do the
waking.

:func:`install_loop_safe_events` gives every buffer a :class:`LoopSafeEvent`: set off the loop's thread,
it only records that it is set (so ``is_set()`` and the loop's next ``wait()`` see it at once) and
leaves its waiters to the call made on the loop's thread, which wakes them even though the flag is
already up.
"""

from __future__ import annotations

import asyncio
import importlib
from typing import Any

from .core import ViserApiChanged, _private

__all__ = ["LoopSafeEvent", "install_loop_safe_events"]

_installed: list[Any] = []


class LoopSafeEvent(asyncio.Event):
    """An ``asyncio.Event`` whose ``set()`` from a thread with no running loop never touches its waiters.

    On the loop's thread ``set()`` wakes every waiter, whether or not the flag was up already (the flag
    may have been raised off the loop, which left the waking to this call).
    """

    def set(self) -> None:
        try:
            asyncio.get_running_loop()
        except RuntimeError:  # another thread (the renderer's): flag only, never the waiters
            self._value = True
            return
        self._value = True
        for waiter in list(self._waiters):
            if not waiter.done():
                waiter.set_result(True)

    async def set_on_loop(self) -> None:
        """Wait for the next :meth:`set` made on the loop's thread, whether or not the flag is up (a
        push inside an atomic block raises it off the loop; the block's end sets it on the loop)."""
        waiter = asyncio.get_running_loop().create_future()
        self._waiters.append(waiter)
        try:
            await waiter
        finally:
            self._waiters.remove(waiter)


def install_loop_safe_events() -> None:
    """Give every message buffer viser creates from now on a :class:`LoopSafeEvent` (idempotent).

    Raises:
        ViserApiChanged: ``AsyncMessageBuffer`` or its ``message_event`` moved.
    """
    if _installed:
        return
    module = _private(
        "install_loop_safe_events",
        "viser.infra._async_message_buffer",
        lambda: importlib.import_module("viser.infra._async_message_buffer"),
    )
    buffer = _private("install_loop_safe_events", "AsyncMessageBuffer", lambda: module.AsyncMessageBuffer)
    fields = getattr(buffer, "__dataclass_fields__", {})
    if "message_event" not in fields or not hasattr(asyncio.Event(), "_waiters"):
        raise ViserApiChanged("install_loop_safe_events", "AsyncMessageBuffer.message_event is gone")
    original = buffer.__init__

    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        original(self, *args, **kwargs)
        self.message_event = LoopSafeEvent()

    buffer.__init__ = __init__
    _installed.append(original)
