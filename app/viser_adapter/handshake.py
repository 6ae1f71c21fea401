"""viser's private API, part 7: which pages may open a websocket to the lab (see the package).

A browser lets any page open a websocket to any address, ``127.0.0.1`` included, and says which page
in the ``Origin`` header; a page served under a name the attacker controls that resolves to this
machine (DNS rebinding) says that name in ``Host``. viser checks neither. Here every HTTP request
and websocket handshake of the server is checked before viser sees it (through the
``process_request`` hook viser gives ``websockets``' ``serve``, see :mod:`.limits`):

* ``Host`` must name this machine: an IP address, ``localhost``, this machine's host names, or the
  host of an origin allowed with ``--allow-origin``;
* ``Origin``, when the client sends one (a browser always does), must be the page's own address
  (the same scheme-less host and port as ``Host``) or an origin allowed with ``--allow-origin``.

A refused request gets ``403 Forbidden`` with the reason in words and is logged in one line.
"""

from __future__ import annotations

import ipaddress
import logging
import socket
import threading
from collections.abc import Iterable
from http import HTTPStatus
from typing import Any
from urllib.parse import urlsplit

from .core import clip

__all__ = ["allow_origins", "handshake_refusal", "normalized_origin"]

log = logging.getLogger("app.viser_adapter")

_lock = threading.Lock()
_allowed: frozenset[str] = frozenset()


def normalized_origin(text: str) -> str:
    """``scheme://host[:port]`` of an origin, lower case (raises ValueError for anything else)."""
    parts = urlsplit(text.strip())
    if parts.scheme not in ("http", "https") or not parts.hostname or parts.path not in ("", "/"):
        raise ValueError(f"expected an origin such as https://example.org:8443, got {clip(text, 80)!r}")
    if parts.query or parts.fragment or parts.username or parts.password:
        raise ValueError(f"an origin has no path, query, fragment or user: got {clip(text, 80)!r}")
    port = f":{parts.port}" if parts.port is not None else ""
    host = f"[{parts.hostname}]" if ":" in parts.hostname else parts.hostname
    return f"{parts.scheme}://{host}{port}".lower()


def allow_origins(origins: Iterable[str]) -> frozenset[str]:
    """Also accept pages from ``origins`` (a deliberate embedding), for every server of this process.

    Raises:
        ValueError: an origin is not ``http(s)://host[:port]``.
    """
    global _allowed
    allowed = frozenset(normalized_origin(o) for o in origins)
    with _lock:
        _allowed = allowed
    return allowed


def _host_name(host_header: str) -> str:
    """The host of a ``Host`` header (``name``, ``1.2.3.4`` or ``::1``), lower case."""
    host = host_header.strip().lower()
    if host.startswith("["):
        return host[1 : host.find("]")] if "]" in host else ""
    return host.rsplit(":", 1)[0] if host.count(":") == 1 else host


def _own_name(name: str) -> bool:
    try:
        ipaddress.ip_address(name)
        return True
    except ValueError:
        pass
    own = {"localhost", socket.gethostname().lower(), socket.getfqdn().lower()}
    own |= {f"{n.split('.')[0]}.local" for n in list(own)}
    with _lock:
        own |= {urlsplit(o).hostname or "" for o in _allowed}
    return name in own or name.endswith(".localhost")


def _all(headers: Any, name: str) -> list[str]:
    get_all = getattr(headers, "get_all", None)
    if get_all is not None:
        return list(get_all(name))
    value = headers.get(name)
    return [] if value is None else [value]


def handshake_refusal(headers: Any) -> str:
    """Why a request with these headers is refused, or ``""``."""
    hosts, origins = _all(headers, "Host"), _all(headers, "Origin")
    if len(hosts) != 1 or len(origins) > 1:
        return "not exactly one Host header and at most one Origin header"
    host, origin = hosts[0], (origins[0] if origins else None)
    if not _own_name(_host_name(host)):
        return f"Host {clip(host, 80)!r} is not a name of this server (start it with --allow-origin)"
    if origin is None:
        return ""  # not a browser: it could send any header it likes anyway
    with _lock:
        allowed = _allowed
    try:
        normal = normalized_origin(origin)
    except ValueError:
        return f"a page from {clip(origin, 80)!r} may not connect to this server (not a web address)"
    if normal in allowed or urlsplit(normal).netloc == host.strip().lower():
        return ""
    return (
        f"a page from {clip(origin, 80)} may not connect to this server "
        "(start it with --allow-origin for a deliberate embedding)"
    )


def checked_process_request(original: Any) -> Any:
    """viser's ``process_request`` (or none) behind the Host and Origin check."""

    def process_request(connection: Any, request: Any) -> Any:
        why = handshake_refusal(request.headers)
        if why:
            peer = clip(getattr(connection, "remote_address", "?"), 60)
            log.warning("refused a connection from %s: %s", peer, why)
            return connection.respond(HTTPStatus.FORBIDDEN, f"Jacobian Lab: {why}.\n")
        return original(connection, request) if original is not None else None

    return process_request
