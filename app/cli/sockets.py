"""The listening sockets of ``jacobian-lab serve --workers N``: one per worker where the kernel balances
them, else one shared by every worker.

On Linux each worker accepts on a socket of its own, every one bound to the same address with
``SO_REUSEPORT``: the kernel puts them in one group and hashes each new connection (its addresses and
ports) over the group's listening sockets, so the tabs spread evenly over the workers, and a restarted
worker's new socket joins the group and takes its share of the new tabs at once. The parent keeps one
more socket bound to the address (not listening: it never receives a connection) so that the port
stays the server's while a worker restarts; each worker gets it and makes its own socket from it (a
dead worker's socket is gone with it: nothing is left to queue connections no one accepts).

Elsewhere (macOS and the BSDs give every connection to one of the sockets, Windows has no
``SO_REUSEPORT``) the workers share one listening socket as before: the operating system hands each
connection to a worker waiting in ``accept``, nearly always the same one.
"""

from __future__ import annotations

import os
import socket
import sys

from app.services.lifecycle import check_listen_address

__all__ = ["BALANCED", "listening_socket", "port_socket", "worker_socket"]

BALANCED = sys.platform.startswith("linux") and hasattr(socket, "SO_REUSEPORT")
"""Whether each worker gets a listening socket of its own, balanced by the kernel (Linux)."""

BACKLOG = 512
"""Connections a listening socket holds until its worker accepts them."""


def listening_socket(host: str, port: int, reuse_port: bool = False) -> socket.socket:
    """A TCP socket on ``host``: ``port``, or the next free port after it (as viser does): listening, or,
    with ``reuse_port``, only bound with ``SO_REUSEPORT`` (the port held for :func:`worker_socket`).

    Raises:
        ValueError: the address is not one of this machine's, or no port from ``port`` to ``port`` + 99
            is free.
    """
    check_listen_address(host, port)
    family, kind, proto, _, address = socket.getaddrinfo(
        host or None, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE
    )[0]
    last: OSError | None = None
    for attempt in range(port, port + 100) if port else [0]:
        sock = socket.socket(family, kind, proto)
        try:
            if reuse_port:  # first as any server binds: a port where another server listens is skipped
                # (else a second server of this user would join the first one's group)
                with socket.socket(family, kind, proto) as probe:
                    _reuse(probe, False)
                    probe.bind((address[0], attempt, *address[2:]))
                    attempt = probe.getsockname()[1]
            _reuse(sock, reuse_port)
            sock.bind((address[0], attempt, *address[2:]))
            if not reuse_port:
                sock.listen(BACKLOG)
                sock.setblocking(False)
            return sock
        except OSError as exc:
            sock.close()
            last = exc
    raise ValueError(f"cannot listen on {host!r}: ports {port} to {port + 99} are busy ({last})")


def port_socket(host: str, port: int) -> socket.socket:
    """The parent's socket: bound with ``SO_REUSEPORT`` (not listening) where :data:`BALANCED`, else the
    one listening socket every worker shares (see :func:`listening_socket`)."""
    return listening_socket(host, port, reuse_port=BALANCED)


def worker_socket(held: socket.socket) -> socket.socket:
    """A worker's socket, made in the worker from the parent's ``held`` socket: where :data:`BALANCED`, a
    new one bound to the same address with ``SO_REUSEPORT``, not listening yet (the worker's server
    listens as it starts serving: asyncio's ``create_server`` does, and the socket joins the group only
    then, so the kernel hands it no tab before its worker can take one); only the worker holds it, and
    when the worker ends the group's other sockets take its share. Elsewhere ``held`` itself (listening,
    shared)."""
    if not BALANCED:
        return held
    sock = socket.socket(held.family, held.type, held.proto)
    try:
        _reuse(sock, True)
        sock.bind(held.getsockname())
        sock.setblocking(False)
    except OSError:
        sock.close()
        raise
    return sock


def _reuse(sock: socket.socket, reuse_port: bool) -> None:
    """``SO_REUSEADDR`` (a restarted server takes its port back from the last run's closing
    connections), and ``SO_REUSEPORT`` for the sockets of one server's group."""
    if os.name != "nt":
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    if reuse_port:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
