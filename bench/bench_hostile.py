"""The attacks of issue 18, measured against a server of the tree this script is run from.

Run from a checkout (``PYTHONPATH=$PWD python bench/bench_hostile.py``); each line says what one
attack did: memory grown, bytes a new tab downloads, another tab's slider round trips (median), how
long a busy server takes to stop. Run it on two commits to compare (the tests hold the bounds).
"""

from __future__ import annotations

import os
import signal
import statistics
import sys
import tempfile
import time
import uuid
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from server_process import Server, rss_bytes  # noqa: E402
from wsclient import ViserWsClient  # noqa: E402

from app.viser_adapter import message_class  # noqa: E402

SERVE = "from app.server import serve; serve(robot='planar2', host='127.0.0.1', port=0, block=True)"
PART = 512 * 1024
UPDATE = message_class("GuiUpdateMessage")


def _widgets(ws):
    return {m["uuid"]: m for _, m in list(ws.messages) if "uuid" in m and "props" in m}


def _slider(ws, prefix="q2 "):
    _, m = ws.wait_for(
        lambda m: m["type"] == "GuiSliderMessage" and m["props"]["label"].startswith(prefix), timeout=60
    )
    return m["uuid"]


def _trip(ws, uuid_, value):
    mark = ws.mark()
    sent = ws.set_value(uuid_, value)
    try:
        t, _ = ws.wait_for(lambda m: str(m.get("name", "")).startswith("/"), after=mark, timeout=10)
    except TimeoutError:
        return 10_000.0
    return (t - sent) * 1e3


def _settled(pid):
    last, now = -1, rss_bytes(pid)
    while abs(now - last) > 256 * 1024:
        time.sleep(0.5)
        last, now = now, rss_bytes(pid)
    return now


def _chain(n):
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        '<origin xyz="0.01 0 0"/>'
        f'<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for i in range(n)
    )
    return f'<?xml version="1.0"?><robot name="long">{links}{joints}</robot>'.encode()


def _upload(ws, button, name, content, parts=None, size=None):
    chunks = [content[i : i + PART] for i in range(0, len(content), PART)]
    transfer = uuid.uuid4().hex
    start = message_class("FileTransferStartUpload")
    ws.send(
        start(
            button,
            transfer,
            name,
            "text/xml",
            parts or len(chunks),
            size if size is not None else len(content),
        )
    )
    for i, c in enumerate(chunks):
        ws.send(message_class("FileTransferPart")(button, transfer, i, c))
        time.sleep(0.012)


def run(tmp: Path) -> None:
    server = Server(tmp, SERVE)
    try:
        with ViserWsClient(server.url()) as good, ViserWsClient(server.url()) as bad:
            g, _ = _slider(good), _slider(bad)
            time.sleep(2)
            w = _widgets(bad)
            start = next(u for u, m in w.items() if m["props"].get("label") == "Start from")
            button = next(u for u, m in w.items() if m["type"] == "GuiUploadButtonMessage")
            add = next(u for u, m in w.items() if "+ Add" in (m["props"].get("options") or ()))
            # 1: Start from a path
            mark = bad.mark()
            bad.send(UPDATE(start, {"value": str(Path("robots/data/puma560.toml").resolve())}))
            time.sleep(3)
            leaked = any(
                "0.4318" in str(m) for _, m in bad.messages[mark:] if m["type"] != "NotificationShowMessage"
            )
            print(f"1 Start from a robot file's path: DH table shown = {leaked}")
            # 2: form dirty
            idle = _settled(server.pid)
            dirty = message_class("GuiFormDirtyMessage")
            for i in range(450):
                bad.send(dirty(uuid=f"{i:05d}" + "x" * 60_000))
                time.sleep(0.011)
            grown = _settled(server.pid) - idle
            with ViserWsClient(server.url()) as late:
                _slider(late)
                time.sleep(1)
                size = sum(len(str(m)) for _, m in late.messages)
            print(
                f"2 form-dirty flood (27 MB): RSS +{grown / 1e6:.0f} MB; "
                f"a new tab receives {size / 1e6:.1f} MB"
            )
            # 3: upload parts beyond the declared size
            idle = _settled(server.pid)
            _upload(bad, button, "big.urdf", b"\0" * (200 * PART), parts=10**9, size=100)
            grown = _settled(server.pid) - idle
            print(f"3 upload declaring 100 bytes, sending 100 MiB: RSS +{grown / 1e6:.0f} MB")
            # 4: 999-joint uploads
            samples = []
            for i in range(3):
                _upload(bad, button, f"long{i}.urdf", _chain(999))
                for k in range(4):
                    samples.append(_trip(good, g, float(10 + k + 4 * i)))
            print(
                f"4 three 999-joint uploads: other tab's round trip median "
                f"{statistics.median(samples):.0f} ms, "
                f"max {max(samples):.0f} ms"
            )
            # 5: + Add at 24/s
            samples = []
            for i in range(120):
                bad.send(UPDATE(add, {"value": "+ Add"}))
                time.sleep(1 / 24)
                if i % 8 == 0:
                    samples.append(_trip(good, g, float(-20 + i % 40)))
            print(
                f"5 + Add at 24/s for 5 s: other tab's round trip median "
                f"{statistics.median(samples):.0f} ms, "
                f"max {max(samples):.0f} ms"
            )
            # 9: SIGTERM while busy
            for i in range(3):
                _upload(bad, button, f"long{i}.urdf", _chain(999))
            for _ in range(20):
                bad.send(UPDATE(add, {"value": "+ Add"}))
            t0 = time.monotonic()
            os.kill(server.pid, signal.SIGTERM)
            try:
                server.proc.wait(60)
                print(f"9 SIGTERM while busy: stopped after {time.monotonic() - t0:.1f} s")
            except Exception:
                print("9 SIGTERM while busy: still running after 60 s")
    finally:
        server.cleanup()


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as d:
        run(Path(d))
