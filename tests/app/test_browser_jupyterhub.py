"""show() behind JupyterHub in Chromium: a real jupyter-server at a hub user's prefix (/user/ana/) with
jupyter-server-proxy; the cell's iframe, found from JUPYTERHUB_SERVICE_PREFIX alone (no url=), loads the
lab through the proxy, its websocket passes through it too, and the arm is drawn and moves."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import ARGS, CHROMIUM, image, new_page, poll, require_browser
from fakes import FakeSymbolicService
from jupyter_helpers import jupyter_server

from app.notebook import show

pytestmark = [pytest.mark.browser, pytest.mark.slow]

PREFIX = "/user/ana/"


def _jupyter_server(root: Path, log: Path) -> tuple[subprocess.Popen, int]:
    """jupyter-server on 127.0.0.1 and a free port, at the hub's prefix (tests/jupyter_helpers.py)."""
    pytest.importorskip("jupyter_server_proxy")
    return jupyter_server(root, log, PREFIX, token="")


def test_show_behind_jupyterhub_loads_the_lab_through_jupyter_server_proxy(tmp_path, monkeypatch):
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    sync_playwright = require_browser()
    monkeypatch.setattr("app.server.SymbolicService", FakeSymbolicService)
    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", PREFIX)  # as JupyterHub sets it in the kernel
    server, port = _jupyter_server(tmp_path, tmp_path / "jupyter.log")
    nb = show("planar2", height=460)  # no url=: the prefix says where the browser finds it
    try:
        assert nb.url == f"{PREFIX}proxy/{nb.lab.port}/"
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = new_page(browser, {"width": 1100, "height": 600})
                # the notebook's page on the hub's origin (JupyterLab's own page is not under test)
                notebook = f"http://127.0.0.1:{port}{PREFIX}lab/tree/hub.ipynb"
                cell = (
                    "<!doctype html><meta charset=utf-8><title>a hub notebook</title>"
                    "<body style='margin:16px;font:14px sans-serif'>"
                    f"<p>In [1]: lab = show('planar2')</p>{nb._repr_html_()}</body>"
                )
                page.route(notebook, lambda route: route.fulfill(body=cell, content_type="text/html"))
                page.goto(notebook)
                poll(lambda: len(nb.lab.sessions) == 1, what="the framed lab's websocket through the proxy")
                live = page.frame_locator("iframe")
                live.locator("[role=slider]").first.wait_for()
                frame = next(f for f in page.frames if f"{PREFIX}proxy/{nb.lab.port}/" in f.url)
                assert frame.url.startswith(f"http://127.0.0.1:{port}{PREFIX}proxy/")  # not the lab's port
                view = live.locator("canvas").first
                view.wait_for()

                def drawn() -> np.ndarray | None:
                    now = image(view.screenshot())
                    # the arm: pixels far from the background's colour (its most common one)
                    flat = now.reshape(-1, 3)
                    colours, counts = np.unique(flat, axis=0, return_counts=True)
                    off = np.abs(flat - colours[counts.argmax()]).max(axis=1) > 60
                    return now if off.mean() > 0.002 else None

                before = poll(drawn, what="the arm drawn in the proxied view")
                nb.set_q([0.9, -1.2])
                poll(
                    lambda: (np.abs(image(view.screenshot()) - before).max(axis=-1) > 60).mean() > 0.002,
                    what="the arm moved by set_q, through the proxy's websocket",
                )
                values = lambda: live.locator("input").evaluate_all("els => els.map(e => e.value)")  # noqa: E731
                poll(lambda: any(v.startswith("51.5") or v.startswith("51.6") for v in values()))  # 0.9 rad
                frame.add_style_tag(content=".mantine-Notifications-root { display: none !important; }")
                page.wait_for_timeout(500)  # the last frame of the move for the screenshot
                page.screenshot(path=str(out_dir / "jupyterhub_proxy_cell.png"))
            finally:
                browser.close()
    finally:
        nb.stop()
        server.terminate()
        server.wait(timeout=30)
