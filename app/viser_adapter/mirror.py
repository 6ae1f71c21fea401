"""viser's private API, part 4: the scene messages of one tab, replayed to others (see the package).

A presenter's redraw changes its scene nodes with messages addressed to its own client (each carries
an ``owner``: the client id). :func:`capture_scene` collects them while the presenter draws;
:func:`replay_scene` sends copies, re-addressed, to a follower whose scene has the same nodes, so a
room of followers costs one scene computation, not one per follower.
"""

from __future__ import annotations

import contextlib
import copy
from collections.abc import Iterator, Sequence
from typing import Any

import viser

from .core import ViserApiChanged, _private

__all__ = ["capture_scene", "replay_scene"]


def _connection(client: viser.ClientHandle, function: str) -> Any:
    conn = _private(function, "SceneApi._websock_interface", lambda: client.scene._websock_interface)
    if not callable(getattr(conn, "queue_message", None)):
        raise ViserApiChanged(function, "the scene's connection has no queue_message")
    return conn


@contextlib.contextmanager
def capture_scene(client: viser.ClientHandle) -> Iterator[list[Any]]:
    """Collect (and still send) the scene messages queued for ``client`` inside the block."""
    conn = _connection(client, "capture_scene")
    owner = str(client.client_id)
    captured: list[Any] = []
    original = conn.queue_message

    def queue(message: Any) -> None:
        if getattr(message, "owner", None) == owner:
            captured.append(message)
        original(message)

    conn.queue_message = queue  # an instance attribute: shadows the method for this connection only
    try:
        yield captured
    finally:
        with contextlib.suppress(AttributeError):
            del conn.queue_message


def replay_scene(client: viser.ClientHandle, messages: Sequence[Any]) -> None:
    """Send copies of ``messages`` (captured for another client) to ``client``'s scene."""
    conn = _connection(client, "replay_scene")
    owner = str(client.client_id)
    for message in messages:
        clone = copy.copy(message)
        clone.owner = owner
        conn.queue_message(clone)
