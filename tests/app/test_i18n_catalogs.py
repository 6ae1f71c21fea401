"""The gettext catalogs (issue 27): complete and valid for every language, compiled as they are written,
holding every string of the code; the language a browser asks for, and numbers written and read as
each language does."""

from __future__ import annotations

import gettext
import math
import re
import string
from pathlib import Path

import pytest
from babel.messages.checkers import num_plurals
from babel.messages.extract import DEFAULT_KEYWORDS, extract_from_dir
from babel.messages.frontend import parse_mapping_cfg
from babel.messages.pofile import read_po

from app.core.i18n import CODES, LANGUAGES, LOCALE_DIR, accepted, negotiate, translations
from app.core.numbers import NumberError, parse_number
from app.views import fmt

ROOT = Path(__file__).resolve().parents[2]
TRANSLATED = [lang for lang in LANGUAGES if lang.code != "en"]


def _catalog(locale: str):
    with (LOCALE_DIR / locale / "LC_MESSAGES" / "messages.po").open("rb") as f:
        return read_po(f, locale=locale)


def _fields(text: str) -> set[str]:
    """The placeholders of a message: ``{name}`` fields and ``%(name)s`` / ``%d`` conversions."""
    brace = {f[1] for f in string.Formatter().parse(text) if f[1] is not None}
    percent = set(re.findall(r"%(?:\((\w+)\))?[#0 +-]?\d*(?:\.\d+)?[sdifgxr]", text))
    return brace | {f"%{p}" for p in percent}


def _code_messages() -> set[tuple[str | None, str]]:
    """(context, msgid) of every string the app's code marks, extracted as ``pybabel extract`` does."""
    keywords = dict(DEFAULT_KEYWORDS)
    keywords["N_"] = None
    found = set()
    with (ROOT / "babel.cfg").open(
        encoding="utf-8"
    ) as f:  # the sources pybabel extract reads (app/, kinematics' words)
        method_map, _options = parse_mapping_cfg(f)
    for _file, _line, message, _comments, context in extract_from_dir(
        str(ROOT), method_map, keywords=keywords
    ):
        msgid = message[0] if isinstance(message, (tuple, list)) else message
        found.add((context, msgid))
    return found


@pytest.mark.parametrize("lang", TRANSLATED, ids=lambda lang: lang.locale)
def test_every_entry_is_translated_not_fuzzy_with_its_placeholders_and_plural_forms(lang):
    catalog = _catalog(lang.locale)
    assert len(catalog) > 0
    plurals = {"pt_BR": 2, "es_AR": 2, "pl": 3}[lang.locale]
    assert catalog.num_plurals == plurals
    problems = []
    for message in catalog:
        if not message.id:
            continue
        ids = message.id if isinstance(message.id, tuple) else (message.id,)
        strings = message.string if isinstance(message.string, tuple) else (message.string,)
        if message.fuzzy:
            problems.append(f"fuzzy: {ids[0]!r}")
        if not all(strings) or (message.pluralizable and len(strings) != plurals):
            problems.append(f"empty or missing a plural form: {ids[0]!r}")
            continue
        wanted = _fields(ids[-1])
        for s in strings:
            if _fields(s) - wanted or (_fields(s) != wanted and not message.pluralizable):
                problems.append(f"placeholders {sorted(_fields(s))} ≠ {sorted(wanted)}: {ids[0]!r}")
        try:
            num_plurals(catalog, message)
        except Exception as exc:
            problems.append(f"{exc}: {ids[0]!r}")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("lang", TRANSLATED, ids=lambda lang: lang.locale)
def test_babels_own_checkers_find_nothing(lang):
    """What `pybabel compile` checks (Babel's checkers: python-format placeholders, plural forms) finds
    no error: a message with "% o" in it reads as a %-format and compiles with an error."""
    errors = [(m.id, [str(e) for e in errs]) for m, errs in _catalog(lang.locale).check()]
    assert not errors, errors


@pytest.mark.parametrize("lang", TRANSLATED, ids=lambda lang: lang.locale)
def test_the_compiled_catalog_is_the_written_one(lang):
    """The .mo files are committed (so `pip install -e .` and the wheel carry them): each must say what
    its .po says (`pybabel compile -d app/locale -D messages` after every edit)."""
    catalog = _catalog(lang.locale)
    with (LOCALE_DIR / lang.locale / "LC_MESSAGES" / "messages.mo").open("rb") as f:
        compiled = gettext.GNUTranslations(f)
    for message in catalog:
        if not message.id:
            continue
        if message.pluralizable:
            for n, form in zip((1, 2, 5), message.string, strict=False):
                got = (
                    compiled.npgettext(message.context, message.id[0], message.id[1], n)
                    if message.context
                    else compiled.ngettext(message.id[0], message.id[1], n)
                )
                assert got in message.string, (message.id, n, got, form)
        else:
            got = (
                compiled.pgettext(message.context, message.id)
                if message.context
                else compiled.gettext(message.id)
            )
            assert got == message.string, f"{lang.locale}: {message.id!r} compiled as {got!r}"


def test_every_string_of_the_code_is_in_every_catalog():
    """A new string goes through the catalogs: extract, update, translate, compile (docs/architecture.md)."""
    code = _code_messages()
    assert code, "no marked string found: the extraction is broken"
    with (LOCALE_DIR / "messages.pot").open("rb") as f:
        template = {(m.context, m.id[0] if isinstance(m.id, tuple) else m.id) for m in read_po(f) if m.id}
    assert code == template, (
        f"pybabel extract is due: new {sorted(code - template)[:5]}, gone {sorted(template - code)[:5]}"
    )
    for lang in TRANSLATED:
        have = {
            (m.context, m.id[0] if isinstance(m.id, tuple) else m.id) for m in _catalog(lang.locale) if m.id
        }
        assert code <= have, f"{lang.locale}: pybabel update is due for {sorted(code - have)[:5]}"


# ---------------------------------------------------------------------- choosing the language
@pytest.mark.parametrize(
    ("wanted", "code"),
    [
        ("pt-BR,pt;q=0.9,en;q=0.8", "pt"),
        ("pt-PT", "pt"),  # the nearest the app has: Brazilian Portuguese
        ("es-MX,es;q=0.9", "es"),  # Argentinian Spanish
        ("pl-PL", "pl"),
        ("pl", "pl"),
        ("en-GB", "en"),
        ("fr-FR,fr;q=0.9", "en"),  # none it has: English
        ("fr-FR, de;q=0.9, es;q=0.5", "es"),  # the first it has, in the browser's order
        ("pl;q=0.2, pt;q=0.8", "pt"),  # by weight, not by position
        ("pt;q=0, es", "es"),  # q=0: not wanted
        ("*", "en"),
        ("", "en"),
        ("x" * 5000, "en"),
        (";;;,,,q=", "en"),
    ],
)
def test_a_browser_gets_its_language_or_the_nearest_one_or_english(wanted, code):
    assert negotiate(wanted) == code


def test_navigator_languages_and_a_room_default():
    assert negotiate(["fr-CA", "es-419"]) == "es"
    assert negotiate(["fr"], default="pl") == "pl"
    assert negotiate(["fr"], default="xx") == "en"
    assert accepted("es;q=0.3, pl, pt;q=0.7") == ["pl", "pt", "es"]


def test_an_unknown_code_speaks_english_never_a_mix():
    assert translations("xx") is translations("en")
    assert translations("en").gettext("the box is empty: type a number") == "the box is empty: type a number"
    assert set(CODES) == {"en", "pt", "es", "pl"}


@pytest.mark.parametrize(("code", "words"), [("pt", "digite"), ("es", "escribí"), ("pl", "wpisz")])
def test_a_language_speaks_its_catalog(code, words):
    assert words in translations(code).gettext("the box is empty: type a number")


# ---------------------------------------------------------------------- numbers
@pytest.mark.parametrize(
    ("code", "shown"),
    [
        ("en", ["−0.432", "1.500", "0.25\u2009m", "1.23×10⁻⁷", "12346", "0", "∞"]),
        ("pt", ["−0,432", "1,500", "0,25\u2009m", "1,23×10⁻⁷", "12346", "0", "∞"]),
        ("es", ["−0,432", "1,500", "0,25\u2009m", "1,23×10⁻⁷", "12346", "0", "∞"]),
        ("pl", ["−0,432", "1,500", "0,25\u2009m", "1,23×10⁻⁷", "12346", "0", "∞"]),
    ],
)
def test_numbers_are_written_as_the_language_writes_them(code, shown):
    tr = translations(code)
    got = [
        fmt.number(-0.43219, tr=tr),
        fmt.fixed(1.5, 3, tr),
        fmt.quantity(0.25, "m", tr=tr),
        fmt.number(1.234e-7, tr=tr),
        fmt.number(12345.6, tr=tr),
        fmt.fixed(1e-9, 3, tr),
        fmt.number(math.inf, tr=tr),
    ]
    assert got == shown
    assert fmt.quantity(12.5, "°", tr=tr) == ("12.5°" if code == "en" else "12,5°")


@pytest.mark.parametrize("code", ["pt", "es", "pl"])
@pytest.mark.parametrize(
    ("typed", "value"), [("0,3", 0.3), ("−1,25", -1.25), ("2,5e-3", 2.5e-3), ("0.3", 0.3), ("12", 12.0)]
)
def test_a_decimal_comma_is_a_number_where_the_language_writes_one(code, typed, value):
    assert parse_number(typed, tr=translations(code)) == value


@pytest.mark.parametrize(
    ("code", "words"), [("pt", "vírgula (1,234)"), ("es", "coma (1,234)"), ("pl", "przecinkiem (1,234)")]
)
def test_a_point_that_may_group_thousands_is_refused_in_the_language(code, words):
    tr = translations(code)
    for typed in ("1.234", "1.234,5", "1,234.5"):
        with pytest.raises(NumberError):
            parse_number(typed, tr=tr)
    with pytest.raises(NumberError, match=re.escape(words)):
        parse_number("1.234", tr=tr)
    with pytest.raises(NumberError, match=re.escape("±0,5 m")):
        parse_number("0,75", 0.5, "m", tr)


def test_english_still_asks_for_a_point():
    with pytest.raises(NumberError, match=re.escape("use a point for decimals (0.3)")):
        parse_number("0,3")
    assert parse_number("1.234") == 1.234
