"""viser's private API, part 11: a room's scene frame serialised once for every socket that sends it.

viser serialises every message once per client: each connection's producer task
(``viser.infra._infra._message_producer``) turns the messages of a window into dicts
(``Message.as_serializable_dict``, in Python), packs them with msgpack and compresses them. A presenter's
scene frame replayed to 300 followers was therefore turned into dicts 300 times.

Here the frame's messages are the *same objects* in every follower's buffer (:func:`share_owner` gives
every tab's scene one owner, so a message drawn for one tab is valid for all), tagged with their
:class:`SharedFrame`. :func:`install_shared_frames` replaces viser's producer (looked up by viser's
connection handler at call time) with one that serialises a frame's messages once per process — each
message packed once, its arrays once — and, for every socket, only places the packed bytes in that
socket's window: the wire format is viser's (zstd-compressed msgpack of ``messages``, ``timestampSec``,
``binaryBufferLengths``, then the arrays, 8-byte aligned), with the socket's own timestamp (the client
paces batches by it). A window is still what viser's buffer holds for that socket: a socket that fell
behind got its older frame's messages replaced, node by node, by the newer ones (viser's redundancy
keys), so a frame that is no longer whole in a window is serialised as viser would, for that socket
only; the others are not held back.
"""

from __future__ import annotations

import collections
import itertools
import time
from collections.abc import Sequence
from typing import Any, ClassVar

import msgspec
import viser
import zstandard
from viser._messages import GuiUpdateMessage as _GuiUpdate
from viser.infra._messages import Message as _InfraMessage
from viser.infra._messages import wire_field_names

from .core import ViserApiChanged, _private
from .props import _PLAIN
from .windows import check_buffer, windows

__all__ = [
    "SHARED_OWNER",
    "SharedFrame",
    "FrameRef",
    "JoinedFrame",
    "share_owner",
    "install_shared_frames",
    "shared_frames_installed",
    "frame_of",
    "frame_at",
]

SHARED_OWNER = "tab"
"""The owner stamped on every tab's scene messages (viser's client only tells "" — the broadcast scope —
from any other string)."""

_TAG = "_jl_frame"
_serial = itertools.count()
_original: dict[str, Any] = {}


class SharedFrame:
    """The scene messages of one drawing, sent to many tabs: each message packed once (lazily)."""

    packed_count = 0
    """How many frames have been packed in this process (for tests: once per frame, whatever the room)."""

    def __init__(self, messages: Sequence[Any], tag: bool = True) -> None:
        """``tag``: mark each message as this frame's (a frame of messages already tagged with others'
        frames, a follower's whole frame sent to the followers alike, leaves their tags)."""
        self.messages = tuple(messages)
        self._packed: tuple[tuple[msgspec.Raw, ...], list[memoryview]] | None = None
        self._keys: tuple[str, ...] | None = None
        self._keyset: frozenset[str] | None = None
        self.removes = any(getattr(m, "lifecycle_phase", None) == "remove" for m in self.messages)
        """Whether a message of the frame removes a node (viser's push then purges that node's messages)."""
        for i, message in enumerate(self.messages if tag else ()):
            try:
                setattr(message, _TAG, (self, i))
            except (AttributeError, TypeError):  # a message that takes no attribute: serialised per socket
                continue

    def packed(self) -> tuple[tuple[msgspec.Raw, ...], list[memoryview]]:
        """Each message as msgpack (arrays as placeholders numbered from 0) and the arrays' bytes."""
        if self._packed is None:  # only the event loop's thread packs: no lock needed
            buffers: list[memoryview] = []
            raws = tuple(msgspec.Raw(_ENCODE(m.as_serializable_dict(buffers))) for m in self.messages)
            self._packed = (raws, buffers)
            SharedFrame.packed_count += 1
        return self._packed

    def __len__(self) -> int:
        return len(self.messages)

    def keys(self) -> tuple[str, ...]:
        """Each message's redundancy key (viser's: a newer message with the same key replaces it)."""
        if self._keys is None:
            self._keys = tuple(m.redundancy_key() for m in self.messages)
        return self._keys

    def keyset(self) -> frozenset[str]:
        if self._keyset is None:
            self._keyset = frozenset(self.keys())
        return self._keyset


class JoinedFrame(SharedFrame):
    """Frames sent together as one (a follower's draw: the room's scene frame and its GUI updates), each
    packed once: their packed messages one after the other when only the first has arrays (their
    placeholders count from 0 in each frame), else packed anew as one frame."""

    def __init__(self, parts: Sequence[SharedFrame]) -> None:
        super().__init__([m for part in parts for m in part.messages], tag=False)
        self.parts = tuple(parts)

    def packed(self) -> tuple[tuple[msgspec.Raw, ...], list[memoryview]]:
        if self._packed is None and not any(part.packed()[1] for part in self.parts[1:]):
            self._packed = (
                tuple(raw for part in self.parts for raw in part.packed()[0]),
                self.parts[0].packed()[1] if self.parts else [],
            )
        return super().packed()


class FrameRef(_InfraMessage):
    """A :class:`~.frames.SharedFrame` waiting in one socket's buffer, less the messages a newer frame
    replaced there (``skip``: their indices)."""

    include_in_scene_serialization: ClassVar[bool] = False

    def __init__(self, frame: SharedFrame, skip: frozenset[int] = frozenset(), key: str = "") -> None:
        self.frame, self.skip = frame, skip
        self.key = key or f"jl-frame:{next(_serial)}"  # kept when replaced: viser's index holds it

    def redundancy_key(self) -> str:
        return self.key  # never culled by viser: the culling of its messages is push_frame's

    @property
    def whole(self) -> bool:
        return not self.skip

    def messages(self) -> list[Any]:
        """The frame's messages still to send, in order."""
        return [m for i, m in enumerate(self.frame.messages) if i not in self.skip]

    def replaced_by(self, keys: frozenset[str]) -> frozenset[int]:
        """Indices of the messages still to send that a frame with ``keys`` replaces."""
        own = self.frame.keys()
        return frozenset(i for i, k in enumerate(own) if i not in self.skip and k in keys)

    def as_serializable_dict(self, binary_buffers: Any = None) -> dict[str, Any]:
        raise ViserApiChanged("FrameRef", "a FrameRef reached viser's own serialiser (frames not installed)")


_ENCODE = msgspec.msgpack.Encoder().encode


def _serializable(message: Any, binary: list[memoryview]) -> Any:
    """``message.as_serializable_dict(binary)``; a GUI update of plain values (a follower's 3-4 a move:
    a slider's value, a readout's HTML) built directly, without viser's walk of the annotations, which
    leaves such values as they are."""
    if type(message) is _GuiUpdate:
        updates = message.updates
        if all(type(v) in _PLAIN for v in updates.values()):
            return {"uuid": message.uuid, "updates": updates, "type": "GuiUpdateMessage"}
    return message.as_serializable_dict(binary)


def frame_of(messages: Sequence[Any]) -> SharedFrame:
    """The frame ``messages`` were tagged with by a previous call, or a new one tagging them."""
    first = getattr(messages[0], _TAG, None) if messages else None
    if first is not None and first[1] == 0 and len(first[0]) == len(messages):
        if all(getattr(m, _TAG, None) == (first[0], i) for i, m in enumerate(messages)):
            return first[0]
    return SharedFrame(messages)


def share_owner(client: viser.ClientHandle) -> None:
    """Stamp ``client``'s scene messages with :data:`SHARED_OWNER` (call before it has any node)."""
    scene = client.scene
    if not isinstance(_private("share_owner", "SceneApi._owner_id", lambda: scene._owner_id), str):
        raise ViserApiChanged("share_owner", "SceneApi._owner_id is not a string")
    scene._owner_id = SHARED_OWNER


def frame_at(messages: Sequence[Any], start: int) -> SharedFrame | None:
    """The frame whose messages are all of ``messages`` from ``start`` on, in order, else None."""
    tag = getattr(messages[start], _TAG, None)
    if tag is None or tag[1] != 0:
        return None
    frame = tag[0]
    run = messages[start : start + len(frame)]
    if len(run) == len(frame) and all(a is b for a, b in zip(run, frame.messages, strict=True)):
        return frame
    return None


def _whole_frame(window: Sequence[Any]) -> tuple[int, SharedFrame] | None:
    """(start, frame) of the first frame whose messages all lie in ``window`` in order, else None."""
    for start in range(len(window)):
        frame = frame_at(window, start)
        if frame is not None:
            return start, frame
    return None


def _shared_run(window: Sequence[Any]) -> tuple[int, int, SharedFrame] | None:
    """(start, end, frame) of the window's first frame to place as packed: a :class:`FrameRef` that
    skips nothing, else the first frame whose messages all lie in the window in order."""
    for i, message in enumerate(window):
        if isinstance(message, FrameRef) and message.whole:
            return i, i + 1, message.frame
    found = _whole_frame(window)
    return None if found is None else (found[0], found[0] + len(found[1]), found[1])


_SENT: collections.OrderedDict[tuple[SharedFrame, ...], tuple[bytes, int, bytes, list[memoryview]]] = (
    collections.OrderedDict()
)
"""The compressed messages of the last windows made only of whole frames, by their frames."""
_SENT_KEPT = 16


def _raw_zstd_frame(content: bytes) -> bytes:
    """``content`` (at most 255 bytes) as one zstd frame of one raw block: nothing to compress, so no
    compressor is run (the frame format: RFC 8878; single segment, its size in one byte)."""
    return (
        b"\x28\xb5\x2f\xfd\x20"  # the magic number, then: a single segment whose size takes one byte
        + bytes((len(content),))
        + ((len(content) << 3) | 1).to_bytes(3, "little")  # the last block, raw, of that size
        + content
    )


def _whole_frames(window: Sequence[Any]) -> tuple[SharedFrame, ...] | None:
    """The frames of ``window`` when it holds only whole frames, arrays in the first alone."""
    if not window or not all(type(m) is FrameRef and m.whole for m in window):
        return None
    frames = tuple(m.frame for m in window)
    if any(f.packed()[1] for f in frames[1:]):
        return None
    return frames


def _room_wire(infra: Any, zstd: Any, frames: tuple[SharedFrame, ...]) -> bytes | None:
    """viser's wire bytes of a window of whole ``frames``, compressed once for every socket that sends
    the same window (followers sent one follower's draw: :func:`~.mirror.send_ridden`): the messages as one
    zstd frame made once, the socket's own timestamp after them as a raw zstd frame of its own (the browser's
    ``ZSTD_decompress`` reads the frames one after the other). None when the tail would not fit."""
    sent = _SENT.get(frames)
    if sent is None:
        raws = [raw for frame in frames for raw in frame.packed()[0]]
        buffers = frames[0].packed()[1]
        head = b"\x83" + _ENCODE("messages") + _ENCODE(raws)  # a map of three: the messages first, as viser's
        lengths = _ENCODE("binaryBufferLengths") + _ENCODE(tuple(b.nbytes for b in buffers))
        sent = (zstd.compress(head), len(head), lengths, buffers)
        _SENT[frames] = sent
        while len(_SENT) > _SENT_KEPT:
            _SENT.popitem(last=False)
    compressed, head_size, lengths, buffers = sent
    tail = _ENCODE("timestampSec") + _ENCODE(time.perf_counter()) + lengths
    if len(tail) > 255:
        return None
    raw = _raw_zstd_frame(tail)
    parts: list[bytes | memoryview] = [
        (head_size + len(tail)).to_bytes(8, "little"),
        (len(compressed) + len(raw)).to_bytes(8, "little"),
        compressed,
        raw,
    ]
    infra._append_aligned_buffers(parts, buffers, 16 + len(compressed) + len(raw))
    return b"".join(parts)


def _wire(infra: Any, zstd: Any, window: Sequence[Any]) -> bytes:
    """viser's wire bytes of ``window``: one whole shared frame in it placed as packed once, the rest
    (and the messages a :class:`FrameRef` still holds) serialised for this socket; a window of whole frames
    alone compressed once for every socket that sends it (:func:`_room_wire`)."""
    frames = _whole_frames(window)
    if frames is not None:
        made = _room_wire(infra, zstd, frames)
        if made is not None:
            return made
    run = _shared_run(window)
    binary: list[memoryview] = []
    serialized: list[Any] = []
    if run is not None:
        raws, frame_buffers = run[2].packed()
        binary.extend(frame_buffers)  # the frame's placeholders count from 0: its arrays come first
    for i, message in enumerate(window):
        if run is not None and run[0] <= i < run[1]:
            if i == run[0]:
                serialized.extend(raws)
        elif isinstance(message, FrameRef) and message.whole and not message.frame.packed()[1]:
            serialized.extend(message.frame.packed()[0])  # no arrays: its packed bytes fit anywhere
        elif isinstance(message, FrameRef):
            serialized.extend(_serializable(m, binary) for m in message.messages())
        else:
            serialized.append(_serializable(message, binary))
    inner = _ENCODE(
        {
            "messages": serialized,
            "timestampSec": time.perf_counter(),
            "binaryBufferLengths": tuple(b.nbytes for b in binary),
        }
    )
    compressed = zstd.compress(inner)
    parts: list[bytes | memoryview] = [
        len(inner).to_bytes(8, "little"),
        len(compressed).to_bytes(8, "little"),
        compressed,
    ]
    infra._append_aligned_buffers(parts, binary, 16 + len(compressed))
    return b"".join(parts)


async def _producer(websocket: Any, buffer: Any, client_id: int, backlog_done_message: Any = None) -> None:
    """viser's ``_message_producer`` (same windows, paced once per window: :mod:`.windows`; same wire
    format), shared frames packed once."""
    infra = _infra_module()
    window_generator = windows(buffer, client_id, backlog_done_message)
    zstd = zstandard.ZstdCompressor(level=1)
    try:
        while not buffer.done:
            try:
                outgoing = await window_generator.__anext__()
            except StopAsyncIteration:
                break
            await websocket.send(_wire(infra, zstd, outgoing))
    finally:
        await window_generator.aclose()


def install_shared_frames() -> None:
    """Replace viser's message producer with :func:`_producer` (idempotent).

    Raises:
        ViserApiChanged: the producer, its window generator or the buffer alignment helper moved.
    """
    infra = _private("install_shared_frames", "viser.infra._infra", _infra_module)
    producer = getattr(infra, "_message_producer", None)
    if not callable(producer) or not callable(getattr(infra, "_append_aligned_buffers", None)):
        raise ViserApiChanged("install_shared_frames", "viser.infra._infra._message_producer moved")
    check_buffer()
    if wire_field_names(_GuiUpdate) != ("uuid", "updates"):
        raise ViserApiChanged("install_shared_frames", "GuiUpdateMessage's fields are not (uuid, updates)")
    if "_message_producer" not in _original:
        _original["_message_producer"] = producer
        infra._message_producer = _producer


def shared_frames_installed() -> bool:
    """Whether the producer of this module sends (a :class:`FrameRef` may be queued)."""
    return "_message_producer" in _original


def uninstall_shared_frames() -> None:
    """Give viser back its own producer (for tests)."""
    if "_message_producer" in _original:
        _infra_module()._message_producer = _original.pop("_message_producer")


def _infra_module() -> Any:
    from viser.infra import _infra

    return _infra
