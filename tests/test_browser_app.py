"""The app in a real headless Chromium: it loads, a keyboard-moved slider changes readouts and 3-D view.

Uses Debian's ``/usr/bin/chromium`` through Playwright (never ``playwright
install``). Where ``CI`` is set a missing browser or Playwright fails the
test; locally it is skipped. The final screenshot is saved to
``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory).
"""

from __future__ import annotations

import io
import math
import os
import time
from pathlib import Path

import numpy as np
import pytest

from app.server import Lab

CHROMIUM = "/usr/bin/chromium"
ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
VIEWPORT = {"width": 1280, "height": 720}

pytestmark = pytest.mark.browser


def _require_browser():
    """Playwright's sync API, or skip (fail in CI) when Chromium or Playwright is missing."""
    missing = []
    if not os.path.exists(CHROMIUM):
        missing.append(CHROMIUM)
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sync_playwright = None
        missing.append("the playwright package")
    if missing:
        message = f"browser test needs {' and '.join(missing)} (python tests/install_test_deps.py)"
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    return sync_playwright


def _image(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)


def _wait(predicate, timeout: float = 15.0) -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError("condition not reached in time")


def test_page_loads_and_a_keyboard_slider_changes_readouts_and_scene(tmp_path):
    sync_playwright = _require_browser()
    out_dir = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out_dir.mkdir(parents=True, exist_ok=True)
    lab = Lab(port=0)
    errors: list[str] = []
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = browser.new_page(viewport=VIEWPORT)
                page.on("pageerror", lambda exc: errors.append(f"pageerror: {exc}"))
                page.goto(lab.url)
                page.wait_for_selector("[role=slider]", timeout=30_000)
                session = lab.session()
                _wait(lambda: session.snapshot is not None and page.locator(".jl-matrix").count() > 0)
                for button in page.query_selector_all(".mantine-Notification-closeButton"):
                    button.click()
                status_before = page.locator(".jl-status").first.inner_text()
                assert "regular" in status_before
                matrix_before = page.locator(".jl-matrix").first.inner_text()
                time.sleep(0.5)  # let the first frames render
                canvas_before = _image(page.locator("canvas").first.screenshot())

                # Move the shoulder slider from the keyboard.
                slider = session.panel.joints.sliders[1]
                q_before = float(session.state.q[1])
                camera_before = session.client.camera.position.copy()
                thumb = page.locator(f'[id="{slider._impl.uuid}"] [role=slider]')
                if thumb.count() == 0:
                    thumb = page.locator(f'[id="{slider._impl.uuid}"]')
                thumb.first.focus()
                for _ in range(20):
                    page.keyboard.press("ArrowRight")
                _wait(lambda: session.state.q[1] > q_before + math.radians(5))
                _wait(lambda: page.locator(".jl-matrix").first.inner_text() != matrix_before)
                time.sleep(0.5)
                canvas_after = _image(page.locator("canvas").first.screenshot())
                # The arm moved, not the camera (arrow keys on a slider must not orbit the view).
                np.testing.assert_allclose(session.client.camera.position, camera_before, atol=1e-6)
                changed = np.abs(canvas_after - canvas_before).max(axis=-1) > 30
                assert changed.mean() > 0.002, f"the 3-D view barely changed ({changed.mean():.4%} of pixels)"

                # A singular configuration reads out in words and as ∞.
                page.get_by_role("button", name="wrist singular").click()
                _wait(lambda: "singular: wrist" in page.locator(".jl-status").first.inner_text())
                assert "∞" in page.locator(".jl-status").first.inner_text()
                body = page.locator("body").inner_text()
                assert "NaN" not in body and "nan" not in body.split()
                time.sleep(0.5)
                shot = out_dir / "app_browser.png"
                page.screenshot(path=str(shot))
                print(f"screenshot: {shot}")
            finally:
                browser.close()
    finally:
        lab.stop()
    assert not errors, errors
    assert session.errors == 0
