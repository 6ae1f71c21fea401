"""Shared pieces of the headless-Chromium tests: the browser (skipped locally, a failure in CI when
missing), pages whose every wait polls with a generous safety net, and canvas captures."""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
from fakes import POLL_TIMEOUT, poll

__all__ = [
    "CHROMIUM",
    "ARGS",
    "VIEWPORT",
    "require_browser",
    "new_page",
    "canvas_box",
    "image",
    "poll",
    "canvas",
    "steady_canvas",
    "close_notifications",
    "app_page",
    "text_input",
    "type_into",
    "served_browser",
    "presenting_lab",
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


PHONE_USER_AGENT = (
    "Mozilla/5.0 (Linux; Android 14; Pixel 8) AppleWebKit/537.36 (KHTML, like Gecko) "
    "Chrome/156.0.0.0 Mobile Safari/537.36"
)
"""What Chromium on an Android phone sends (a touch page narrower than 600 px is given it)."""


def new_page(
    browser,
    viewport: dict[str, int] | None = None,
    scale: float = 1.0,
    locale: str | None = None,
    touch: bool = False,
):
    """A page of ``browser`` (default 1280×720, ``scale``: the device scale factor, 1.5 for a 150 %
    zoom; ``locale``: the browser's language, e.g. "pt-BR": its Accept-Language and navigator.language) whose Playwright waits (clicks, locators, screenshots, navigation) poll up to
    :data:`fakes.POLL_TIMEOUT` instead of Playwright's 30 s: a loaded machine makes a browser test
    slower, never red."""
    options: dict[str, Any] = {"locale": locale} if locale else {}
    if touch:  # a phone or tablet: a mobile viewport and touch events
        options.update(is_mobile=True, has_touch=True)
        if (viewport or VIEWPORT)["width"] < 600:  # a phone says so, as Chromium on Android does
            options["user_agent"] = PHONE_USER_AGENT
    page = browser.new_page(viewport=viewport or VIEWPORT, device_scale_factor=scale, **options)
    page.set_default_timeout(POLL_TIMEOUT * 1000)
    page.set_default_navigation_timeout(POLL_TIMEOUT * 1000)
    return page


def canvas_box(page) -> dict[str, float]:
    """The 3-D view's bounding box, once it has one with a size (the canvas is laid out after the
    first frames: read before, its box is missing or empty)."""

    def sized() -> dict[str, float] | None:
        box = page.locator("canvas").first.bounding_box()
        return box if box and box["width"] > 0 and box["height"] > 0 else None

    return poll(sized, what="the 3-D view laid out with a size")


def canvas(page) -> np.ndarray:
    """A capture of the 3-D view (once it has a size)."""
    canvas_box(page)
    return image(page.locator("canvas").first.screenshot())


def steady_canvas(page, timeout: float = POLL_TIMEOUT) -> np.ndarray:
    """The 3-D view once two consecutive frames agree (rendering has caught up)."""
    frames = [canvas(page)]

    def settled() -> np.ndarray | None:
        frames.append(canvas(page))
        last, now = frames[-2:]
        del frames[:-1]
        return now if (np.abs(now - last).max(axis=-1) > 30).mean() < 0.0005 else None

    return poll(settled, timeout, "the 3-D view settled (two frames alike)", interval=0.0)


def close_notifications(page) -> None:
    """Keep the start-up toasts out of the way: hidden by a style sheet, so no click on a toast that is
    sliding in (or away) can time out on a busy machine, and React keeps its own nodes."""
    page.add_style_tag(content=".mantine-Notifications-root { display: none !important; }")


@contextlib.contextmanager
def app_page(
    lab,
    viewport: dict[str, int] | None = None,
    scale: float = 1.0,
    locale: str | None = None,
    path: str = "",
    touch: bool = False,
) -> Iterator[tuple[Any, Any, list[str]]]:
    """A headless-Chromium page (1280×720 unless ``viewport``; ``scale``: device pixels per CSS pixel,
    1.5 for a 150 % zoom; ``locale``: the browser's language; ``path``: after the address, e.g.
    ``?lang=pl``; ``touch``: a phone's or tablet's touch screen) on ``lab``'s app, once its tab is drawn and its toasts are hidden:
    ``(page, session, errors)``, ``errors`` collecting the page's script errors. The browser closes and
    the lab stops on the way out (also when the browser is missing: skipped, or failed in CI).
    """
    errors: list[str] = []
    try:
        sync_playwright = require_browser()
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = new_page(browser, viewport, scale, locale, touch)
                page.on("pageerror", lambda exc: errors.append(f"pageerror: {exc}"))
                page.goto(lab.url + path)
                page.wait_for_selector("[role=slider]")
                session = lab.session()
                poll(lambda: session.snapshot is not None)
                close_notifications(page)
                yield page, session, errors
            finally:
                browser.close()
    finally:
        lab.stop()


_CONTRAST_JS = r"""() => {
  const parse = (c) => { const m = c.match(/rgba?\(([^)]+)\)/); if (!m) return null; const p = m[1].split(/[ ,\/]+/).filter(Boolean).map(Number); return [p[0], p[1], p[2], p.length > 3 ? p[3] : 1]; };
  const lum = (c) => { const f = (v) => { v /= 255; return v <= 0.03928 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4); }; return 0.2126 * f(c[0]) + 0.7152 * f(c[1]) + 0.0722 * f(c[2]); };
  const bgOf = (el) => { let layers = []; for (let e = el; e; e = e.parentElement) { const b = parse(getComputedStyle(e).backgroundColor); if (b && b[3] > 0) { layers.push(b); if (b[3] >= 1) break; } } let c = [255, 255, 255]; for (const l of layers.reverse()) c = [0,1,2].map(i => l[i] * l[3] + c[i] * (1 - l[3])); return c; };
  const out = [];
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  const fields = [...document.querySelectorAll("input, textarea")].filter(
    (e) => !["hidden", "checkbox", "radio", "range"].includes(e.type) && e.value.trim());
  const items = [];
  for (let n = walker.nextNode(); n; n = walker.nextNode()) items.push([n.textContent.trim(), n.parentElement]);
  for (const e of fields) items.push([e.type === "password" ? "•••" : e.value.trim(), e]);
  for (const [t, el] of items) {
    if (!t) continue;
    const r = el.getBoundingClientRect();
    if (r.width === 0 || r.height === 0 || r.bottom < 0 || r.top > innerHeight || r.right < 0 || r.left > innerWidth) continue;
    const s = getComputedStyle(el); if (s.visibility === "hidden" || s.display === "none") continue;
    let op = 1; for (let e = el; e; e = e.parentElement) op *= Number(getComputedStyle(e).opacity);
    if (op < 0.05) continue;
    const fg = parse(s.color); if (!fg) continue;
    const bg = bgOf(el); const f = [0,1,2].map(i => fg[i] * fg[3] * op + bg[i] * (1 - fg[3] * op));
    const L1 = lum(f), L2 = lum(bg); const ratio = (Math.max(L1, L2) + 0.05) / (Math.min(L1, L2) + 0.05);
    let zoom = 1; for (let e = el; e; e = e.parentElement) zoom *= parseFloat(getComputedStyle(e).zoom || 1);
    out.push({t: t.slice(0, 30), ratio: Math.round(ratio * 100) / 100, size: s.fontSize,
      px: Math.round(parseFloat(s.fontSize) * zoom * 100) / 100, color: s.color, bg: bg.map(Math.round).join(","), tag: el.tagName, cls: (el.className || "").toString().slice(0, 40)});
  }
  return out;
}"""


def text_contrasts(page) -> list[dict[str, Any]]:
    """Every visible text of the page in its viewport (the values in its inputs included): ``t`` (its
    start), ``ratio`` (WCAG contrast of its colour, with its own and its ancestors' opacity, over the backgrounds stacked behind it), ``size``
    (its computed font size), ``px`` (its size on screen [CSS px]: the font size times the zoom of its
    ancestors), ``color`` and ``bg``."""
    return list(page.evaluate(_CONTRAST_JS))


wait = poll
"""The name of :func:`fakes.poll` here before tests/fakes.py (for tests written before it)."""


def screenshot_dir(tmp_path) -> Any:
    """Where a browser test saves its screenshots: ``$APP_SCREENSHOT_DIR``, else pytest's ``tmp_path``."""
    import os
    from pathlib import Path

    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def whole_in_view(page, locator) -> bool:
    """Whether ``locator`` is drawn, whole, inside the page's viewport (a button one can click)."""
    box = locator.bounding_box()
    size = page.viewport_size
    return (
        box is not None
        and box["width"] > 0
        and box["height"] > 0
        and box["x"] >= 0
        and box["y"] >= 0
        and box["x"] + box["width"] <= size["width"]
        and box["y"] + box["height"] <= size["height"]
    )


def text_input(page, handle, kind: str = "input") -> Any:
    """The ``<input>`` of a viser text or number field (``handle``) on ``page``: the one in the row of
    its label (``kind``: a class to narrow it, e.g. ``input[contains(@class,'mantine-NumberInput-input')]``)."""
    from app.viser_adapter import handle_uuid

    return page.locator(f'label[for="{handle_uuid(handle)}"]').locator(
        f"xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]//{kind}"
    )


def type_into(page, handle, text: str) -> None:
    """Type ``text`` into ``handle``'s field as a person does: the field shown, filled, and the server
    holding the text before the next field is touched. (viser's panel sends every field's edits through
    one sender throttled to 50 ms, keeping only the latest message: two fields filled within 50 ms lose
    the first one's text, which no hand is quick enough to do.)"""
    field = text_input(page, handle)
    poll(field.is_visible, what=f"the field {handle.label!r} shown")
    field.fill(text)
    poll(lambda: str(handle.value) == text, what=f"the server holding {text!r} in {handle.label!r}")


@contextlib.contextmanager
def served_browser(tmp_path, argv: list[str]) -> Iterator[tuple[str, Any]]:
    """The app started as a user starts it (``jacobian-lab`` with ``argv``, e.g. ``serve --presenter``:
    :class:`server_process.Server`), the presenter link it printed, and a headless Chromium; both closed
    after the block. Yields ``(link, browser)``."""
    from server_process import Server, printed_presenter_link

    sync_playwright = require_browser()
    server = Server(tmp_path, argv=argv)
    try:
        link = printed_presenter_link(server)
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                yield link, browser
            finally:
                browser.close()
    finally:
        server.cleanup()


@contextlib.contextmanager
def presenting_lab(token: str, query: str = "") -> Iterator[tuple[Any, Any, Any, Any]]:
    """A lab in classroom mode (``token``) in this process, a headless Chromium, and a 1280×720 page opened
    at the presenter link (``query``: more of its address, e.g. ``&fixedDpr=1``) that now presents, its
    notifications out of the way; all closed after the block. Yields ``(lab, browser, page, session)``."""
    from app.server import Lab
    from app.services.presenter_token import presenter_link

    sync_playwright = require_browser()
    lab = Lab(port=0, presenter_token=token)
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = new_page(browser)
                page.goto(presenter_link(lab.url, token) + query)
                page.wait_for_selector("[role=slider]")
                presenter = lab.session()
                poll(lambda: presenter.role.presenting, what="the first tab presents")
                close_notifications(page)
                yield lab, browser, page, presenter
            finally:
                browser.close()
    finally:
        lab.stop()
