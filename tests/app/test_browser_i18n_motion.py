"""The Motion tab in Polish in a real headless Chromium whose locale is pl-PL (issue 27): the tab speaks
Polish from what the browser asks for (no ?lang=), plays the preset with its readout, charts and buttons
in Polish and decimal commas, and nothing of it is cut off at 1280×720 nor at a phone's 390×844.
Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's temporary directory).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from browser_helpers import ARGS, CHROMIUM, close_notifications, require_browser
from fakes import POLL_TIMEOUT, poll

from app.server import Lab

pytestmark = [pytest.mark.browser, pytest.mark.slow]

_CUT = """() => {
  const out = [];
  const width = document.documentElement.clientWidth;
  const shown = (e) => e.offsetParent !== null && e.getClientRects().length > 0 && e.textContent.trim();
  const sel = 'label, button, .mantine-Button-label, .u-title, .u-label, .jl-note, .jl-warn, .jl-live, ' +
    '.jl-live-foot, [role=tab]';
  for (const e of document.querySelectorAll(sel)) {
    if (!shown(e)) continue;
    const s = getComputedStyle(e);
    const r = e.getBoundingClientRect();
    if (r.width === 0 || r.height === 0) continue;
    const text = e.textContent.trim().slice(0, 90);
    const sideways = e.scrollWidth > e.clientWidth + 1 && s.overflowX !== 'visible';
    const downwards = e.scrollHeight > e.clientHeight + 1 && s.overflowY === 'hidden';
    const outside = r.right > width + 1 || r.left < -1;
    if (sideways || downwards || outside) out.push({text, cls: String(e.className).slice(0, 60),
      scroll: [e.scrollWidth, e.scrollHeight], client: [e.clientWidth, e.clientHeight], right: r.right});
  }
  return out;
}"""
"""Every visible label, button, tab, note, chart title and axis label whose text is cut (wider or taller
than its clipping box) or that runs out of the window. (Inputs' values are numbers and the robot's
title, not words of the catalogs: a phone's narrow boxes cut them in every language.)"""


_AXES = """(labels) => {
  const plots = [...document.querySelectorAll('.uplot .u-over')].filter((e) => e.offsetParent !== null);
  const c = document.createElement('canvas').getContext('2d');
  c.font = 'bold 12px system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", sans-serif';  // uPlot's
  return {plot: Math.min(...plots.map((e) => e.getBoundingClientRect().height)),
          labels: labels.map((t) => c.measureText(t).width)};
}"""
"""The charts' y-axis titles (drawn on the canvas along the plot, cut beyond it): each one's length
and the shortest plot's height [px]."""


def _out(tmp_path: Path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def _cut(page) -> list[dict]:
    """What :data:`_CUT` finds on the page as it is now."""
    return list(page.evaluate(_CUT))


@pytest.mark.parametrize(
    ("name", "viewport"),
    [("1280x720", {"width": 1280, "height": 720}), ("390x844", {"width": 390, "height": 844})],
)
def test_the_motion_tab_plays_the_preset_in_polish_and_nothing_is_cut_off(tmp_path, name, viewport):
    out = _out(tmp_path)
    lab = Lab(port=0)
    errors: list[str] = []
    try:
        sync_playwright = require_browser()
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=[*ARGS, "--lang=pl-PL"])
            try:
                page = browser.new_page(viewport=viewport, locale="pl-PL")  # navigator and Accept-Language
                page.set_default_timeout(POLL_TIMEOUT * 1000)
                page.set_default_navigation_timeout(POLL_TIMEOUT * 1000)
                page.on("pageerror", lambda exc: errors.append(f"pageerror: {exc}"))
                page.goto(lab.url)  # no ?lang=: the browser's pl-PL chooses
                page.wait_for_selector("[role=slider]")
                session = lab.session()
                poll(lambda: session.language == "pl", what="the tab speaking Polish")
                close_notifications(page)
                tab = page.locator('[role=tab]:has-text("Ruch")')
                phone = viewport["width"] < 800
                if not phone:
                    tab.first.click()  # its Polish title, as a student clicks it
                    page.get_by_text("Metoda jakobianowa: q̇ = J⁺v utrzymywane w czasie").first.wait_for()
                    page.get_by_role("button", name="Odtwórz", exact=True).click()
                else:  # a phone's sheet folds the tabs to one line: the tab's own Play, pressed in the server
                    page.screenshot(path=str(out / f"i18n_motion_pl_start_{name}.png"))
                    session.panel.motion._click(session.dispatch, "Play")
                poll(lambda: session.state.playing, what="the preset playing")
                # near the singularity the readout beside the arm says, in Polish, it is slowed down
                poll(
                    lambda: "spowolnione ×" in (page.locator(".jl-live").first.inner_text() or ""),
                    timeout=240,
                    what="the readout saying 'spowolnione ×'",
                )
                live = page.locator(".jl-live").first.inner_text()
                rates = re.findall(r"q̇[₁-₆]\s*([−-]?\d+,\d)\s*°/s", live)
                assert len(rates) == 6, live  # the rates with a decimal comma
                assert "odtwarzanie: utrzymywanie v" in live
                page.screenshot(path=str(out / f"i18n_motion_pl_playing_{name}.png"))
                cut = _cut(page)
                poll(lambda: not session.state.playing, timeout=240, what="the motion over")
                session.settle()
                if not phone:  # the charts' titles and axes in Polish
                    titles = page.locator(".u-title").all_inner_texts()
                    assert any(t.startswith("prędkości w przegubach") for t in titles), titles
                    assert any(t.startswith("współczynnik uwarunkowania κ (skala log.") for t in titles), (
                        titles
                    )
                    page.locator(".u-title", has_text="σmin i w").first.scroll_into_view_if_needed()
                page.screenshot(path=str(out / f"i18n_motion_pl_charts_{name}.png"))
                # each chart's y-axis title (turned on its side) fits the chart's height
                motion = session.panel.motion
                labels = [chart.axes[1]["label"] for chart in (motion.rates, motion.kappa, motion.measures)]
                axes = page.evaluate(_AXES, labels)
                assert axes["plot"] > 0 and all(width <= axes["plot"] for width in axes["labels"]), (
                    labels,
                    axes,
                )
                cut += _cut(page)
                assert not cut, cut
            finally:
                browser.close()
    finally:
        lab.stop()
    assert not errors, errors
