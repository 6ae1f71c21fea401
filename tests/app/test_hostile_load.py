"""Points 4, 5 and 9 of issue 18, against the app in its own process: work whose cost grows with a
tab's input is capped in words and kept off the drawing thread, another tab's slider keeps answering,
a busy server stops within 5 s of SIGTERM, and one tab's downloads queue behind each other."""

from __future__ import annotations

import os
import signal
import subprocess
import time
import uuid

import pytest
from app_helpers import running_lab, wait_until
from fakes import poll
from hostile_helpers import RoundTrips, slider, widget
from server_process import Server
from wsclient import ViserWsClient

from app.core.build_table import MAX_ROWS
from app.services.symbolic_service import SymbolicService
from app.tab.robots import MAX_UPLOAD_JOINTS
from app.viser_adapter import UPLOAD_PART_BYTES, message_class

SERVE = "from app.server import serve; serve(robot='planar2', host='127.0.0.1', port=0, block=True)"
UPDATE = message_class("GuiUpdateMessage")


def chain_urdf(joints: int) -> bytes:
    links = "".join(f'<link name="l{i}"/>' for i in range(joints + 1))
    chain = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin xyz="0.01 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
        "</joint>"
        for i in range(joints)
    )
    return f'<?xml version="1.0"?><robot name="long">{links}{chain}</robot>'.encode()


def _notice(ws: ViserWsClient, mark: int, text: str, timeout: float = 60.0) -> str:
    _, m = ws.wait_for(
        lambda m: m["type"] == "NotificationShowMessage" and text in m["props"]["body"],
        after=mark,
        timeout=timeout,
    )
    return m["props"]["body"]


def _upload(ws: ViserWsClient, name: str, content: bytes) -> None:
    button = widget(ws, lambda m: m["type"] == "GuiUploadButtonMessage")
    transfer = uuid.uuid4().hex
    parts = [content[i : i + UPLOAD_PART_BYTES] for i in range(0, len(content), UPLOAD_PART_BYTES)]
    ws.send(
        message_class("FileTransferStartUpload")(button, transfer, name, "text/xml", len(parts), len(content))
    )
    for i, part in enumerate(parts):
        ws.send(message_class("FileTransferPart")(button, transfer, i, part))


def _rows_button(ws: ViserWsClient) -> str:
    return widget(ws, lambda m: m["type"] == "GuiButtonGroupMessage" and "+ Add" in m["props"]["options"])


def test_a_999_joint_urdf_is_refused_in_words_and_the_room_carries_on(tmp_path):
    server = Server(tmp_path, SERVE)
    try:
        with ViserWsClient(server.url()) as good, ViserWsClient(server.url()) as bad:
            with RoundTrips(good, slider(good)) as trips:
                slider(bad)
                for i in range(10):  # the ten uploads
                    mark = bad.mark()
                    _upload(bad, f"long{i}.urdf", chain_urdf(999))
                    body = _notice(bad, mark, "joints")
                    assert f"has 999 joints; an uploaded URDF may have at most {MAX_UPLOAD_JOINTS}" in body
                trips.check()
    finally:
        server.cleanup()


def test_a_50_joint_chain_is_refused_and_a_20_joint_one_draws(tmp_path):
    server = Server(tmp_path, SERVE)
    try:
        with ViserWsClient(server.url()) as good, ViserWsClient(server.url()) as bad:
            with RoundTrips(good, slider(good)) as trips:
                slider(bad)
                mark = bad.mark()
                _upload(bad, "fifty.urdf", chain_urdf(50))
                assert "its chain has 50 moving joints; at most 24 are shown" in _notice(
                    bad, mark, "moving joints"
                )
                mark = bad.mark()
                _upload(bad, "twenty.urdf", chain_urdf(20))
                bad.wait_for(
                    lambda m: m["type"] == "GuiSliderMessage" and m["props"]["label"].startswith("q20 "),
                    after=mark,
                    timeout=60,
                )
                trips.check(n=10)
    finally:
        server.cleanup()


def test_add_clicked_24_times_a_second_stops_at_the_row_limit(tmp_path):
    server = Server(tmp_path, SERVE)
    try:
        with ViserWsClient(server.url()) as good, ViserWsClient(server.url()) as bad:
            with RoundTrips(good, slider(good)) as trips:
                slider(bad)
                add, mark = _rows_button(bad), bad.mark()
                for _ in range(2 * MAX_ROWS):  # 48 clicks at 24/s, under the 25/s limit
                    bad.send(UPDATE(add, {"value": "+ Add"}))
                    time.sleep(1 / 24)
                _, m = bad.wait_for(
                    lambda m: m["type"] == "GuiUpdateMessage" and "at most 24 rows" in str(m.get("updates")),
                    after=mark,
                    timeout=60,
                )
                trips.check()
    finally:
        server.cleanup()


def _stop_time(server: Server) -> float:
    start = time.monotonic()
    os.kill(server.pid, signal.SIGTERM)
    try:
        server.proc.wait(60)
    except subprocess.TimeoutExpired:
        os.kill(server.pid, signal.SIGUSR1)  # the server prints every thread's stack to its log
        poll(lambda: "most recent call first" in server.log.read_text(), what="the stacks in the log")
        pytest.fail(f"still running 60 s after SIGTERM; its threads:\n{server.log.read_text()[-8000:]}")
    return time.monotonic() - start


def test_a_busy_server_stops_within_5_s_of_sigterm(tmp_path):
    """Busy (uploads building, rows being added), the server stops within 5 s of what an idle one
    takes on this machine now (measured first: a loaded machine slows both alike)."""
    (tmp_path / "idle").mkdir()
    idle = Server(tmp_path / "idle", SERVE)
    try:
        with ViserWsClient(idle.url()) as tab:
            slider(tab)
            reference = _stop_time(idle)
    finally:
        idle.cleanup()
    server = Server(tmp_path, SERVE)
    try:
        with ViserWsClient(server.url()) as bad:
            slider(bad)
            add = _rows_button(bad)
            for i in range(3):
                _upload(bad, f"twenty{i}.urdf", chain_urdf(20))
            for _ in range(20):
                bad.send(UPDATE(add, {"value": "+ Add"}))
            stopped = _stop_time(server)
        assert stopped < 5.0 + reference, f"stopped after {stopped:.1f} s (idle: {reference:.1f} s)"
    finally:
        server.cleanup()


@pytest.mark.slow
def test_one_tab_s_downloads_queue_behind_each_other_not_in_front_of_another_s():
    # The real symbolic worker: the order in which it takes the work is what is tested.
    with running_lab(robot="trr", symbolic=SymbolicService()) as (lab, hog, ws_hog):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as ws_other:
            wait_until(lambda: len(lab.sessions) == 2)
            other = next(s for s in lab.sessions.values() if s is not hog)
            download = lambda ws: [m for _, m in ws.messages if m["type"] == "FileTransferStartDownload"]  # noqa: E731
            labels = ["LaTeX", "Python", "JSON", "LaTeX"]
            for label in labels:  # four symbolic exports at once from one tab
                hog.commands._download(hog.state, label)
            asked = time.perf_counter()  # the other tab asks now (the clock of ws.messages' times)
            other.commands._download(other.state, "JSON")
            wait_until(lambda: download(ws_other), timeout=240)
            t_other = next(t for t, m in ws_other.messages if m["type"] == "FileTransferStartDownload")
            hog_times = [t for t, m in ws_hog.messages if m["type"] == "FileTransferStartDownload"]
            done_before_asking = sum(t < asked for t in hog_times)
            before_other = sum(t < t_other for t in hog_times)
            assert before_other <= done_before_asking + 1, (
                f"{before_other} of the first tab's downloads went before the other's "
                f"({done_before_asking} were done before it asked)"
            )
            wait_until(lambda: len(download(ws_hog)) == len(labels), timeout=240)


def test_a_newer_upload_cancels_a_pending_older_one_without_blocking_the_tab(monkeypatch):
    """A newer upload cancels the older one while it still waits for the pool: cancelling runs the older
    one's callback at once, on the drawing thread, which must not wait for a lock that thread holds
    (it did: a busy server then never stopped)."""
    import threading
    from concurrent.futures import Future
    from types import SimpleNamespace

    import app.tab.commands as commands
    from app.core.commands import UploadRobot

    pending: list[Future] = []
    pool = SimpleNamespace(submit=lambda fn: pending.append(Future()) or pending[-1])  # never started
    monkeypatch.setattr(commands, "background", lambda: pool)
    from app.core.i18n import translations

    notices = SimpleNamespace(preparing=lambda *a: lambda: None, error=lambda exc: None, tr=translations())
    runner = commands.CommandRunner(
        None, None, None, None, None, notices, lambda m: None, lambda: (None, None), lambda: False
    )
    done = threading.Event()

    def two_uploads() -> None:
        runner.run(None, UploadRobot("a.urdf", b"<robot/>"))
        runner.run(None, UploadRobot("b.urdf", b"<robot/>"))
        done.set()

    threading.Thread(target=two_uploads, daemon=True).start()
    assert done.wait(10), "the second upload blocked the drawing thread"
    assert pending[0].cancelled() and not pending[1].cancelled() and runner.building
