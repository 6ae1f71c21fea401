"""Issue 26, point 2: the presenter link as a teacher gets it. The command line starts exactly as the
docs print it (``jacobian-lab serve --host 0.0.0.0 --presenter``: the default workers, one per core;
and ``serve --presenter --workers 1``), only on a free port; the link is read from what it prints,
opened in headless Chromium, and that tab presents with the token gone from the address bar. On the
old code the default (workers) printed ``…/#presenter=TOKEN``: the page stayed on "Connecting…" with
the token in the address bar. Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's temporary
directory)."""

from __future__ import annotations

import os
import urllib.parse
from pathlib import Path

import pytest
from browser_helpers import new_page, served_browser
from fakes import poll

from app.core.i18n import translations
from app.core.role import Role
from app.views.panel.classroom import compact_title

pytestmark = [pytest.mark.browser, pytest.mark.slow]


@pytest.mark.parametrize(
    ("argv", "lang"),
    [
        (["serve", "--host", "0.0.0.0", "--presenter"], ""),
        (["serve", "--presenter", "--workers", "1"], ""),
        # The panel is built again in the page's language (here ?lang=pl): the token must reach the new
        # box (on fe3d267: the first box's script took it and the Polish box stayed empty, not presenting).
        (["serve", "--presenter"], "pl"),
    ],
    ids=["default-workers", "one-process", "default-workers-pl"],
)
def test_the_printed_presenter_link_presents_and_leaves_no_token_in_the_address_bar(tmp_path, argv, lang):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    with served_browser(tmp_path, [*argv, "--port", "0"]) as (link, browser):
        token = urllib.parse.parse_qs(urllib.parse.urlsplit(link).query)["presenter"][0]
        assert "#" not in link and len(token) == 22  # 128 random bits, in the query
        page = new_page(browser)
        entries = page.evaluate("history.length")  # about:blank
        page.goto(link + (f"&lang={lang}" if lang else ""))
        page.wait_for_selector("[role=slider]")  # connected: the panel is drawn
        presenting = compact_title(Role(presenting=True), translations(lang or "en"))
        title = page.get_by_text(presenting, exact=False)
        poll(lambda: title.count() > 0 and title.first.is_visible(), what="the tab presents")
        page.screenshot(path=str(out / f"presenter_link_{'-'.join(argv[1:])}{lang}.png"))
        href = page.evaluate("location.href")
        assert token not in href and "presenter" not in href and token not in page.url, href
        # one entry for the link, rewritten in place: Back does not bring the token back
        assert page.evaluate("history.length") == entries + 1
