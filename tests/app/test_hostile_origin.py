"""Point 7 of issue 18: a page of another site (or a name rebound to this machine) cannot open the lab's
websocket from the teacher's browser; ``--allow-origin`` lets a deliberate embedding in."""

from __future__ import annotations

import socket
import urllib.error
import urllib.request

import pytest
import viser
import websockets.sync.client
from app_helpers import running_lab
from hostile_helpers import RoundTrips, slider
from websockets.exceptions import InvalidStatus
from wsclient import ViserWsClient

from app.cli.main import main
from app.viser_adapter import allow_origins


def _handshake(port: int, origin: str | None = None, host: str | None = None) -> int:
    """The HTTP status of a websocket handshake with these headers (101: accepted)."""
    try:  # the socket goes to this machine whatever name the URL says (as after DNS rebinding)
        with websockets.sync.client.connect(
            f"ws://{host or f'127.0.0.1:{port}'}",
            sock=socket.create_connection(("127.0.0.1", port), timeout=10),
            subprotocols=[f"viser-v{viser.__version__}"],
            origin=origin,
            open_timeout=10,
        ):
            return 101
    except InvalidStatus as exc:
        body = bytes(exc.response.body)
        assert b"may not connect" in body or b"not a name" in body, body
        return exc.response.status_code


def test_a_foreign_origin_or_host_is_refused_and_the_room_carries_on():
    with running_lab(robot="planar2") as (lab, session, ws):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as good:
            with RoundTrips(good, slider(good)) as trips:
                for _ in range(20):  # a page elsewhere retrying
                    assert _handshake(lab.port, origin="http://evil.example") == 403
                    assert _handshake(lab.port, origin="null") == 403  # a sandboxed frame, a file:// page
                    assert _handshake(lab.port, host=f"rebound.example:{lab.port}") == 403
                trips.check()
        assert _handshake(lab.port, origin=f"http://127.0.0.1:{lab.port}") == 101  # the lab's own page
        assert (
            _handshake(lab.port, origin=f"http://localhost:{lab.port}", host=f"localhost:{lab.port}") == 101
        )
        assert _handshake(lab.port) == 101  # no Origin: not a browser (it could send any header anyway)
        assert _handshake(lab.port, origin=f"http://127.0.0.1:{lab.port + 1}") == 403  # another port
        request = urllib.request.Request(f"http://127.0.0.1:{lab.port}/", headers={"Host": "rebound.example"})
        with pytest.raises(urllib.error.HTTPError) as page:
            urllib.request.urlopen(request, timeout=10)
        assert page.value.code == 403  # the page itself is not served under a foreign name


def test_allow_origin_lets_a_deliberate_embedding_connect():
    try:
        with running_lab(robot="planar2", allow_origin=["https://Course.Example.org"]) as (lab, session, ws):
            assert _handshake(lab.port, origin="https://course.example.org") == 101
            assert _handshake(lab.port, origin="https://course.example.org:444") == 403
            assert _handshake(lab.port, origin="http://evil.example") == 403
    finally:
        allow_origins(())


def test_allow_origin_on_the_command_line_is_checked(capsys):
    assert main(["serve", "--allow-origin", "course.example.org/page", "--port", "0"]) == 2
    assert "expected an origin such as https://" in capsys.readouterr().err
