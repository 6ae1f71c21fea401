"""A recorded demo plays from the player beside the notebook, in Chromium: a real kernel (nbclient, in the
folder of a real jupyter-server at a hub user's prefix) records and shows a demo, and the saved notebook
is small. The demo plays (its frames change) in the cell's output on a page of the Jupyter server (as
JupyterLab shows it: the player at {base_url}files/..., logged in with the server's token), and in the
nbconvert page beside the notebook opened from the disk and from another web server (the player by its
relative path)."""

from __future__ import annotations

import functools
import http.server
import os
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import ARGS, CHROMIUM, image, new_page, poll, require_browser
from jupyter_helpers import jupyter_server

from app.demo.player import PLAYER_DIR, player_name

pytestmark = [pytest.mark.browser, pytest.mark.slow]

PREFIX = "/user/ana/"


def _jupyter_server(root: Path, log: Path) -> tuple[subprocess.Popen, int]:
    """jupyter-server on 127.0.0.1 and a free port, at the hub's prefix (tests/jupyter_helpers.py)."""
    return jupyter_server(root, log, PREFIX, token="secret")


def _plays(page, shot: Path) -> str:
    """Wait for the demo's frame and see its 3-D view change as it plays; returns the frame's address."""
    box = page.locator("iframe").first
    box.wait_for()
    frame = box.content_frame
    view = frame.locator("canvas").first
    view.wait_for()
    seen = [image(view.screenshot())]

    def changed() -> bool:
        now = image(view.screenshot())
        moved = any((np.abs(now.astype(int) - s).max(axis=-1) > 60).mean() > 0.002 for s in seen)
        seen.append(now)
        return moved

    poll(changed, what="the demo's frames change")
    shown = box.element_handle().content_frame()
    shown.add_style_tag(content=".mantine-Notifications-root { display: none !important; }")  # headless GL
    page.wait_for_timeout(300)  # the style applied, for the screenshot
    page.screenshot(path=str(shot))
    return str(box.evaluate("f => f.src"))


def test_a_saved_notebook_plays_its_demo_from_the_player_beside_it(tmp_path, monkeypatch):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nbconvert = pytest.importorskip("nbconvert")
    pytest.importorskip("jupyter_server")
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    sync_playwright = require_browser()
    monkeypatch.setenv("JUPYTER_RUNTIME_DIR", str(tmp_path / "runtime"))  # this server alone, for both
    for name in ("VSCODE_PID", "VSCODE_CWD", "COLAB_RELEASE_TAG"):  # a kernel of Jupyter's, not VS Code's
        monkeypatch.delenv(name, raising=False)
    root = tmp_path / "root"
    folder = root / "course" / "week 1"
    folder.mkdir(parents=True)
    server, port = _jupyter_server(root, tmp_path / "jupyter.log")
    try:
        nb = nbformat.v4.new_notebook()
        nb.cells = [
            nbformat.v4.new_code_cell(
                "import robots\nfrom app.demo.record import record\nfrom app.notebook import show_recording\n"
                'show_recording(record("planar2", robots.load("planar2"), seconds=3, fps=10), height=360)'
            )
        ]
        client = nbclient.NotebookClient(
            nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(folder)}}
        )
        client.execute()
        saved = folder / "demo.ipynb"
        nbformat.write(nb, saved)
        assert saved.stat().st_size < 40_000  # the planar arm's 3 s: the recording and a script
        player = f"{PLAYER_DIR}/{player_name()}"
        assert (folder / player).is_file()
        (cell,) = [o["data"]["text/html"] for o in nb.cells[0].outputs if "text/html" in o.get("data", {})]
        served = f"{PREFIX}files/course/week%201/{player}"
        assert f'server="{served}"' in cell  # the kernel found its server's root and prefix
        body, _ = nbconvert.HTMLExporter().from_notebook_node(nbformat.read(saved, as_version=4))
        (folder / "demo.html").write_text(body, encoding="utf-8")
        handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(root))
        pages = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
        threading.Thread(target=pages.serve_forever, daemon=True).start()
        base = f"http://127.0.0.1:{port}"
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = new_page(browser, {"width": 1280, "height": 720})
                page.goto(f"{base}{PREFIX}api/status?token=secret")  # logged in, as the lab's user is
                # the notebook's page on the server's origin (JupyterLab's own page is not installed here)
                lab = f"{base}{PREFIX}lab/tree/course/week%201/demo.ipynb"
                shown = f"<!doctype html><meta charset=utf-8><title>demo.ipynb</title><body>{cell}</body>"
                page.route(lab, lambda route: route.fulfill(body=shown, content_type="text/html"))
                page.goto(lab)
                src = _plays(page, out_dir / "notebook_demo_in_jupyter.png")
                assert src.startswith(f"{base}{served}#")  # the server's player
                for address, shot in [
                    ((folder / "demo.html").as_uri(), "notebook_demo_export_file.png"),
                    (
                        f"http://127.0.0.1:{pages.server_address[1]}/course/week%201/demo.html",
                        "notebook_demo_export_web.png",
                    ),
                ]:
                    page = new_page(browser, {"width": 1280, "height": 720})
                    page.goto(address)
                    src = _plays(page, out_dir / shot)
                    assert src.startswith(address.rsplit("/", 1)[0] + f"/{player}#")  # the player beside it
            finally:
                browser.close()
                pages.shutdown()
    finally:
        server.terminate()
        server.wait(timeout=30)
