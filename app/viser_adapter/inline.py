"""viser's private API, part 9: a widget's callback that only queues an action, run where the value arrives.

viser runs a widget's plain (not ``async``) update callback in its thread pool: every slider change
wakes a pool thread only for the app's callback to append an action to the tab's queue and wake the
renderer, one more thread hand-over (and its share of the interpreter lock) per change. A callback
marked with :func:`on_event_loop` is called where viser's event loop takes the value instead (through
the ``submit`` of ``GuiApi._thread_executor``, wrapped by :func:`run_marked_inline` when a GUI takes
its first value): only for callbacks that return at once and never block
(``app.views.panel.common.bind``). A value the server itself assigns still calls the callback on the
assigning thread, as viser does.

An exception in such a callback is logged; it never reaches the event loop.
"""

from __future__ import annotations

import concurrent.futures
import logging
from collections.abc import Callable
from typing import Any, TypeVar

from .core import _private

__all__ = ["on_event_loop", "run_marked_inline"]

log = logging.getLogger("app.viser_adapter")

_MARK = "_jl_on_event_loop"
F = TypeVar("F", bound=Callable[..., Any])


def on_event_loop(callback: F) -> F:
    """Mark ``callback`` (a widget's update or click callback) to run on viser's event loop, not in its
    thread pool: it must return at once and never block (queue an action, nothing more)."""
    setattr(callback, _MARK, True)
    return callback


class InlineFirst:
    """A ``ThreadPoolExecutor`` stand-in: ``submit`` runs a marked callable at once, on the calling
    thread, and hands anything else to the pool it wraps."""

    def __init__(self, pool: concurrent.futures.Executor) -> None:
        self.pool = pool

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> concurrent.futures.Future:
        if not getattr(fn, _MARK, False):
            return self.pool.submit(fn, *args, **kwargs)
        future: concurrent.futures.Future = concurrent.futures.Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception:  # logged here, never raised into the event loop
            log.exception("a widget's callback failed")
            future.set_result(None)
        return future

    def __getattr__(self, name: str) -> Any:  # shutdown, map, … of the pool
        return getattr(self.pool, name)


def run_marked_inline(gui_api: Any) -> None:
    """Let ``gui_api`` (a viser ``GuiApi``) run callbacks marked :func:`on_event_loop` where it takes a
    value (idempotent).

    Raises:
        ViserApiChanged: ``GuiApi._thread_executor`` moved.
    """
    pool = _private("run_marked_inline", "GuiApi._thread_executor", lambda: gui_api._thread_executor)
    if not isinstance(pool, InlineFirst):
        gui_api._thread_executor = InlineFirst(pool)
