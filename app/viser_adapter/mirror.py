"""viser's private API, part 4: the scene messages of one tab, replayed to others (see the package).

A presenter's redraw changes its scene nodes with messages addressed to its own scene (each carries
an ``owner``: :data:`~.frames.SHARED_OWNER` for every tab given :func:`~.frames.share_owner`, else the
client id). :func:`capture_scene` collects them while the presenter draws, as one
:class:`~.frames.SharedFrame`; :func:`replay_scene` queues the very same messages for a follower whose
scene has the same nodes (copies, re-addressed, for a tab with an owner of its own), so a room of
followers costs one scene computation and one serialisation, not one per follower.
"""

from __future__ import annotations

import contextlib
import copy
from collections.abc import Iterator, Sequence
from typing import Any

import viser

from .core import ViserApiChanged, _private
from .frame_refs import push_frame, segments
from .frames import SHARED_OWNER, JoinedFrame, SharedFrame, shared_frames_installed
from .panel_ledger import can_take_gui_updates, captured_into, take_gui_updates

__all__ = ["capture_scene", "replay_scene", "ridden_frame", "send_ridden"]


def _connection(client: viser.ClientHandle, function: str) -> Any:
    conn = _private(function, "SceneApi._websock_interface", lambda: client.scene._websock_interface)
    if not callable(getattr(conn, "queue_message", None)):
        raise ViserApiChanged(function, "the scene's connection has no queue_message")
    return conn


@contextlib.contextmanager
def capture_scene(client: viser.ClientHandle) -> Iterator[list[Any]]:
    """Collect (and still send) the scene messages queued for ``client`` inside the block."""
    conn = _connection(client, "capture_scene")
    owner = _owner(client)
    captured: list[Any] = []
    before = conn.__dict__.get("queue_message")  # a capture_frame around this one keeps its own
    original = conn.queue_message

    def queue(message: Any) -> None:
        if getattr(message, "owner", None) == owner:
            captured.append(message)
        original(message)

    conn.queue_message = queue  # an instance attribute: shadows the method for this connection only
    try:
        yield captured
    finally:
        if before is None:
            conn.__dict__.pop("queue_message", None)
        else:
            conn.queue_message = before
    if captured:
        SharedFrame(captured)  # tags the messages: serialised once for every socket that sends them


def replay_scene(client: viser.ClientHandle, messages: Sequence[Any]) -> None:
    """Send ``messages`` (captured for another client) to ``client``'s scene: under the shared owner, a
    whole captured frame as one entry of its buffer (:func:`~.frame_refs.push_frame`), else copies."""
    conn = _connection(client, "replay_scene")
    owner = _owner(client)
    if owner == SHARED_OWNER and shared_frames_installed() and not _recording(conn):
        buffer = conn.get_message_buffer()
        capture = captured_into(conn)  # a capture_frame of this tab's whole draw sees the frame too
        for segment in segments(messages):
            if isinstance(segment, SharedFrame) and not segment.removes:
                push_frame(buffer, segment)
                if capture is not None:
                    capture.extend(segment.messages)
            elif isinstance(segment, SharedFrame):
                for message in segment.messages:
                    conn.queue_message(message)
            else:
                conn.queue_message(segment)
        return
    for message in messages:
        if getattr(message, "owner", owner) != owner:  # drawn for a tab with another owner: re-addressed
            message = copy.copy(message)
            message.owner = owner
        conn.queue_message(message)


def _recording(conn: Any) -> bool:
    """Whether a serializer records what is queued on ``conn`` (it must see each message)."""
    return bool(_private("replay_scene", "WebsockConnection._record_handles", lambda: conn._record_handles))


def _owner(client: viser.ClientHandle) -> str:
    owner = _private("replay_scene", "SceneApi._owner_id", lambda: client.scene._owner_id)
    if not isinstance(owner, str):
        raise ViserApiChanged("replay_scene", "SceneApi._owner_id is not a string")
    return owner


def ridden_frame(captured: Sequence[Any]) -> tuple[SharedFrame, ...] | None:
    """The frame of a follower's draw (:func:`~.panel_ledger.capture_frame`) that followers showing what
    it showed before may be sent as it is: its scene messages and its GUI updates (a page script, its
    address, stays its own), as one frame joining the scene frames already packed for the room and the
    rest (one entry in each follower's buffer);
    None when it made or removed an element, told the tab something, or drew a scene of another owner."""
    from viser._messages import GuiUpdateMessage, RunJavascriptMessage

    kept = []
    for message in captured:
        if type(message) is GuiUpdateMessage or getattr(message, "owner", None) == SHARED_OWNER:
            kept.append(message)
        elif type(message) is not RunJavascriptMessage:
            return None
    parts: list[SharedFrame] = []
    run: list[Any] = []
    for segment in segments(kept):
        if isinstance(segment, SharedFrame):
            if run:
                parts.append(SharedFrame(run, tag=False))
                run = []
            parts.append(segment)
        else:
            run.append(segment)
    if run:
        parts.append(SharedFrame(run, tag=False))  # untagged: its messages may be another frame's too
    if not parts:
        return None
    return (JoinedFrame(parts),) if not any(part.removes for part in parts) else tuple(parts)


def send_ridden(
    client: viser.ClientHandle, frame: Sequence[SharedFrame], after: tuple[int, dict[str, int]] | None = None
) -> bool:
    """Queue ``frame`` (:func:`ridden_frame`, drawn for a follower of the same panel digest) for ``client``
    and set its GUI elements to match; False, with nothing sent, when ``client``'s scene is not under the
    shared owner or an update names an element it lacks. ``after``: the drawing tab's
    :func:`~.panel_ledger.panel_after`."""
    conn = _connection(client, "send_ridden")
    if _owner(client) != SHARED_OWNER or not shared_frames_installed() or _recording(conn):
        return False
    if not all(can_take_gui_updates(client, part.messages) for part in frame):
        return False
    buffer = conn.get_message_buffer()
    for part in frame:
        if part.removes:
            for message in part.messages:
                conn.queue_message(message)
        else:
            push_frame(buffer, part)
    take_gui_updates(client, [m for part in frame for m in part.messages], after)
    return True
