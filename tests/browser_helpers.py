"""Shared pieces of the headless-Chromium tests: the browser (skipped locally, a failure in CI when
missing), polling waits and canvas captures."""

from __future__ import annotations

import io
import os
import time

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
