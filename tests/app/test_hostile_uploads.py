"""Unfinished uploads (issue 26, point 5): what they hold is given back when their tab leaves.

Measured on d6b043b with ``jacobian-lab serve`` (two workers): 30 tabs each starting 3 uploads of 2 MB
and sending 3 of their 4 parts grew the server tree's memory by 58 MB, all of it kept after the tabs
had gone (the parts were freed, but a closed tab's last part stayed in a reference cycle until the
cyclic collector ran, and glibc kept the freed heap for the process's own reuse)."""

from __future__ import annotations

import gc
import uuid

from app_helpers import wait_until
from fakes import FakeSymbolicService, poll
from hostile_helpers import widget
from wsclient import ViserWsClient

from app.server import Lab
from app.viser_adapter import UPLOAD_PART_BYTES, message_class

START = message_class("FileTransferStartUpload")
PART = message_class("FileTransferPart")


def _button(ws: ViserWsClient) -> str:
    return widget(ws, lambda m: m["type"] == "GuiUploadButtonMessage", timeout=120)


def test_a_closed_tab_keeps_no_part_of_an_unfinished_upload_for_the_cyclic_collector():
    """With the cyclic collector off, a tab that leaves right after a part leaves no part behind (its
    last part and frame, 1 MiB, were held by the message consumer's frame, in a cycle with the
    exception that ended it)."""

    def parts() -> int:
        return sum(1 for o in gc.get_objects() if type(o) is PART)

    gc.collect()
    gc.disable()
    lab = Lab(port=0, robot="planar2", symbolic=FakeSymbolicService())
    try:
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as ws:
            button = _button(ws)
            transfer = uuid.uuid4().hex
            ws.send(START(button, transfer, "arm.urdf", "text/xml", 2, 2 * UPLOAD_PART_BYTES))
            ws.send(PART(button, transfer, 0, b"\0" * UPLOAD_PART_BYTES))
            wait_until(lambda: lab.room.uploads_in_flight() == (1, 2 * UPLOAD_PART_BYTES), timeout=30)
        wait_until(
            lambda: not lab.server.get_clients() and lab.room.uploads_in_flight() == (0, 0), timeout=30
        )
        poll(lambda: parts() == 0, timeout=15, what="every FileTransferPart freed")
    finally:
        lab.stop()
        gc.enable()
