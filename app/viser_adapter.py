"""The one module that touches viser's private API; everything else in ``app/`` uses viser's public API.

Each function here wraps one private detail of viser (tested with the versions in
:data:`TESTED_VISER`). When an upgrade moves that detail, the function raises
:class:`ViserApiChanged` naming itself and the installed viser version, and
``tests/test_viser_adapter.py`` (which runs each function against a real
``viser.ViserServer``) fails with the same message.

Wrapped:
* :func:`message_class` — a protocol message class (``viser._messages``), for test clients.
* :func:`run_javascript` and :func:`set_page_title` — viser's ``RunJavascriptMessage``, sent
  to one client through ``client._websock_connection``.
* :func:`handle_uuid`, :func:`is_removed`, :func:`scene_handles`, :func:`node_props` — a handle's
  internal state (``handle._impl``) and a scene's node table (``SceneApi._handle_from_node_name``).
* :func:`install_message_limits` — what one websocket message and one tab may cost:
  replaces ``viser.infra._infra._message_consumer`` (looked up by viser's connection
  handler at call time) and the ``max_size`` viser passes to ``websockets``' ``serve``.
"""

from __future__ import annotations

import asyncio
import dataclasses
import inspect
import json
import logging
import threading
import traceback
from collections.abc import Callable
from typing import Any, TypeVar

import viser

from .ratelimit import TabLimiter

__all__ = [
    "TESTED_VISER",
    "ViserApiChanged",
    "message_class",
    "run_javascript",
    "set_page_title",
    "handle_uuid",
    "is_removed",
    "scene_handles",
    "node_props",
    "MessageLimits",
    "install_message_limits",
    "uninstall_message_limits",
    "clip",
]

log = logging.getLogger(__name__)

TESTED_VISER = ">=1.1.1,<1.2"
"""The viser versions this module was tested with (the same range as the pin in pyproject.toml)."""

T = TypeVar("T")


class ViserApiChanged(RuntimeError):
    """A private detail of viser that :mod:`app.viser_adapter` relies on is gone or changed.

    The message names the adapter function, what it looked for, and the installed viser version.
    """

    def __init__(self, function: str, detail: str) -> None:
        super().__init__(
            f"app.viser_adapter.{function}: {detail} — viser {viser.__version__} is installed, the "
            f"adapter was tested with viser{TESTED_VISER}; update app/viser_adapter.py for this version"
        )


def _private(function: str, what: str, get: Callable[[], T]) -> T:
    """``get()``, turning the errors of a moved attribute into :class:`ViserApiChanged`."""
    try:
        return get()
    except (AttributeError, ImportError, KeyError, TypeError) as exc:
        raise ViserApiChanged(function, f"{what} ({type(exc).__name__}: {exc})") from exc


def clip(text: object, limit: int = 200) -> str:
    """``str(text)`` cut to at most ``limit`` characters (with a note of the full length) for a log line."""
    s = str(text)
    if len(s) <= limit:
        return s
    return f"{s[: limit - 40]}… [{len(s)} characters]"


# --------------------------------------------------------------------------- messages and handles
def message_class(name: str) -> type:
    """The viser protocol message class called ``name`` (e.g. ``"GuiUpdateMessage"``).

    Raises:
        ViserApiChanged: viser has no such message class.
    """

    def get() -> type:
        from viser import _messages

        cls = getattr(_messages, name)
        if not (isinstance(cls, type) and issubclass(cls, _messages.Message)):
            raise TypeError(f"{name} is not a message class")
        return cls

    return _private("message_class", f"viser._messages.{name}", get)


def run_javascript(client: viser.ClientHandle, source: str) -> None:
    """Run the JavaScript ``source`` in this client's page (viser's ``RunJavascriptMessage``).

    The page runs it once when the message arrives; nothing is kept for later tabs.

    Raises:
        ViserApiChanged: the message class or the client's connection moved.
    """
    cls = message_class("RunJavascriptMessage")
    connection = _private("run_javascript", "client._websock_connection", lambda: client._websock_connection)
    _private("run_javascript", "queue_message", lambda: connection.queue_message(cls(source=source)))


_TITLE_SCRIPT = """(() => {
  window.__jacobianLabTitle = %s;
  const apply = () => {
    if (document.title !== window.__jacobianLabTitle) document.title = window.__jacobianLabTitle;
  };
  apply();
  if (!window.__jacobianLabTitleObserver) {
    window.__jacobianLabTitleObserver = new MutationObserver(apply);
    const options = {subtree: true, childList: true, characterData: true};
    window.__jacobianLabTitleObserver.observe(document.head, options);
  }
})();"""


def set_page_title(client: viser.ClientHandle, title: str) -> None:
    """Title this client's browser tab ``title`` (viser's says "Viser"), kept if the page resets it.

    ``title`` is passed as a JSON string literal, never as code.
    """
    run_javascript(client, _TITLE_SCRIPT % json.dumps(str(title)))


def handle_uuid(handle: Any) -> str:
    """The id of a GUI handle: its element's DOM ``id`` in the page (e.g. for per-slider CSS)."""
    uuid = _private("handle_uuid", "handle._impl.uuid", lambda: handle._impl.uuid)
    if not isinstance(uuid, str):
        raise ViserApiChanged("handle_uuid", f"handle._impl.uuid is a {type(uuid).__name__}, not a str")
    return uuid


def is_removed(handle: Any) -> bool:
    """Whether a GUI or scene handle was removed (its callbacks may still see late events)."""
    removed = _private("is_removed", "handle._impl.removed", lambda: handle._impl.removed)
    if not isinstance(removed, bool):
        raise ViserApiChanged("is_removed", f"handle._impl.removed is a {type(removed).__name__}, not a bool")
    return removed


def scene_handles(scene_api: Any) -> dict[str, Any]:
    """A copy of the scene's node table: node name (e.g. ``"/lab/arm"``) → handle, of ``server.scene`` or
    ``client.scene``."""
    table = _private(
        "scene_handles", "SceneApi._handle_from_node_name", lambda: scene_api._handle_from_node_name
    )
    return dict(table)


def node_props(handle: Any) -> dict[str, Any]:
    """The props the scene node ``handle`` sends to the browser, with ``position``, ``wxyz``, ``visible``."""

    def get() -> dict[str, Any]:
        impl = handle._impl
        return {**vars(impl.props), "position": impl.position, "wxyz": impl.wxyz, "visible": impl.visible}

    return _private("node_props", "handle._impl.props / position / wxyz / visible", get)


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
    closed: int = 0
    _lock: threading.Lock = dataclasses.field(default_factory=threading.Lock, repr=False)

    def count(self, field: str) -> None:
        with self._lock:
            setattr(self, field, getattr(self, field) + 1)


_limits: MessageLimits | None = None
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


def _serve_with_limit(*args: Any, **kwargs: Any) -> Any:
    """``websockets.asyncio.server.serve`` as viser calls it, with our ``max_size``."""
    if _limits is not None:
        kwargs["max_size"] = _limits.max_message_bytes
    return _original["websockets"].asyncio.server.serve(*args, **kwargs)


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
        protocol.max_message_size = limits.max_message_bytes  # for servers started before the install
    rate, burst = limits.max_messages_per_second, limits.burst
    gui_rate, gui_burst = limits.max_gui_updates_per_second, limits.gui_burst
    limiter = TabLimiter(rate, burst, gui_rate, gui_burst, limits.close_after_drops)
    wake = asyncio.Event()
    drain = loop.create_task(_drain(limiter, wake, handle_message, limits))
    peer = clip(getattr(websocket, "remote_address", "?"), 60)
    import websockets.exceptions as wse

    try:
        while True:
            try:
                raw = await websocket.recv()
            except wse.ConnectionClosedError as exc:
                if exc.sent is not None and exc.sent.code == 1009:
                    limits.count("closed")
                    log.warning(
                        "closed the connection of %s: a message over %d bytes", peer, limits.max_message_bytes
                    )
                raise
            try:
                if not isinstance(raw, bytes):
                    raise TypeError(f"a text frame of {len(raw)} characters")
                message = message_class.deserialize(raw)
            except Exception as exc:  # a hostile or broken client must not end the server's loop
                limits.count("malformed")
                log.warning("dropped a message from %s: %s: %s", peer, type(exc).__name__, clip(exc))
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
                    limits.count("closed")
                    log.warning(
                        "closed the connection of %s: over %g messages/s",
                        peer,
                        limits.max_messages_per_second,
                    )
                    await websocket.close(1008, "too many messages")
    finally:
        drain.cancel()


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


# --------------------------------------------------------------------------- faster prop assignment
_FAST_CAST_INSTALLED = False


def install_fast_prop_casts() -> None:
    """Make every handle prop assignment cheaper, with the same result.

    viser 1.1's ``AssignablePropsBase._cast_value_recursive`` builds four ``numpy.typing``
    aliases (``npt.NDArray[np.float32]``, ...) on every assignment to compare the prop's type
    hint with them: about a third of the cost of moving a scene node. This builds them once.
    Idempotent.

    Raises:
        ViserApiChanged: the method moved.
    """
    global _FAST_CAST_INSTALLED
    if _FAST_CAST_INSTALLED:
        return
    import numpy as np
    import numpy.typing as npt

    props_api = _private(
        "install_fast_prop_casts",
        "viser._assignable_props_api.AssignablePropsBase._cast_value_recursive",
        lambda: __import__("viser._assignable_props_api", fromlist=["AssignablePropsBase"]),
    )
    base = props_api.AssignablePropsBase
    if not callable(getattr(base, "_cast_value_recursive", None)):
        raise ViserApiChanged("install_fast_prop_casts", "AssignablePropsBase._cast_value_recursive is gone")
    f16, f32, f64, u8 = (npt.NDArray[t] for t in (np.float16, np.float32, np.float64, np.uint8))
    colors_to_uint8 = props_api.colors_to_uint8

    def cast(self: Any, hint: Any, value: Any, prop_name: str) -> Any:
        if hint == f32:
            return np.asarray(value).astype(np.float32)
        if hint == f64:
            return np.asarray(value).astype(np.float64)
        if hint == f16:
            return np.asarray(value).astype(np.float16)
        if hint == u8 and "color" in prop_name:
            return colors_to_uint8(value)
        if isinstance(value, np.ndarray):
            return value
        if (
            isinstance(value, tuple)
            and getattr(hint, "__origin__", None) is tuple
            and len(getattr(hint, "__args__", ())) == 2
            and hint.__args__[1] is ...
        ):
            element = hint.__args__[0]
            return tuple(cast(self, element, item, prop_name) for item in value)
        return value

    base._jl_original_cast = base._cast_value_recursive
    base._cast_value_recursive = cast
    _FAST_CAST_INSTALLED = True
