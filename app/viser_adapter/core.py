"""viser's private API, part 1: protocol messages, page scripts, handle internals (see the package)."""

from __future__ import annotations

import contextlib
import ipaddress
import json
import logging
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any, TypeVar

import viser

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
    "clip",
    "client_address",
    "trusted_proxies",
    "forwarded_client",
    "quiet_banner",
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
            f"adapter was tested with viser{TESTED_VISER}; update app/viser_adapter/ for this version"
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


Network = ipaddress.IPv4Network | ipaddress.IPv6Network


def trusted_proxies(texts: Iterable[str]) -> tuple[Network, ...]:
    """The reverse proxies named by ``--trusted-proxy``: addresses (``127.0.0.1``) or networks
    (``10.0.0.0/8``).

    Raises:
        ValueError: a text is neither, named in words.
    """
    networks = []
    for text in texts:
        try:
            networks.append(ipaddress.ip_network(text.strip(), strict=False))
        except ValueError:
            raise ValueError(
                f"expected an IP address or network such as 127.0.0.1 or 10.0.0.0/8, got {clip(text, 80)!r}"
            ) from None
    return tuple(networks)


def _in(address: str, networks: Sequence[Network]) -> bool:
    try:
        ip = ipaddress.ip_address(address)
    except ValueError:
        return False
    if isinstance(ip, ipaddress.IPv6Address) and ip.ipv4_mapped is not None:
        ip = ip.ipv4_mapped  # a dual-stack socket's IPv4 peer, ::ffff:10.0.0.1
    return any(ip in network for network in networks)


def forwarded_client(peer: str, forwarded_for: Sequence[str], trusted: Sequence[Network]) -> str:
    """The client's address: ``peer`` (who opened the connection) unless ``peer`` is a trusted proxy;
    then the ``X-Forwarded-For`` hops (each proxy appends the address it was reached from) read from
    the right, past every trusted proxy, to the first address no trusted proxy is. What a client wrote
    into the header itself stands left of that and is never read; an untrusted peer's header is ignored.
    """
    if not _in(peer, trusted):
        return peer
    hops = [hop.strip() for field in forwarded_for for hop in field.split(",") if hop.strip()]
    address = peer
    for hop in reversed(hops):
        address = clip(hop, 60)
        if not _in(hop, trusted):
            break
    return address


def client_address(server: viser.ViserServer, client_id: int, trusted: Sequence[Network] = ()) -> str:
    """The network address (IP) tab ``client_id`` connected from, or ``""`` once it has gone.

    Through the server's connection table (``server._websock_server._live_connections``); behind a
    ``trusted`` reverse proxy, from its ``X-Forwarded-For`` header (:func:`forwarded_client`).
    """
    connections = _private(
        "client_address",
        "ViserServer._websock_server._live_connections",
        lambda: server._websock_server._live_connections,
    )
    connection = connections.get(client_id)
    address = getattr(connection, "remote_address", None)
    peer = str(address[0]) if isinstance(address, tuple) and address else ""
    if not peer or not trusted:
        return peer
    headers = getattr(getattr(connection, "request", None), "headers", None)
    hops = headers.get_all("X-Forwarded-For") if headers is not None else []
    return forwarded_client(peer, hops, trusted)


def client_header(server: viser.ViserServer, client_id: int, name: str) -> str:
    """The header ``name`` of the websocket handshake tab ``client_id`` connected with (at most 1024
    characters; ``""`` when it sent none or has gone), e.g. its ``Accept-Language``.

    Through the server's connection table (``server._websock_server._live_connections``) and the
    connection's handshake request (``websockets``' ``ServerConnection.request``).
    """
    connections = _private(
        "client_header",
        "ViserServer._websock_server._live_connections",
        lambda: server._websock_server._live_connections,
    )
    request = getattr(connections.get(client_id), "request", None)
    headers = getattr(request, "headers", None)
    value = headers.get(name, "") if headers is not None else ""
    return str(value)[:1024]


_QUIET = threading.Lock()


@contextlib.contextmanager
def quiet_banner() -> Iterator[None]:
    """viser's own console lines (its address box on start, "Server stopped" on stop) left out.

    viser prints them with ``rich.print`` whatever ``verbose`` says; the app prints one line of its own
    with the address (once for the whole server, not once per worker process). ``rich.print`` is
    swapped for the duration only (one block at a time).
    """
    import rich

    with _QUIET:
        original = rich.print
        rich.print = lambda *args, **kwargs: None
        try:
            yield
        finally:
            rich.print = original
