"""The notebook cells in Chromium: the live app framed by a page of another origin (as JupyterLab
frames it) connects and follows set_q, and a recorded demo plays from the player beside the page."""

from __future__ import annotations

import functools
import http.server
import os
import threading
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import ARGS, CHROMIUM, new_page, poll, require_browser
from fakes import FakeSymbolicService

import robots
from app.demo.record import record
from app.notebook import NotebookLab, show_recording
from app.server import Lab

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def test_a_notebook_page_frames_the_live_app_and_a_recorded_demo(tmp_path):
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    sync_playwright = require_browser()
    nb = NotebookLab(Lab(robot="planar2", port=0, symbolic=FakeSymbolicService()), height=460)
    notebook = tmp_path / "notebook"
    notebook.mkdir()
    rec = record("planar2", robots.load("planar2"), seconds=2, fps=10)
    demo = show_recording(rec, height=300, folder=notebook, inline=False)
    (notebook / "index.html").write_text(
        "<!doctype html><meta charset=utf-8><title>a notebook</title><body style='margin:16px;font:14px sans-serif'>"
        f"<p>In [1]: lab = show('planar2')</p>{nb._repr_html_()}"
        f"<p>In [2]: show_recording(...)</p>{demo._repr_html_()}</body>",
        encoding="utf-8",
    )
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(notebook))
    pages = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=pages.serve_forever, daemon=True).start()
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = new_page(browser, {"width": 1100, "height": 900})
                # the notebook's origin (localhost:P) is not the lab's (127.0.0.1:PORT)
                page.goto(f"http://localhost:{pages.server_address[1]}/")
                poll(lambda: len(nb.lab.sessions) == 1)  # the framed app passed the Origin check
                session = nb.lab.session()
                live = page.frame_locator("iframe[data-src]")
                live.locator("[role=slider]").first.wait_for()
                nb.set_q([0.5, -1.0])
                assert np.allclose(session.state.q, [0.5, -1.0])
                values = lambda: live.locator("input").evaluate_all("els => els.map(e => e.value)")  # noqa: E731
                poll(
                    lambda: any(v.startswith("28.6") for v in values())
                )  # q1 = 0.5 rad = 28.65° on its slider
                recorded = page.frame_locator("iframe[src*='jacobian-lab-player/']")
                recorded.locator("canvas").first.wait_for()
                page.wait_for_timeout(1500)  # let both canvases draw a frame for the screenshot
                page.screenshot(path=str(out_dir / "notebook_cells.png"), full_page=True)
            finally:
                browser.close()
    finally:
        pages.shutdown()
        nb.stop()
