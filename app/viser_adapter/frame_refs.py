"""viser's private API, part 12: a replayed scene frame queued for a follower as one buffer entry.

viser's per-client buffer (``viser.infra._async_message_buffer.AsyncMessageBuffer``) takes one message
at a time: each push computes the message's keys and takes the buffer's lock, and each window pops the
messages one by one again. A presenter's frame is some 20 messages, so a room of followers paid that
twice per follower per change, for messages the producer then places as one packed run anyway
(:mod:`.frames`).

:func:`push_frame` queues a whole :class:`~.frames.SharedFrame` as one :class:`FrameRef` instead, with
viser's culling kept: a slow follower still gets, node by node, only the latest of what it missed.
When a frame is queued, the messages of frames still waiting in that buffer whose redundancy key the
new frame carries are marked as replaced (the waiting entry becomes a :class:`FrameRef` that skips
them), and single messages waiting with such a key are dropped, as viser's own push would drop them.
The producer of :mod:`.frames` places a :class:`FrameRef` that skips nothing as the frame's packed
bytes, and serialises the messages of one that skips some for that socket alone.
A single message queued after a waiting frame does not cut that frame's message of the same key (viser
would drop it): both are sent, in order, so the browser ends the same.

Only for followers whose scene has the shared owner, while the producer of :mod:`.frames` is installed
(viser's own producer could not serialise a :class:`FrameRef`), no recording of that connection is
running (viser's serializers see each queued message) and the frame removes nothing (a removal purges
the removed node's pending messages in viser's push: such a frame is queued message by message).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import Any

from .core import _private
from .frames import FrameRef, SharedFrame, frame_at

__all__ = ["FrameRef", "push_frame", "segments"]

_PENDING = "_jl_pending_frames"


def segments(messages: Sequence[Any]) -> Iterator[Any]:
    """``messages`` as whole tagged frames (:class:`SharedFrame`) and single messages, in order."""
    i = 0
    while i < len(messages):
        frame = frame_at(messages, i)
        yield messages[i] if frame is None else frame
        i += 1 if frame is None else len(frame)


def push_frame(buffer: Any, frame: SharedFrame) -> None:
    """Queue ``frame`` in ``buffer`` (a client's ``AsyncMessageBuffer``) as one entry, culling what it
    replaces among the messages still waiting there (see the module)."""
    keys = frame.keyset()
    lock = _private("push_frame", "AsyncMessageBuffer.buffer_lock", lambda: buffer.buffer_lock)
    with lock:
        waiting = buffer.message_from_id
        pending: dict[int, FrameRef] = buffer.__dict__.setdefault(_PENDING, {})
        for ident, ref in list(pending.items()):
            if waiting.get(ident) is not ref:  # sent (or dropped) since
                del pending[ident]
                continue
            gone = ref.replaced_by(keys)
            if not gone:
                continue
            if len(gone) + len(ref.skip) == len(ref.frame):
                buffer.pop_message_locked(ident)
                del pending[ident]
            else:
                waiting[ident] = pending[ident] = FrameRef(ref.frame, ref.skip | gone, ref.key)
        by_key = buffer.id_from_redundancy_key
        for key in keys:  # single messages still waiting that the frame replaces (as viser's push culls)
            ident = by_key.get(key)
            if ident is not None:
                buffer.pop_message_locked(ident)
    ref = FrameRef(frame)
    buffer.push(ref)
    with lock:
        ident = buffer.id_from_redundancy_key.get(ref.key)
        if ident is not None and buffer.message_from_id.get(ident) is ref:
            buffer.__dict__[_PENDING][ident] = ref
