"""viser's private API, part 2: what one websocket message and one tab may cost (see the package)."""

from __future__ import annotations

import asyncio
import dataclasses
import inspect
import logging
import socket
import threading
import traceback
from collections.abc import Callable
from typing import Any

from ..services.ratelimit import TabLimiter
from .core import ViserApiChanged, _private, clip
from .gate import check_message, room_limits
from .handshake import checked_process_request

__all__ = [
    "MessageLimits",
    "install_message_limits",
    "uninstall_message_limits",
    "UPLOAD_PART_BYTES",
    "MAX_UPLOAD_BYTES",
    "upload_too_large",
    "welcome_tabs",
]

UPLOAD_PART_BYTES = 512 * 1024
"""The browser sends an uploaded file in parts of this size (viser's ``UploadButton.tsx``)."""
MAX_UPLOAD_BYTES = 2 * 1024 * 1024
"""Largest file a tab may upload [bytes]; a larger one reaches its callback empty, marked (see
:func:`upload_too_large`), and its parts are never buffered."""
_TOO_LARGE = "\x00too-large\x00"

log = logging.getLogger("app.viser_adapter")


# --------------------------------------------------------------------------- message limits
@dataclasses.dataclass
class MessageLimits:
    """What one websocket message and one connection may cost, and counts of what was refused.

    Attributes:
        max_message_bytes: Largest message accepted [bytes]; a larger one closes the connection (1009).
        max_messages_per_second: Steady rate of messages passed on per connection [1/s]; above it
            messages wait, and a newer state of the same input (slider value, camera) replaces the
            waiting one, so that the last value sent is never lost.
        burst: Messages a connection may send at once above the rate; also the most that may wait.
        max_gui_updates_per_second, gui_burst: The same for GUI updates, each of which may cost a
            redraw (a browser sends at most ~20 per second while a slider is dragged).
        close_after_drops: A connection that had this many messages dropped (forgiven at the lower
            rate) is closed (1008).
        accepted: Messages passed on to viser, over all connections.
        dropped: Messages replaced by a newer state while waiting, or refused (too many waiting).
        malformed: Messages that could not be decoded (logged in one bounded line each).
        refused: Messages refused by :func:`.gate.check_message` (a value out of range, a form's
            dirty flag, ...).
        closed: Connections closed for violating a limit (too large or too many messages).
    """

    max_message_bytes: int = 64 * 1024
    max_messages_per_second: float = 100.0
    burst: int = 100
    close_after_drops: int = 500
    max_gui_updates_per_second: float = 25.0
    gui_burst: int = 25
    accepted: int = 0
    dropped: int = 0
    malformed: int = 0
    refused: int = 0
    closed: int = 0
    _lock: threading.Lock = dataclasses.field(default_factory=threading.Lock, repr=False)

    def count(self, field: str) -> None:
        with self._lock:
            setattr(self, field, getattr(self, field) + 1)


_limits: MessageLimits | None = None
_listen_socket: socket.socket | None = None
_welcome = threading.Event()  # a server on a shared socket serves tabs (its Lab is built)
_original: dict[str, Any] = {}


def install_message_limits(
    max_message_bytes: int = 64 * 1024,
    max_messages_per_second: float = 100.0,
    burst: int = 100,
    close_after_drops: int = 500,
    max_gui_updates_per_second: float = 25.0,
    gui_burst: int = 25,
) -> MessageLimits:
    """Limit what a browser tab's messages may cost every viser server in this process.

    Call before creating the ``viser.ViserServer`` (the size limit is then enforced by the
    websocket layer before a large message is buffered; servers already running get it from
    their next connection on). Calling again replaces the limits. A browser sends at most ~20
    GUI updates/s per input and a camera pose per frame; its messages are a few hundred bytes
    (file uploads and ``get_render`` images, unused here, would need a larger size).

    Errors in viser's handling of a message (e.g. a slider value that is not a number) are logged
    in one line with at most ~200 characters of the message's text.

    Returns:
        The active limits, whose counters the caller may read.
    """
    global _limits
    rates = (max_messages_per_second, burst, close_after_drops, max_gui_updates_per_second, gui_burst)
    numbers = (max_message_bytes, *rates)
    if max_message_bytes < 1024 or min(numbers) <= 0 or min(burst, gui_burst, close_after_drops) < 1:
        raise ValueError(
            f"install_message_limits: expected sizes >= 1024 and rates, bursts >= 1; got {numbers}"
        )
    infra = _private("install_message_limits", "viser.infra._infra", _infra_module)
    consumer = getattr(infra, "_message_consumer", None)
    if not (callable(consumer) and len(inspect.signature(consumer).parameters) == 3 and infra.websockets):
        raise ViserApiChanged(
            "install_message_limits", "viser.infra._infra._message_consumer(3 args) changed"
        )
    _limits = MessageLimits(*numbers)
    if not _original:
        _original["_message_consumer"] = infra._message_consumer
        _original["websockets"] = infra.websockets
        infra._message_consumer = _guarded_consumer
        ws = infra.websockets  # seen by viser.infra._infra only: the package with our serve()
        infra.websockets = _Overlay(
            ws, asyncio=_Overlay(ws.asyncio, server=_Overlay(ws.asyncio.server, serve=_serve_with_limit))
        )
    return _limits


def uninstall_message_limits() -> None:
    """Give viser back its own message handling (for tests)."""
    global _limits
    if _original:
        infra = _infra_module()
        infra._message_consumer = _original.pop("_message_consumer")
        infra.websockets = _original.pop("websockets")
    _limits = None


def _infra_module() -> Any:
    from viser.infra import _infra

    return _infra


def upload_too_large(file: Any) -> tuple[str, int] | None:
    """(file name, declared size [bytes]) of an upload refused for its size, else ``None``.

    An upload over :data:`MAX_UPLOAD_BYTES` reaches the upload button's callback as an empty
    ``UploadedFile`` whose name carries this mark, so the tab can say why in words.
    """
    name = getattr(file, "name", "")
    if not (isinstance(name, str) and name.startswith(_TOO_LARGE)):
        return None
    size, _, original = name[len(_TOO_LARGE) :].partition("\x00")
    return original, int(size) if size.isdigit() else 0


def _frame_limit(limits: MessageLimits) -> int:
    """Largest websocket frame read: a message, or one part of an upload (checked after decoding)."""
    return max(limits.max_message_bytes, UPLOAD_PART_BYTES + 4096)


def _checked_upload(message: Any, size: int, limits: MessageLimits) -> tuple[Any, str]:
    """``message`` as passed on, or why the connection is closed: only an upload's parts may exceed
    the message limit, and an upload declared over :data:`MAX_UPLOAD_BYTES` starts as an empty file."""
    kind = type(message).__name__
    if size > limits.max_message_bytes and kind != "FileTransferPart":
        return message, f"a message over {limits.max_message_bytes} bytes"
    if kind == "FileTransferStartUpload" and message.size_bytes > MAX_UPLOAD_BYTES:
        name = f"{_TOO_LARGE}{int(message.size_bytes)}\x00{message.filename}"
        return dataclasses.replace(message, filename=name, part_count=0, size_bytes=0), ""
    return message, ""


def _serve_with_limit(*args: Any, **kwargs: Any) -> Any:
    """``websockets.asyncio.server.serve`` as viser calls it (``serve(handler, host, port, ...)``), with
    our ``max_size``, every request's Host and Origin checked (:mod:`.handshake`), and on the listening
    socket given to :func:`listen_on` instead of host and port."""
    if _limits is not None:
        kwargs["max_size"] = _frame_limit(_limits)
    kwargs["process_request"] = checked_process_request(kwargs.get("process_request"))
    if _listen_socket is not None:
        args = args[:1]
        kwargs.pop("host", None)
        kwargs.pop("port", None)
        kwargs["sock"] = _listen_socket
        args = (_until_welcome(args[0]),)
    return _original["websockets"].asyncio.server.serve(*args, **kwargs)


def _until_welcome(handler: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """viser's connection handler, closing a tab's connection (1013, "try again later") until
    :func:`welcome_tabs`: a worker accepts on the shared socket as soon as its websocket server runs,
    before the viser server and the Lab around it are built (viser then fails on the half-built server
    and the tab stays connected to nothing). viser's page tries again at once, then every second."""

    async def until_welcome(connection: Any) -> Any:
        if not _welcome.is_set():
            await connection.close(1013, "Jacobian Lab is starting: try again")
            return None
        return await handler(connection)

    return until_welcome


def welcome_tabs() -> None:
    """The server on the shared socket (:func:`listen_on`) is built: serve the tabs that connect."""
    _welcome.set()


def listen_on(sock: socket.socket | None) -> None:
    """Make the next viser server of this process accept on ``sock`` (a listening socket shared by
    several worker processes, or a worker's own bound socket of a ``SO_REUSEPORT`` group, which the
    server's ``listen`` puts in the group as it starts serving) instead of binding its own host and
    port; ``None`` undoes it.

    Needs :func:`install_message_limits` first (its ``serve`` wrapper passes the socket on). Tabs that
    connect before :func:`welcome_tabs` are told to try again.
    """
    global _listen_socket
    if sock is not None and not _original:
        raise RuntimeError("listen_on: call install_message_limits() first")
    _listen_socket = sock
    if sock is not None:
        _welcome.clear()


class _Overlay:
    """A module seen through a few replaced attributes."""

    def __init__(self, real: Any, **overrides: Any) -> None:
        self._real = real
        self._overrides = overrides

    def __getattr__(self, name: str) -> Any:
        if name in self._overrides:
            return self._overrides[name]
        return getattr(self._real, name)


async def _guarded_consumer(
    websocket: Any, handle_message: Callable[[Any], None], message_class: Any
) -> None:
    """viser's ``_message_consumer`` with limits: size, rate (latest state kept), bounded logging."""
    limits = _limits
    if limits is None:  # uninstalled while a server runs: behave as viser does
        return await _infra_module()._message_consumer(websocket, handle_message, message_class)
    loop = _bound_loop_logging(asyncio.get_running_loop())
    protocol = getattr(websocket, "protocol", None)
    if protocol is not None and hasattr(protocol, "max_message_size"):
        protocol.max_message_size = _frame_limit(limits)  # for servers started before the install
    rate, burst = limits.max_messages_per_second, limits.burst
    gui_rate, gui_burst = limits.max_gui_updates_per_second, limits.gui_burst
    limiter = TabLimiter(rate, burst, gui_rate, gui_burst, limits.close_after_drops)
    wake = asyncio.Event()
    drain = loop.create_task(_drain(limiter, wake, handle_message, limits))
    peer = clip(getattr(websocket, "remote_address", "?"), 60)
    import websockets.exceptions as wse

    why = ""
    closing = False  # once closed for flooding, frames still buffered are discarded, not counted again
    try:
        while True:
            try:
                raw = await websocket.recv()
            except wse.ConnectionClosedError as exc:
                if exc.sent is not None and exc.sent.code == 1009 and not closing:  # (else counted below)
                    limits.count("closed")
                    log.warning(
                        "closed the connection of %s: a message over %d bytes", peer, _frame_limit(limits)
                    )
                raise
            if closing:
                continue
            refused = (
                f"a message over {limits.max_message_bytes} bytes"
                if len(raw) > limits.max_message_bytes
                else ""
            )
            try:
                if not isinstance(raw, bytes):
                    raise TypeError(f"a text frame of {len(raw)} characters")
                message = message_class.deserialize(raw)
                why = check_message(message)
                if not why:
                    message, refused = _checked_upload(message, len(raw), limits)
            except Exception as exc:  # a hostile or broken client must not end the server's loop
                if not refused:
                    limits.count("malformed")
                    log.warning("dropped a message from %s: %s: %s", peer, type(exc).__name__, clip(exc))
                    continue
            if why and not refused:
                limits.count("refused")
                room = room_limits()
                if room is not None:
                    room.refuse(peer, f"{type(message).__name__}: {why}")
                log.warning("refused a message of %s: %s", peer, clip(why))
                continue
            if refused:
                closing = True
                limits.count("closed")
                log.warning("closed the connection of %s: %s", peer, refused)
                await websocket.close(1009, "message too big")
                continue
            verdict = limiter.offer(message)
            if verdict == "now":
                limits.count("accepted")
                handle_message(message)
            elif verdict == "queued":
                wake.set()
            else:  # superseded by this newer state, or refused
                limits.count("dropped")
                if verdict == "close":
                    closing = True
                    limits.count("closed")
                    log.warning(
                        "closed the connection of %s: over %g messages/s",
                        peer,
                        limits.max_messages_per_second,
                    )
                    await websocket.close(1008, "too many messages")
    finally:
        drain.cancel()
        # The closing exception's traceback holds this frame in a cycle that only the cyclic collector
        # breaks: drop what the frame holds, the last frame and message read (an upload's part, 1 MiB
        # with its frame) and the messages waiting, so that they are freed when the tab leaves.
        limiter.clear()
        raw = message = None


async def _drain(limiter: TabLimiter, wake: asyncio.Event, handle: Callable, limits: MessageLimits) -> None:
    """Pass waiting messages on at the allowed rates."""
    while True:
        delay = limiter.wait_time()
        if delay == float("inf"):
            wake.clear()
            await wake.wait()
        elif delay > 0:
            await asyncio.sleep(delay)
        for message in limiter.pop_ready():
            limits.count("accepted")
            handle(message)


def _bound_loop_logging(loop: asyncio.AbstractEventLoop) -> asyncio.AbstractEventLoop:
    """Make the loop log an unhandled task error in one bounded line (viser's float cast quotes the value)."""
    if loop.get_exception_handler() is not _bounded_exception_handler:
        loop.set_exception_handler(_bounded_exception_handler)
    return loop


def _bounded_exception_handler(loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
    exc = context.get("exception")
    where = ""
    if isinstance(exc, BaseException) and exc.__traceback__ is not None:
        frames = traceback.extract_tb(exc.__traceback__)
        where = " at " + " < ".join(
            f"{f.name} ({f.filename.rsplit('/', 1)[-1]}:{f.lineno})" for f in frames[-3:][::-1]
        )
    text = f"{type(exc).__name__}: {clip(exc)}" if exc is not None else ""
    log.error("%s: %s%s", clip(context.get("message", "error in the event loop"), 80), text, clip(where, 300))
