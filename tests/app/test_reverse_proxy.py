"""The nginx configuration of ``docs/classroom.md``, run as written: nginx (from Debian's
``nginx-light``, installed by ``tests/install_test_deps.py``) terminates TLS in front of a running lab
started with the options of the page's ``jacobian-lab serve`` line for a room behind the proxy
(``--allow-origin`` naming the public address, ``--trusted-proxy`` naming the proxy); the page and a
websocket (its GUI arrives) pass through it, and the lab knows the tab by the address nginx was reached
from, not by what the tab wrote in its own ``X-Forwarded-For``. Only the listening port, the
certificate and the upstream's port are changed for the test."""

from __future__ import annotations

import asyncio
import re
import shutil
import socket
import ssl
import subprocess
import urllib.request
from pathlib import Path

import msgspec
import pytest
import viser
import websockets
from app_helpers import running_lab
from fakes import poll
from wsclient import decode_frame

from app.cli.main import _build_parser
from app.viser_adapter import message_class

ROOT = Path(__file__).resolve().parents[2]
NGINX = shutil.which("nginx") or "/usr/sbin/nginx"
ORIGIN = "https://lab.example.org"


def _documented_config() -> str:
    text = (ROOT / "docs" / "classroom.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```nginx\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1, "docs/classroom.md has one nginx configuration"
    return blocks[0]


def _documented_room() -> dict:
    """The options of the page's ``jacobian-lab serve`` line for a room behind the proxy, as the
    command line reads them."""
    text = (ROOT / "docs" / "classroom.md").read_text(encoding="utf-8")
    lines = re.findall(
        r"^jacobian-lab (serve .*--allow-origin https://lab\.example\.org.*?)(?:#.*)?$", text, re.M
    )
    assert len(lines) == 1, lines
    args = _build_parser().parse_args(lines[0].split())
    return {"allow_origin": args.allow_origin, "trusted_proxy": args.trusted_proxy}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.slow
def test_the_documented_nginx_configuration_serves_the_page_and_its_websocket_over_tls(tmp_path):
    assert Path(NGINX).exists(), "nginx is missing: run python tests/install_test_deps.py"
    key, cert = tmp_path / "lab.key", tmp_path / "lab.pem"
    subprocess.run(
        [
            "openssl",
            "req",
            "-x509",
            "-newkey",
            "rsa:2048",
            "-nodes",
            "-days",
            "1",
            "-subj",
            "/CN=lab.example.org",
        ]
        + ["-keyout", str(key), "-out", str(cert)],
        check=True,
        capture_output=True,
    )
    room = _documented_room()
    assert room == {"allow_origin": [ORIGIN], "trusted_proxy": ["127.0.0.1"]}
    with running_lab(robot="planar2", presenter_token="Xq7-vR2pLw9sKd4TzY", **room) as (lab, _session, _ws):
        port = _free_port()
        config = _documented_config()
        for documented, ours in (
            ("listen 443 ssl;", f"listen 127.0.0.1:{port} ssl;"),
            ("server 127.0.0.1:8080;", f"server 127.0.0.1:{lab.port};"),
            ("/etc/ssl/certs/lab.example.org.pem", str(cert)),
            ("/etc/ssl/private/lab.example.org.key", str(key)),
        ):
            assert documented in config
            config = config.replace(documented, ours)
        temp = {name: tmp_path / name for name in ("client", "proxy", "fastcgi", "uwsgi", "scgi")}
        for folder in temp.values():
            folder.mkdir()
        (tmp_path / "nginx.conf").write_text(
            f"daemon off;\npid {tmp_path / 'nginx.pid'};\nerror_log {tmp_path / 'error.log'} info;\n"
            "events { worker_connections 256; }\n"
            "http {\n"
            f"access_log {tmp_path / 'access.log'};\n"
            f"client_body_temp_path {temp['client']};\nproxy_temp_path {temp['proxy']};\n"
            f"fastcgi_temp_path {temp['fastcgi']};\nuwsgi_temp_path {temp['uwsgi']};\n"
            f"scgi_temp_path {temp['scgi']};\n"
            f"{config}\n}}\n"
        )
        nginx = subprocess.Popen(
            [NGINX, "-p", str(tmp_path), "-c", str(tmp_path / "nginx.conf")],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
        )
        try:
            context = ssl.create_default_context(cafile=str(cert))
            context.check_hostname = False  # the test reaches it as 127.0.0.1, not lab.example.org

            def page() -> str:
                try:
                    url = f"https://127.0.0.1:{port}/"
                    with urllib.request.urlopen(url, context=context, timeout=10) as response:
                        return response.read().decode("utf-8", "replace")
                except OSError:
                    assert nginx.poll() is None, nginx.stderr.read().decode() if nginx.stderr else ""
                    return ""

            assert "<html" in poll(page, what="the page through nginx").lower()
            # A tab on 127.0.0.2 that wrote its own X-Forwarded-For: nginx appends the address it was
            # reached from, and the lab (trusting only nginx, 127.0.0.1) reads that one.
            # Read once the tab's session is registered and its handshake's headers are (the slider can
            # reach the page first; read before, the address was the proxy's, 127.0.0.1, in one CI run).
            tab_address = lambda: (
                poll(  # noqa: E731
                    lambda: lab.sessions and lab.classroom.address(max(lab.sessions)) == "127.0.0.2",
                    what="the tab's address read through the proxy",
                )
                and lab.classroom.address(max(lab.sessions))
            )
            assert asyncio.run(_websocket(port, context, tab_address)) == "127.0.0.2"
        finally:
            nginx.terminate()
            nginx.wait(10)


async def _websocket(port: int, context: ssl.SSLContext, address) -> str:
    """A tab's websocket through the proxy, from 127.0.0.2 with a forged ``X-Forwarded-For``, as a page
    of the public address opens it: once its first slider arrives, ``address()`` (what the lab reads)."""
    camera = message_class("ViewerCameraMessage")(
        (1.0, 0.0, 0.0, 0.0), (2.0, -2.0, 1.5), 1.0, 0.01, 100.0, 600, 800, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    )
    async with websockets.connect(
        f"wss://127.0.0.1:{port}",
        ssl=context,
        subprotocols=[f"viser-v{viser.__version__}"],
        origin=ORIGIN,
        max_size=None,
        compression=None,
        additional_headers={"X-Forwarded-For": "6.6.6.6"},
        local_addr=("127.0.0.2", 0),
    ) as ws:
        await ws.send(msgspec.msgpack.encode(camera.as_serializable_dict()))
        while True:
            for m in decode_frame(await asyncio.wait_for(ws.recv(), 60)):
                if m["type"] == "GuiSliderMessage":
                    return await asyncio.to_thread(address)
