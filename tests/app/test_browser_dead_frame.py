"""A saved notebook whose lab is gone keeps its picture, in Chromium: a real kernel runs show() (nbclient),
a browser tab draws the cell's lab, ``lab.stop()`` keeps the last picture in the cell's output, the
notebook is saved and exported (nbconvert), and the exported page, with no lab answering, shows that
picture and the line on how to start it again, in the notebook's language."""

from __future__ import annotations

import base64
import os
import re
from pathlib import Path

import numpy as np
import pytest
from browser_helpers import ARGS, CHROMIUM, image, new_page, poll, require_browser

from app.notebook_frame import restart_line

pytestmark = [pytest.mark.browser, pytest.mark.slow]

TESTS = Path(__file__).resolve().parents[1]


def _arm_pixels(rgb: np.ndarray) -> float:
    """Share of pixels far from the most common colour (the background): the arm and its glyphs."""
    flat = rgb.reshape(-1, 3).astype(int)
    colours, counts = np.unique(flat, axis=0, return_counts=True)
    return float((np.abs(flat - colours[counts.argmax()]).max(axis=1) > 60).mean())


def test_a_saved_notebook_shows_the_cells_last_picture_and_how_to_start_it_again(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nbconvert = pytest.importorskip("nbconvert")
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    sync_playwright = require_browser()
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_code_cell(
            # tests/fakes.py by its path: tests/ on sys.path would shadow the installed package
            # kinematics with the folder tests/kinematics (a namespace package, in an editable install)
            "import importlib.util, sys\n"
            f"spec = importlib.util.spec_from_file_location('fakes', {str(TESTS / 'fakes.py')!r})\n"
            "fakes = importlib.util.module_from_spec(spec); sys.modules['fakes'] = fakes\n"
            "spec.loader.exec_module(fakes)\n"
            "import app.server; app.server.SymbolicService = fakes.FakeSymbolicService"
        ),
        nbformat.v4.new_code_cell(
            'from app.notebook import show\nlab = show("planar2", height=420, lang="es")\nlab'
        ),
        nbformat.v4.new_code_cell("lab.set_q([0.9, -1.2]);"),
        nbformat.v4.new_code_cell("lab.stop(wait=120)"),  # a busy machine renders slowly
    ]
    client = nbclient.NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
        try:
            with client.setup_kernel():
                client.execute_cell(nb.cells[0], 0)
                client.execute_cell(nb.cells[1], 1)
                (cell,) = [o for o in nb.cells[1].outputs if "text/html" in o.get("data", {})]
                url = re.search(r'data-src="([^"]+)"', cell["data"]["text/html"]).group(1)
                tab = new_page(browser, {"width": 1100, "height": 620})
                tab.goto(url.replace("&amp;", "&"))  # the lab itself, as the cell's iframe shows it
                tab.locator("[role=slider]").first.wait_for()
                client.execute_cell(nb.cells[2], 2)  # the arm moves; the picture follows it
                poll(lambda: _arm_pixels(image(tab.locator("canvas").first.screenshot())) > 0.002)
                client.execute_cell(nb.cells[3], 3)  # stop(): the last picture kept in the output
                tab.close()
            saved = tmp_path / "saved.ipynb"
            nbformat.write(nb, saved)
            reopened = nbformat.read(saved, as_version=4)
            (kept,) = [o for o in reopened.cells[1].outputs if "text/html" in o.get("data", {})]
            found = re.search(r'src="data:image/jpeg;base64,([^"]+)"', kept["data"]["text/html"])
            assert found, "the saved output holds no picture"
            picture = image(base64.b64decode(found.group(1)))
            assert picture.shape[:2] == (420, int(420 * 16 / 9)) and _arm_pixels(picture) > 0.002
            body, _ = nbconvert.HTMLExporter().from_notebook_node(reopened)
            (tmp_path / "saved.html").write_text(body, encoding="utf-8")
            page = new_page(browser, {"width": 1280, "height": 720})
            page.goto((tmp_path / "saved.html").as_uri())  # no lab answers now
            cell_box = page.locator(".jlab-cell").first
            cell_box.scroll_into_view_if_needed()
            still = cell_box.locator("img")
            poll(lambda: still.evaluate("i => i.complete && i.naturalWidth") == int(420 * 16 / 9))
            line = cell_box.locator(".jlab-restart")
            assert line.is_visible() and line.inner_text() == restart_line("es")
            assert "Ejecutá la celda de nuevo" in line.inner_text()
            assert not cell_box.locator("iframe").is_visible()  # the probe found no lab: no error page
            shown = image(still.screenshot())
            assert _arm_pixels(shown) > 0.002  # the arm is in the picture the page shows
            cell_box.screenshot(path=str(out_dir / "dead_frame_saved_notebook.png"))
        finally:
            browser.close()
