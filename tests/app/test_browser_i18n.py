"""Every course in its own language, in a real headless Chromium whose locale is the course's (issue 27):
its Accept-Language and navigator.language choose the tab's language; at the Puma's wrist singularity the
panel's words are that language's (no English message of the catalogs left on screen), its numbers have
the language's decimal mark, and no text is cut off at 1280×720. Screenshots: ``$APP_SCREENSHOT_DIR``
(default: pytest's temporary directory)."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from babel.messages.pofile import read_po
from browser_helpers import app_page
from fakes import FakeSymbolicService, poll

from app.core.actions import GoTo
from app.core.i18n import LOCALE_DIR, translations
from app.server import Lab
from app.views.panel import TAB_LABELS

pytestmark = [pytest.mark.browser, pytest.mark.slow]

_TEXTS = """() => {
  const out = [];
  const walk = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  for (let n = walk.nextNode(); n; n = walk.nextNode()) {
    const text = n.textContent.trim();
    const e = n.parentElement;
    if (!text || !e || e.closest('script,style,[aria-hidden=true],.mantine-Notifications-root')) continue;
    const box = e.getBoundingClientRect();
    if (box.width === 0 || box.height === 0 || getComputedStyle(e).visibility === 'hidden') continue;
    if (e.offsetParent === null && getComputedStyle(e).position !== 'fixed') continue;
    const s = getComputedStyle(e);
    const cut = s.textOverflow === 'ellipsis' && e.scrollWidth > e.clientWidth + 1;
    out.push({text, cut, tag: e.tagName});
  }
  return out;
}"""


def _out(tmp_path: Path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def _english_only(code: str) -> set[str]:
    """The catalog's English messages that this language writes otherwise (their plain text)."""
    if code == "en":
        return set()
    tr = translations(code)
    with (LOCALE_DIR / "messages.pot").open("rb") as f:
        template = read_po(f)
    out = set()
    for m in template:
        if not m.id or m.pluralizable or m.context:
            continue
        if tr.gettext(m.id) != m.id and "{" not in m.id:
            out.add(re.sub(r"<[^>]*>", "", m.id).replace("**", "").strip())
    return {t for t in out if len(t) > 3}


@pytest.mark.parametrize(
    ("locale", "code", "status"),
    [
        ("pt-BR", "pt", "configuração singular: punho"),
        ("es-AR", "es", "configuración singular: muñeca"),
        ("pl-PL", "pl", "konfiguracja osobliwa: nadgarstek"),
        ("en-US", "en", "singular: wrist"),
    ],
)
def test_the_puma_at_its_wrist_singularity_speaks_the_browsers_language(tmp_path, locale, code, status):
    out = _out(tmp_path)
    with app_page(Lab(port=0, symbolic=FakeSymbolicService()), locale=locale) as (page, session, errors):
        poll(lambda: session.language == code, what=f"the tab speaks {code}")
        session.dispatch(GoTo("wrist_singular"))
        session.settle()
        banner = page.locator(".jl-status").first
        poll(lambda: status in banner.inner_text(), what=f"the status says {status!r}")
        page.screenshot(path=str(out / f"i18n_{code}_puma_wrist_singular_1280x720.png"))
        texts = page.evaluate(_TEXTS)
        shown = {t["text"] for t in texts}
        english = _english_only(code)
        left = sorted(shown & english)
        assert not left, f"English left on a {code} screen: {left}"
        numbers = re.findall(r"\d+[.,]\d+", " ".join(shown))
        if code != "en":
            assert numbers and not [x for x in numbers if "." in x], numbers
        cut = [t["text"] for t in texts if t["cut"]]
        assert not cut, f"cut off: {cut}"
        assert not errors


@pytest.mark.parametrize(("locale", "code"), [("pt-BR", "pt"), ("es-AR", "es"), ("pl-PL", "pl")])
def test_the_motion_tab_plays_the_preset_in_the_browsers_language(tmp_path, locale, code):
    out = _out(tmp_path)
    _ = translations(code).gettext
    with app_page(Lab(port=0, symbolic=FakeSymbolicService()), locale=locale) as (page, session, errors):
        poll(lambda: session.language == code, what=f"the tab speaks {code}")
        page.get_by_role("tab", name=_("Motion")).click()
        page.get_by_role("button", name=_("Play"), exact=True).click()
        poll(lambda: session.state.motion.trace is not None and len(session.state.motion.trace) > 20)
        page.screenshot(path=str(out / f"i18n_{code}_motion_playing_1280x720.png"))
        texts = page.evaluate(_TEXTS)
        shown = {t["text"] for t in texts}
        left = sorted(shown & _english_only(code))
        assert not left, f"English left on a {code} screen: {left}"
        assert _("Resolved rate: q̇ = J⁺v held in time") in shown
        cut = [t["text"] for t in texts if t["cut"]]
        assert not cut, f"cut off: {cut}"
        assert not errors


@pytest.mark.parametrize(("locale", "code"), [("pt-BR", "pt"), ("pl-PL", "pl"), ("en-US", "en")])
def test_the_longer_phrases_are_whole_at_a_phones_width(tmp_path, locale, code):
    out = _out(tmp_path)
    phone = {"width": 390, "height": 844}
    with app_page(Lab(port=0, symbolic=FakeSymbolicService()), phone, locale=locale) as (
        page,
        session,
        errors,
    ):
        poll(lambda: session.language == code, what=f"the tab speaks {code}")
        session.dispatch(GoTo("wrist_singular"))
        session.settle()
        poll(lambda: page.locator(".jl-status").first.is_visible())
        page.screenshot(path=str(out / f"i18n_{code}_phone_390x844.png"))
        texts = page.evaluate(_TEXTS)
        # viser's one-line summary of the folded tab list ("J(q) · … · Build") ends in "…" at a phone's
        # width in every language, English too: its tabs open whole.
        summary = " · ".join(translations(code).gettext(label) for label in TAB_LABELS)
        cut = [t["text"] for t in texts if t["cut"] and t["text"] != summary]
        assert not cut, f"cut off at 390 px: {cut}"
        assert not errors


def test_a_link_naming_the_tab_in_another_language_opens_that_tab_in_the_browsers_language(tmp_path):
    """A Spanish student's shared address (``?tab=Deducción``) opened by a Polish browser: the Derive tab
    opens, under its Polish name, and the address then names it in Polish."""
    out = _out(tmp_path)
    polish = translations("pl").gettext("Derive")
    lab = Lab(port=0, symbolic=FakeSymbolicService())
    with app_page(lab, locale="pl-PL", path="?robot=trr&tab=Deducci%C3%B3n") as (page, session, errors):
        poll(lambda: session.language == "pl", what="the tab speaks Polish")
        selected = page.locator("[role=tab][aria-selected=true]")
        poll(lambda: selected.first.inner_text().strip() == polish, what=f"the {polish!r} tab is open")
        poll(lambda: "tab=Wyprowadzenie" in page.url, what="the address names the tab in Polish")
        page.screenshot(path=str(out / "i18n_pl_derive_from_a_spanish_link_1280x720.png"))
        assert not errors


_NOTICE = """() => [...document.querySelectorAll('.mantine-Notification-root, .mantine-Notifications-root [role=alert]')]
  .filter(e => e.offsetParent !== null || getComputedStyle(e).position === 'fixed')
  .map(e => { const r = e.getBoundingClientRect();
    const cut = [...e.querySelectorAll('*')].some(c => getComputedStyle(c).textOverflow === 'ellipsis' && c.scrollWidth > c.clientWidth + 1);
    return {text: e.innerText, cut, right: r.right, bottom: r.bottom}; })"""


@pytest.mark.parametrize(
    ("locale", "code", "title"),
    [
        ("pt-BR", "pt", "Nada foi gravado"),
        ("es-AR", "es", "No se grabó nada"),
        ("pl-PL", "pl", "Nic nie nagrano"),
    ],
)
def test_a_refusal_notice_is_in_the_browsers_language_and_whole(tmp_path, locale, code, title):
    """A recording stopped with nothing moved is refused in a notice: in Chromium its title and body are
    the browser's language (no English message of the catalogs), whole and inside the window."""
    from app.core.commands import ToggleRecording

    out = _out(tmp_path)
    with app_page(Lab(port=0, symbolic=FakeSymbolicService()), locale=locale) as (page, session, errors):
        poll(lambda: session.language == code, what=f"the tab speaks {code}")
        # The notices shown again (app_page hides the start-up toasts)
        page.add_style_tag(content=".mantine-Notifications-root { display: block !important; }")
        session.dispatch(ToggleRecording())
        session.settle()
        session.dispatch(ToggleRecording())  # nothing moved: nothing recorded, refused in words
        session.settle()
        notices = poll(lambda: [n for n in page.evaluate(_NOTICE) if title in n["text"]], what="the notice")
        page.screenshot(path=str(out / f"i18n_{code}_refusal_notice_1280x720.png"))
        notice = notices[0]
        english = _english_only(code)
        lines = {line.strip() for line in notice["text"].splitlines() if line.strip()}
        assert not lines & english, f"English in the {code} notice: {lines & english}"
        assert not notice["cut"] and notice["right"] <= 1280 and notice["bottom"] <= 720, notice
        assert not errors
