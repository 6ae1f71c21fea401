"""A minimal client of viser's websocket protocol, for tests and benchmarks (no browser).

It connects like the browser does (subprotocol ``viser-v<version>``), sends
one camera message (viser counts a client as connected only after it),
then decodes every frame the server sends: zstd-compressed msgpack followed
by raw binary buffers, which come back as NumPy arrays.

Example::

    with ViserWsClient(f"ws://127.0.0.1:{port}") as ws:
        mark = ws.mark()
        ws.set_value(slider_uuid, 30.0)
        t, msg = ws.wait_for(lambda m: m["type"] == "SceneNodeUpdateMessage", after=mark)
"""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Callable
from typing import Any

import msgspec.msgpack
import numpy as np
import viser
import websockets
import zstandard
from fakes import POLL_TIMEOUT
from websockets.exceptions import InvalidMessage

from app.viser_adapter import message_class

__all__ = ["ViserWsClient", "decode_frame"]


def decode_frame(data: bytes) -> list[dict[str, Any]]:
    """The messages of one server → client frame, binary placeholders replaced by arrays."""
    raw_size = int.from_bytes(data[:8], "little")
    compressed_size = int.from_bytes(data[8:16], "little")
    # One zstd frame, or several one after the other (a window compressed once for a room, its socket's
    # timestamp in a frame of its own): read across frames, as the browser's ZSTD_decompress does.
    reader = zstandard.ZstdDecompressor().stream_reader(
        data[16 : 16 + compressed_size], read_across_frames=True
    )
    chunks = []
    while chunk := reader.read(raw_size + 1):
        chunks.append(chunk)
    inner = b"".join(chunks)
    if len(inner) != raw_size:
        raise ValueError(f"a frame of {len(inner)} bytes said it held {raw_size}")
    payload = msgspec.msgpack.decode(inner)
    buffers = []
    offset = 16 + compressed_size
    for length in payload.get("binaryBufferLengths", ()):
        offset += (8 - offset % 8) % 8
        buffers.append(data[offset : offset + length])
        offset += length

    def restore(obj: Any) -> Any:
        if isinstance(obj, dict):
            if "__binary_index" in obj and "dtype" in obj:
                return np.frombuffer(buffers[obj["__binary_index"]], dtype=np.dtype(obj["dtype"]))
            return {k: restore(v) for k, v in obj.items()}
        if isinstance(obj, list):
            return [restore(v) for v in obj]
        return obj

    return [restore(m) for m in payload["messages"]]


class ClientLoop:
    """One event loop thread for many :class:`ViserWsClient` (a bench's room of followers: one thread per
    client would be hundreds of threads taking turns at the interpreter lock, each a switch interval
    late)."""

    def __init__(self) -> None:
        self.loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self.loop.run_forever, daemon=True, name="viser-ws-clients")
        self._thread.start()

    def close(self) -> None:
        self.loop.call_soon_threadsafe(self.loop.stop)
        self._thread.join(5.0)


class ViserWsClient:
    """A headless viser client running its own event loop thread (or the thread of a shared
    :class:`ClientLoop`).

    Attributes:
        messages: Every message received, as (perf_counter time, message dict), in order.
    """

    def __init__(
        self,
        url: str,
        width: int = 800,
        height: int = 600,
        headers: dict[str, str] | None = None,
        shared: ClientLoop | None = None,
    ) -> None:
        self.url = url
        self.headers = dict(
            headers or {}
        )  # extra handshake headers (Accept-Language, a proxy's X-Forwarded-For)
        self.size = (width, height)
        self.messages: list[tuple[float, dict[str, Any]]] = []
        self._cond = threading.Condition()
        self._loop = shared.loop if shared is not None else asyncio.new_event_loop()
        self._ws: Any = None
        self._error: BaseException | None = None
        self._thread: threading.Thread | None = None
        if shared is None:
            self._thread = threading.Thread(
                target=self._loop.run_forever, daemon=True, name="viser-ws-client"
            )

    def __enter__(self) -> ViserWsClient:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def start(self, timeout: float = POLL_TIMEOUT) -> None:
        """Connect and announce a camera (the server then builds this client's session).

        A worker of ``serve --workers N`` that is still starting closes a new tab with 1013 ("try again
        later"), or, on a busy machine, drops a connection it accepted before it could answer (no HTTP
        response); like viser's page, this client then connects again (at once, then every second).
        """
        if self._thread is not None:
            self._thread.start()
        end = time.monotonic() + timeout
        while True:
            try:
                asyncio.run_coroutine_threadsafe(self._connect(), self._loop).result(timeout)
            except (InvalidMessage, ConnectionResetError):
                if time.monotonic() > end:
                    raise
                time.sleep(1.0)
                continue
            with self._cond:  # the first message, or the close of a worker not yet serving
                while not self.messages and self._ws.close_code is None and time.monotonic() < end:
                    self._cond.wait(0.05)
            if self.messages or self._ws.close_code != 1013 or time.monotonic() > end:
                return
            time.sleep(1.0)  # viser's page: "retry immediately, then every second"

    async def _connect(self) -> None:
        self._ws = await websockets.connect(
            self.url,
            subprotocols=[f"viser-v{viser.__version__}"],
            max_size=None,
            compression=None,
            additional_headers=self.headers or None,
        )
        self._loop.create_task(self._receive())
        w, h = self.size
        await self._ws.send(
            self._encode(
                message_class("ViewerCameraMessage")(
                    wxyz=(1.0, 0.0, 0.0, 0.0),
                    position=(2.0, -2.0, 1.5),
                    fov=1.0,
                    near=0.01,
                    far=100.0,
                    image_height=h,
                    image_width=w,
                    look_at=(0.0, 0.0, 0.0),
                    up_direction=(0.0, 0.0, 1.0),
                )
            )
        )

    async def _receive(self) -> None:
        try:
            async for frame in self._ws:
                t = time.perf_counter()
                msgs = decode_frame(frame)
                with self._cond:
                    self.messages.extend((t, m) for m in msgs)
                    self._cond.notify_all()
        except websockets.ConnectionClosed:
            pass
        except BaseException as exc:  # surfaced by wait_for
            self._error = exc
            with self._cond:
                self._cond.notify_all()

    @staticmethod
    def _encode(message: Any) -> bytes:
        return msgspec.msgpack.encode(message.as_serializable_dict())

    def send(self, message: Any) -> None:
        """Send one client → server message."""
        data = self._encode(message)
        asyncio.run_coroutine_threadsafe(self._ws.send(data), self._loop).result(5.0)

    def send_bytes(self, data: bytes) -> None:
        """Send one raw binary frame (e.g. a malformed or oversized message, for tests of limits)."""
        asyncio.run_coroutine_threadsafe(self._ws.send(data), self._loop).result(30.0)

    def set_value(self, uuid: str, value: Any) -> float:
        """Change a GUI input as the browser would; returns the send time (perf_counter)."""
        t = time.perf_counter()
        self.send(message_class("GuiUpdateMessage")(uuid, {"value": value}))
        return t

    def mark(self) -> int:
        """Index of the next message to arrive (for :meth:`wait_for`)."""
        with self._cond:
            return len(self.messages)

    def wait_for(
        self, predicate: Callable[[dict[str, Any]], bool], after: int = 0, timeout: float = POLL_TIMEOUT
    ) -> tuple[float, dict[str, Any]]:
        """The first message from index ``after`` on that satisfies ``predicate``."""
        end = time.monotonic() + timeout
        i = after
        with self._cond:
            while True:
                while i < len(self.messages):
                    t, m = self.messages[i]
                    if predicate(m):
                        return t, m
                    i += 1
                if self._error is not None:
                    raise RuntimeError("the websocket client failed") from self._error
                left = end - time.monotonic()
                if left <= 0:
                    raise TimeoutError("no matching message arrived")
                self._cond.wait(left)

    def close(self) -> None:
        """Disconnect and stop the thread."""
        if self._ws is not None:
            try:
                asyncio.run_coroutine_threadsafe(self._ws.close(), self._loop).result(5.0)
            except Exception:
                pass
        if self._thread is not None:  # its own thread (a shared ClientLoop is closed by its owner)
            self._loop.call_soon_threadsafe(self._loop.stop)
            self._thread.join(5.0)
