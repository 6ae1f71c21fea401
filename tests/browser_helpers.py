"""Shared pieces of the headless-Chromium tests: the browser (skipped locally, a failure in CI when
missing), polling waits and canvas captures."""

from __future__ import annotations

import contextlib
import io
import os
import time
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

__all__ = [
    "CHROMIUM",
    "ARGS",
    "VIEWPORT",
    "require_browser",
    "image",
    "wait",
    "canvas",
    "steady_canvas",
    "close_notifications",
    "app_page",
]

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


def require_browser():
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


def image(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)


def wait(predicate, timeout: float = 30.0) -> None:
    """Poll ``predicate`` every 50 ms until it holds, or fail after ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError("condition not reached in time")


def canvas(page) -> np.ndarray:
    return image(page.locator("canvas").first.screenshot())


def steady_canvas(page, timeout: float = 30.0) -> np.ndarray:
    """The 3-D view once two consecutive frames agree (rendering has caught up)."""
    end = time.monotonic() + timeout
    last = canvas(page)
    while time.monotonic() < end:
        now = canvas(page)
        if (np.abs(now - last).max(axis=-1) > 30).mean() < 0.0005:
            return now
        last = now
    raise AssertionError("the 3-D view never settled")


def close_notifications(page) -> None:
    """Keep the start-up toasts out of the way: hidden by a style sheet, so no click on a toast that is
    sliding in (or away) can time out on a busy machine, and React keeps its own nodes."""
    page.add_style_tag(content=".mantine-Notifications-root { display: none !important; }")


@contextlib.contextmanager
def app_page(
    lab, viewport: dict[str, int] | None = None, scale: float = 1.0
) -> Iterator[tuple[Any, Any, list[str]]]:
    """A headless-Chromium page (1280×720 unless ``viewport``; ``scale``: device pixels per CSS pixel,
    1.5 for a 150 % zoom) on ``lab``'s app, once its tab is drawn and its toasts are hidden:
    ``(page, session, errors)``, ``errors`` collecting the page's script errors. The browser closes and
    the lab stops on the way out (also when the browser is missing: skipped, or failed in CI).
    """
    errors: list[str] = []
    try:
        sync_playwright = require_browser()
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = browser.new_page(viewport=viewport or VIEWPORT, device_scale_factor=scale)
                page.on("pageerror", lambda exc: errors.append(f"pageerror: {exc}"))
                page.goto(lab.url)
                page.wait_for_selector("[role=slider]", timeout=120_000)
                session = lab.session()
                wait(lambda: session.snapshot is not None)
                close_notifications(page)
                yield page, session, errors
            finally:
                browser.close()
    finally:
        lab.stop()
