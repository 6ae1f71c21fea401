"""The one module that touches viser's private API (checked by tests/test_viser_adapter.py)."""

from __future__ import annotations

import logging

import viser

__all__ = ["run_javascript", "handle_uuid", "is_removed"]

log = logging.getLogger(__name__)


def run_javascript(client: viser.ClientHandle, source: str) -> None:
    """Run ``source`` in this client's page (viser has no public API for it in 1.1)."""
    try:
        from viser._messages import RunJavascriptMessage

        client._websock_connection.queue_message(RunJavascriptMessage(source=source))  # type: ignore[attr-defined]
    except Exception:
        log.warning("cannot send a page script to client %s", client.client_id, exc_info=True)


def handle_uuid(handle: object) -> str:
    """The DOM id of a GUI handle's root element."""
    return str(handle._impl.uuid)  # type: ignore[attr-defined]


def is_removed(handle: object) -> bool:
    """Whether a GUI handle was removed."""
    return bool(handle._impl.removed)  # type: ignore[attr-defined]
