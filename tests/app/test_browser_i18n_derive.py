"""The Derive tab's Whitney walk in Portuguese, Spanish and Polish (issue 27), in a real headless Chromium
whose locale is the course's: the tab, the menu, the buttons and every step in the course's words with decimal commas, no
English word left on screen (names, symbols and numbers aside) and nothing cut off or wider than the
panel, at 1280×720. Screenshots: ``$APP_SCREENSHOT_DIR`` (default: pytest's
temporary directory)."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from browser_helpers import app_page
from fakes import FakeSymbolicService, poll
from i18n_words import english_only, words

from app.core.i18n import translations
from app.core.snapshot.derive import METHODS
from app.server import Lab

pytestmark = [pytest.mark.browser, pytest.mark.slow]

_SHOWN = """(head) => {
  const out = [];
  const step = [...document.querySelectorAll('.jl-step-head')].find(e => e.textContent === head);
  const root = step ? step.closest('.jl-views') : null;
  if (!root) return out;
  const walk = document.createTreeWalker(root, NodeFilter.SHOW_TEXT);
  for (let n = walk.nextNode(); n; n = walk.nextNode()) {
    const text = n.textContent.trim();
    const e = n.parentElement;
    if (!text || !e || e.closest('script,style,math,[aria-hidden=true],.mantine-Notifications-root')) continue;  // formulas: symbols
    const box = e.getBoundingClientRect();
    if (box.width === 0 || box.height === 0 || getComputedStyle(e).visibility === 'hidden') continue;
    if (e.offsetParent === null && getComputedStyle(e).position !== 'fixed') continue;
    const s = getComputedStyle(e);
    const cut = (s.textOverflow === 'ellipsis' || s.overflow === 'hidden') && e.scrollWidth > e.clientWidth + 1;
    out.push({text, cut});
  }
  return out;
}"""
_WIDEST = (
    "Math.max(0, ...[...document.querySelectorAll('.jl-vec, .jl-dh, .jl-t4s, .jl-step-head, .jl-formula')]"
    ".filter(e => e.offsetParent !== null).map(e => e.scrollWidth - e.clientWidth))"
)


@pytest.mark.parametrize(("locale", "code"), [("pt-BR", "pt"), ("es-AR", "es"), ("pl-PL", "pl")])
def test_the_whitney_walk_speaks_the_browsers_language_in_chromium(
    tmp_path, locale, code, width=1280, height=720
):
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    tr = translations(code)
    _ = tr.gettext
    english = english_only(code)
    lab = Lab(robot="puma560", port=0, symbolic=FakeSymbolicService())
    viewport = {"width": width, "height": height}
    with app_page(lab, viewport=viewport, locale=locale) as (page, session, errors):
        poll(lambda: session.language == code, what=f"the tab speaks {code}")
        robot = session.state.robot
        names = words(" ".join([robot.name, *(j.name for j in robot.joints)]))
        page.get_by_role("tab", name=_("Derive"), exact=True).click()
        table = page.locator(".jl-dh").first
        table.wait_for(state="attached")
        table.scroll_into_view_if_needed()
        page.get_by_text("θᵢ", exact=True).first.wait_for()  # the DH table
        page.get_by_label(_("Walk through"), exact=True).first.click()
        page.get_by_role("option", name=_(METHODS["whitney"]), exact=True).click()
        poll(lambda: session.state.options.derive == "whitney")
        for step in range(robot.dof):
            if step:
                page.get_by_role("button", name=_("Next ▶"), exact=True).click()
                poll(lambda s=step: session.state.options.derive_step == s)
            head = _("Step {i} of {n}: joint {i} ({name})").format(
                i=step + 1, n=robot.dof, name=robot.joints[step].name
            )
            page.get_by_text(head, exact=True).first.wait_for()
            check = page.get_by_text(_("equals column {i} of J(q)").format(i=step + 1), exact=False).first
            check.scroll_into_view_if_needed()
            assert check.is_visible()
            shown = page.evaluate(_SHOWN, head)  # the Derive tab's panel
            texts = " ".join(t["text"] for t in shown if not t["text"].startswith("fake "))
            assert head in texts and _("Walk through") in texts
            left = sorted((words(texts) - names) & english)
            where = [t["text"] for t in shown if set(left) & words(t["text"])]
            assert not left, f"step {step + 1}: English on the {code} screen: {left} in {where}"
            numbers = re.findall(r"\d+[.,]\d+", texts)
            assert numbers and not [x for x in numbers if "." in x], numbers
            cut = [t["text"] for t in shown if t["cut"]]
            assert not cut, f"step {step + 1}: cut off: {cut}"
            widest = page.evaluate(_WIDEST)
            assert widest <= 1, f"step {step + 1}: a Derive table overflows by {widest} px"
            if step in (0, robot.dof - 1):
                page.screenshot(path=str(out / f"derive_whitney_{code}_step{step + 1}_{width}x{height}.png"))
    assert not errors, errors
    assert session.errors == 0
