"""app.viser_adapter's message limits against a real viser server: size, rate (latest state kept),
malformed messages and uploads, each closing or refusing only the connection at fault."""

from __future__ import annotations

import logging
import time

import msgspec
import pytest
import viser
import websockets.sync.client
from fakes import POLL_TIMEOUT, poll
from wsclient import ViserWsClient

from app import viser_adapter as va


@pytest.fixture
def limited():
    """Limits installed for one test (small, so that the test is fast), then viser's own handling back.
    The widget checks a Lab installs are taken off, so that viser's own handling of a bad value is seen
    (tests/app/test_hostile_values.py tests them)."""
    va.uninstall_input_checks()
    limits = va.install_message_limits(
        max_message_bytes=8 * 1024,
        max_messages_per_second=200.0,
        burst=50,
        close_after_drops=100,
        max_gui_updates_per_second=50.0,
        gui_burst=20,
    )
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield srv, limits
    finally:
        srv.stop()
        va.uninstall_message_limits()


def _raw_client(port: int):
    return websockets.sync.client.connect(
        f"ws://127.0.0.1:{port}", subprotocols=[f"viser-v{viser.__version__}"], max_size=None, close_timeout=1
    )


def _encode(message) -> bytes:
    return msgspec.msgpack.encode(message.as_serializable_dict())


def _camera() -> bytes:
    cls = va.message_class("ViewerCameraMessage")
    return _encode(cls((1.0, 0, 0, 0), (2.0, -2.0, 1.5), 1.0, 0.01, 100.0, 600, 800, (0, 0, 0), (0, 0, 1)))


def test_a_message_over_the_size_limit_closes_that_connection_only(limited):
    server, limits = limited
    with ViserWsClient(f"ws://127.0.0.1:{server.get_port()}") as good:
        poll(lambda: len(server.get_clients()) == 1)
        with _raw_client(server.get_port()) as bad:  # as its very first message
            with pytest.raises(websockets.exceptions.ConnectionClosed) as info:
                bad.send(b"\x00" * (64 * 1024))
                while True:  # the frames queued before the close, then the close frame
                    bad.recv(timeout=POLL_TIMEOUT)
            assert info.value.rcvd is not None and info.value.rcvd.code == 1009
        poll(lambda: limits.closed == 1)
        (client,) = server.get_clients().values()
        mark = good.mark()
        va.run_javascript(client, "1")
        good.wait_for(lambda m: m["type"] == "RunJavascriptMessage", after=mark)


@pytest.mark.slow
def test_a_flood_is_dropped_beyond_the_rate_and_then_closed(limited):
    server, limits = limited
    slider = server.gui.add_slider("q", min=0.0, max=10000.0, step=1.0, initial_value=0.0)
    calls = []
    slider.on_update(lambda e: calls.append(slider.value))
    update = va.message_class("GuiUpdateMessage")
    with _raw_client(server.get_port()) as bad:
        bad.send(_camera())
        poll(lambda: len(server.get_clients()) == 1)
        start = time.monotonic()
        with pytest.raises(websockets.exceptions.ConnectionClosed) as info:
            for i in range(1, 5001):
                bad.send(_encode(update(va.handle_uuid(slider), {"value": float(i)})))
            while True:
                bad.recv(timeout=POLL_TIMEOUT)
        elapsed = time.monotonic() - start
    assert info.value.rcvd is not None and info.value.rcvd.code == 1008
    poll(lambda: limits.closed == 1)
    assert limits.dropped >= 100
    # Accepted: the camera message, the burst and what the rate allowed until the close.
    assert 20 <= limits.accepted <= 20 + 50.0 * elapsed + 2
    poll(lambda: len(calls) == limits.accepted - 1)


def test_over_the_rate_only_the_latest_value_of_an_input_waits_and_it_arrives(limited):
    server, limits = limited
    slider = server.gui.add_slider("q", min=0.0, max=100.0, step=1.0, initial_value=0.0)
    update = va.message_class("GuiUpdateMessage")
    with ViserWsClient(f"ws://127.0.0.1:{server.get_port()}") as ws:
        poll(lambda: len(server.get_clients()) == 1)
        for i in range(1, 61):  # 60 changes at once: 20 pass (the GUI burst), the rest wait
            ws.send_bytes(_encode(update(va.handle_uuid(slider), {"value": float(i)})))
        poll(lambda: slider.value == 60.0)
        assert limits.closed == 0
        # The waiting changes of one slider collapse into its latest value: far fewer than 60 pass on.
        assert limits.accepted < 1 + 20 + 5
        assert limits.accepted + limits.dropped == 61


def test_a_bad_message_is_logged_in_one_bounded_line(limited, caplog):
    server, limits = limited
    slider = server.gui.add_slider("q", min=0.0, max=1.0, step=0.1, initial_value=0.5)
    update = va.message_class("GuiUpdateMessage")
    caplog.set_level(logging.WARNING)
    with ViserWsClient(f"ws://127.0.0.1:{server.get_port()}") as ws:
        poll(lambda: len(server.get_clients()) == 1)
        ws.send(update(va.handle_uuid(slider), {"value": "9" * 5000 + "x"}))  # float() quotes the value
        poll(lambda: any("could not convert" in r.getMessage() for r in caplog.records))
        ws.send_bytes(b"\xc1 not msgpack")
        poll(lambda: limits.malformed == 1)
        ws.set_value(va.handle_uuid(slider), 0.7)  # the connection still works
        poll(lambda: slider.value == 0.7)
    lines = [r.getMessage() for r in caplog.records if r.name == "app.viser_adapter"]
    assert len(lines) == 2
    assert all(len(line) < 700 for line in lines), [len(line) for line in lines]
    assert "could not convert" in lines[0] and "characters]" in lines[0] and "_handle_gui_updates" in lines[0]
    assert "DecodeError" in lines[1]


def test_only_an_upload_part_may_exceed_the_message_limit(limited):
    """The browser uploads in 512 KiB parts: those pass; any other large message, decodable or not,
    closes the connection (1009); an upload declared over the cap starts empty, marked as refused."""
    server, limits = limited
    button = server.gui.add_upload_button("up")
    got = []
    button.on_upload(lambda event: got.append(event.target.value))
    start, part = va.message_class("FileTransferStartUpload"), va.message_class("FileTransferPart")
    uuid = va.handle_uuid(button)
    content = b"x" * (va.UPLOAD_PART_BYTES + 10)
    with _raw_client(server.get_port()) as tab:
        tab.send(_camera())
        poll(lambda: len(server.get_clients()) == 1)
        tab.send(_encode(start(uuid, "t1", "a.urdf", "text/xml", 2, len(content))))
        tab.send(_encode(part(uuid, "t1", 0, content[: va.UPLOAD_PART_BYTES])))
        tab.send(_encode(part(uuid, "t1", 1, content[va.UPLOAD_PART_BYTES :])))
        poll(lambda: len(got) == 1)
        assert got[0].content == content and va.upload_too_large(got[0]) is None
        tab.send(_encode(start(uuid, "t2", "big.urdf", "text/xml", 100, 50 * 1024 * 1024)))
        poll(lambda: len(got) == 2)
        assert got[1].content == b"" and va.upload_too_large(got[1]) == ("big.urdf", 50 * 1024 * 1024)
        assert limits.closed == 0
        update = va.message_class("GuiUpdateMessage")
        with pytest.raises(websockets.exceptions.ConnectionClosed) as info:
            tab.send(_encode(update(uuid, {"value": "y" * 20_000})))  # decodable, over 8 KiB
            while True:
                tab.recv(timeout=POLL_TIMEOUT)
        assert info.value.rcvd is not None and info.value.rcvd.code == 1009
    poll(lambda: limits.closed == 1)


def test_a_worker_s_server_on_the_shared_socket_tells_tabs_to_try_again_until_its_lab_is_built():
    """A worker accepts on the shared socket as soon as its websocket server runs, before viser's server
    and the Lab around it are built: a tab then was connected to nothing for good (viser failed on the
    half-built server). Now it is closed with 1013 ("try again later": the page retries at once)."""
    from app.cli.workers import listening_socket

    va.install_message_limits()
    sock = listening_socket("127.0.0.1", 0)
    va.listen_on(sock)
    try:
        with va.quiet_banner():
            server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    finally:
        va.listen_on(None)
    try:
        with _raw_client(sock.getsockname()[1]) as early:
            with pytest.raises(websockets.exceptions.ConnectionClosed) as info:
                early.recv(timeout=POLL_TIMEOUT)
        assert info.value.rcvd is not None and info.value.rcvd.code == 1013
        assert "try again" in info.value.rcvd.reason
        assert not server.get_clients()
        va.welcome_tabs()  # what the Lab calls once built
        with _raw_client(sock.getsockname()[1]) as tab:
            assert tab.recv(timeout=POLL_TIMEOUT)  # served: viser's first messages arrive
    finally:
        server.stop()
        sock.close()
        va.uninstall_message_limits()
