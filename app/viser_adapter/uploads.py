"""viser's private API, part 7: an unfinished upload's memory, given back (see the package).

viser keeps an upload's parts in ``GuiApi._current_file_upload_states`` until its last part arrives,
and drops a tab's unfinished uploads when the tab leaves. Two holes were left, measured with 30 tabs
each starting 3 uploads of 2 MB and sending 3 of their 4 parts (issue 26, point 5: the server tree's
memory grew by 58 MB and kept it after the tabs had gone):

* the parts were freed, but the process kept their memory: CPython asks ``malloc`` for each 512 KiB
  part (and for the frame it was read from), glibc serves such blocks from its heaps once its mmap
  threshold has risen past them, and a freed block in the middle of a heap is kept for reuse, never
  given back to the system. :func:`give_back_memory` trims every heap of the process (glibc's
  ``malloc_trim(0)``, in a thread of its own, once for tabs leaving together); the input checks of
  :mod:`.gate` call it when a tab leaves and when an unfinished upload is dropped;
* an upload that stops sending parts while its tab stays kept them for the tab's life:
  :func:`watch_upload` ends it after ``RoomLimits.upload_stall_seconds`` without a part.

Elsewhere than glibc (macOS, musl) there is no ``malloc_trim`` and :func:`give_back_memory` does
nothing: the memory is freed for the process's own reuse, not given back.
"""

from __future__ import annotations

import asyncio
import ctypes
import logging
import threading
import time
import weakref
from collections.abc import Callable
from typing import Any

__all__ = ["give_back_memory", "trims", "watch_upload", "TRIM_DELAY"]

log = logging.getLogger("app.viser_adapter")

TRIM_DELAY = 1.0
"""Seconds between a tab leaving and the trim [s]: the tabs of a closing class leave within this
and are given back in one trim (a trim of 60 MB of freed heap took 39 ms, off the event loop)."""


def _find_malloc_trim() -> Callable[[int], int] | None:
    try:
        trim = ctypes.CDLL(None).malloc_trim  # the C library this interpreter runs on
    except (AttributeError, OSError):
        return None
    trim.argtypes, trim.restype = [ctypes.c_size_t], ctypes.c_int
    return trim


_malloc_trim = _find_malloc_trim()
_lock = threading.Lock()
_pending = False
_trims = 0


def give_back_memory(delay: float = TRIM_DELAY) -> bool:
    """Give the memory this process freed back to the system, ``delay`` seconds from now.

    Calls during the wait are served by the same trim. Safe from any thread; the trim runs in a thread
    of its own (``malloc_trim`` holds no interpreter lock). Returns whether a trim is coming (``False``
    without glibc).
    """
    global _pending
    if _malloc_trim is None:
        return False
    with _lock:
        if _pending:
            return True
        _pending = True
    timer = threading.Timer(delay, _trim)
    timer.daemon, timer.name = True, "give-back-memory"
    timer.start()
    return True


def _trim() -> None:
    global _pending, _trims
    with _lock:
        _pending = False
    assert _malloc_trim is not None
    start = time.perf_counter()
    _malloc_trim(0)
    with _lock:
        _trims += 1
    log.debug("trimmed the heaps in %.1f ms", (time.perf_counter() - start) * 1e3)


def trims() -> int:
    """How many trims :func:`give_back_memory` ran in this process."""
    with _lock:
        return _trims


def watch_upload(
    api: Any,
    transfer: str,
    stall: float,
    idle: Callable[[str], float | None],
    drop: Callable[[Any, str], None],
) -> None:
    """Call ``drop(api, transfer)`` once the upload ``transfer`` of the viser GUI ``api`` waited
    ``stall`` seconds for a part (``idle(transfer)``: seconds since its last part, ``None`` once it
    ended). Call on the event loop, from the handler that started the upload.

    One timer per upload in flight, on the loop: it looks again when the upload's wait could first
    reach ``stall``, and holds the GUI weakly (a tab that left is not kept for its timer).
    """
    loop = asyncio.get_running_loop()
    gui = weakref.ref(api)

    def check() -> None:
        waited, target = idle(transfer), gui()
        if waited is None or target is None:
            return
        if waited < stall:
            loop.call_later(stall - waited, check)
        else:
            drop(target, transfer)

    loop.call_later(stall, check)
