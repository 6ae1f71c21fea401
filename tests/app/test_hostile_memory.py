"""Memory attacks of issue 18 (points 2 and 3), against the app in its own process: the server's
memory stays within 50 MB of its idle figure, later tabs download nothing planted, and another tab's
slider keeps answering."""

from __future__ import annotations

import time
import uuid

from hostile_helpers import RoundTrips, slider, widget
from server_process import Server, rss_bytes
from wsclient import ViserWsClient

from app.viser_adapter import UPLOAD_PART_BYTES, message_class

SERVE = "from app.server import serve; serve(robot='planar2', host='127.0.0.1', port=0, block=True)"
MB = 1e6


def _settled_rss(pid: int) -> int:
    """RSS after it stopped moving (the server finished what it was sent)."""
    last, now = -1, rss_bytes(pid)
    end = time.monotonic() + 15
    while abs(now - last) > 256 * 1024 and time.monotonic() < end:
        time.sleep(0.3)
        last, now = now, rss_bytes(pid)
    return now


def test_form_dirty_messages_plant_nothing(tmp_path):
    """Point 2: 450 form-dirty messages of 60 kB each (27 MB) used to stay in the buffer every new tab
    replays; now they are refused as they enter."""
    dirty = message_class("GuiFormDirtyMessage")
    server = Server(tmp_path, SERVE)
    try:
        with ViserWsClient(server.url()) as good, ViserWsClient(server.url()) as bad:
            good_uuid = slider(good)
            slider(bad)
            idle = _settled_rss(server.pid)
            with RoundTrips(good, good_uuid) as trips:
                for i in range(450):  # a bounded attack, paced under the message rate limit
                    bad.send(dirty(uuid=f"{i:05d}" + "x" * 60_000))
                    time.sleep(0.011)
                trips.check()
            grown = _settled_rss(server.pid) - idle
            with ViserWsClient(server.url()) as late:
                slider(late)
                received = sum(len(str(m)) for _, m in late.messages)
                assert not [m for _, m in late.messages if m["type"] == "GuiFormDirtyMessage"]
        assert grown < 50 * MB, f"RSS grew by {grown / MB:.0f} MB"
        assert received < 5 * MB, f"a new tab received {received / MB:.1f} MB"
    finally:
        server.cleanup()


def test_an_upload_whose_parts_outgrow_its_declared_size_holds_nothing(tmp_path):
    """Point 3: size_bytes = 100 with part_count = 10⁹ and 200 parts of 512 KiB (100 MiB) used to be
    buffered; now the start is refused and no part is kept."""
    start_msg = message_class("FileTransferStartUpload")
    part_msg = message_class("FileTransferPart")
    server = Server(tmp_path, SERVE)
    try:
        with ViserWsClient(server.url()) as good, ViserWsClient(server.url()) as bad:
            good_uuid = slider(good)
            slider(bad)
            button = widget(bad, lambda m: m["type"] == "GuiUploadButtonMessage")
            idle = _settled_rss(server.pid)
            transfer = uuid.uuid4().hex
            mark = bad.mark()
            with RoundTrips(good, good_uuid) as trips:
                bad.send(start_msg(button, transfer, "big.urdf", "text/xml", 10**9, 100))
                chunk = b"\0" * UPLOAD_PART_BYTES
                for i in range(200):
                    bad.send(part_msg(button, transfer, i, chunk))
                    time.sleep(0.012)  # under the message rate limit: the attack of the issue
                trips.check()
            _, notice = bad.wait_for(lambda m: m["type"] == "NotificationShowMessage", after=mark, timeout=30)
            grown = _settled_rss(server.pid) - idle
        assert "parts for 100 bytes" in notice["props"]["body"], notice
        assert grown < 50 * MB, f"RSS grew by {grown / MB:.0f} MB"
    finally:
        server.cleanup()


def test_uploads_in_flight_are_bounded_per_tab(tmp_path):
    """Point 3: a tab may have two uploads under way; a third is refused in words until one ends."""
    start_msg = message_class("FileTransferStartUpload")
    server = Server(tmp_path, SERVE)
    try:
        with ViserWsClient(server.url()) as bad:
            slider(bad)
            button = widget(bad, lambda m: m["type"] == "GuiUploadButtonMessage")
            mark = bad.mark()
            for _ in range(3):  # declared, never sent: they stay in flight
                bad.send(start_msg(button, uuid.uuid4().hex, "a.urdf", "text/xml", 2, 2 * UPLOAD_PART_BYTES))
            _, notice = bad.wait_for(lambda m: m["type"] == "NotificationShowMessage", after=mark, timeout=30)
        assert "already has 2 uploads under way" in notice["props"]["body"], notice
    finally:
        server.cleanup()
