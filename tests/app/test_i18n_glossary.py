"""The glossary (app/locale/glossary.toml) held: every translation uses the course's word for a term the
English message names, and no translation uses a word the course does not (issue 27)."""

from __future__ import annotations

import re

import pytest
from babel.messages.pofile import read_po
from i18n_words import GLOSSARY, glossary_problems

from app.core.i18n import LANGUAGES, LOCALE_DIR

TRANSLATED = [lang for lang in LANGUAGES if lang.code != "en"]


_PLACEHOLDER = re.compile(r"\{\w*\}|%\(\w+\)[sd]")


def _words(text: str) -> str:
    """A message without its placeholders (``{joints}`` is a value, not the word "joints")."""
    return _PLACEHOLDER.sub(" ", text)


def _pairs(locale: str) -> list[tuple[str, str, str]]:
    """(context, English, translation) of every entry of a catalog, each plural form with its English
    plural."""
    with (LOCALE_DIR / locale / "LC_MESSAGES" / "messages.po").open("rb") as f:
        catalog = read_po(f, locale=locale)
    out = []
    for m in catalog:
        if not m.id:
            continue
        if m.pluralizable:
            out += [(m.context or "", _words(m.id[min(i, 1)]), _words(s)) for i, s in enumerate(m.string)]
        else:
            out.append((m.context or "", _words(m.id), _words(m.string)))
    return out


def test_the_glossary_names_every_language_and_its_source():
    assert len(GLOSSARY) >= 12
    for name, term in GLOSSARY.items():
        re.compile(term["match"])
        for lang in TRANSLATED:
            entry = term[lang.code]
            assert entry["word"] and entry["source"], f"{name}/{lang.code}"
            assert entry["source"].startswith((lang.course + ":", "(not in the course)")), (
                f"{name}/{lang.code}"
            )
            assert re.search(entry["use"], entry["word"], re.IGNORECASE), f"{name}/{lang.code}: word ≠ use"


@pytest.mark.parametrize("lang", TRANSLATED, ids=lambda lang: lang.locale)
def test_every_translation_says_the_courses_word(lang):
    problems = []
    for context, english, text in _pairs(lang.locale):
        problems += glossary_problems(lang.code, english, text, context)
    assert not problems, "\n".join(problems)


def test_the_glossary_test_finds_a_word_the_course_would_not_use():
    """The check can fail: a Portuguese "articulação" for the course's "junta" is caught."""
    term = GLOSSARY["joint"]
    assert any(re.search(a, "velocidade da articulação 2", re.IGNORECASE) for a in term["pt"]["avoid"])
    assert not re.search(term["pl"]["use"], "prędkość stawu 2", re.IGNORECASE)
