"""What the tests of a translated screen share: the words that only English uses (the catalog ids' words
that no translation of a language holds), to find English left on a screen in another language."""

from __future__ import annotations

import functools
import re

from babel.messages.pofile import read_po

from app.core.i18n import LOCALE_DIR, language_of

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

__all__ = ["words", "plain", "english_only", "GLOSSARY", "glossary_problems"]

_WORD = re.compile(r"[^\W\d_]{3,}")


def words(text: str) -> set[str]:
    """The words of ``text`` of three letters or more, lower-cased (symbols and numbers aside)."""
    return {w.lower() for w in _WORD.findall(text)}


def plain(html: str) -> str:
    """An HTML fragment's text, its entities read (&lt;origin&gt; → <origin>)."""
    text = re.sub(r"<[^>]*>", " ", html)
    return text.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&").replace("&quot;", '"')


@functools.cache
def english_only(code: str) -> frozenset[str]:
    """Words of the English catalog ids that no translation of ``code`` uses: any of them on a ``code``
    screen is English left over ("column", "joint", "equals", "step")."""
    locale = language_of(code).locale
    with (LOCALE_DIR / "messages.pot").open("rb") as f:
        ids = [m.id for m in read_po(f) if m.id]
    with (LOCALE_DIR / locale / "LC_MESSAGES" / "messages.po").open("rb") as f:
        strings = [m.string for m in read_po(f, locale=locale) if m.id]
    english = set().union(*(words(" ".join(i) if isinstance(i, tuple) else i) for i in ids))
    own = set().union(*(words(" ".join(s) if isinstance(s, tuple) else s) for s in strings))
    return frozenset(english - own)


GLOSSARY = tomllib.loads((LOCALE_DIR / "glossary.toml").read_text(encoding="utf-8"))
"""app/locale/glossary.toml: each term in the words of each course."""


def glossary_problems(code: str, english: str, text: str, context: str | None = None) -> list[str]:
    """Where ``text`` (language ``code``'s translation of ``english``) breaks the glossary: a term the
    English names without the course's word, or a word the course does not use (``context``: the
    message's, for terms that mean something else there)."""
    out = []
    for name, term in GLOSSARY.items():
        entry = term[code]
        if context in term.get("other_contexts", ()):
            continue
        if re.search(term["match"], english, re.IGNORECASE) and not re.search(
            entry["use"], text, re.IGNORECASE
        ):
            out.append(f"{name}: {english!r} → {text!r} lacks «{entry['word']}»")
        for avoided in entry["avoid"]:
            if re.search(avoided, text, re.IGNORECASE):
                out.append(f"{name}: {text!r} says {avoided!r}, not «{entry['word']}»")
    return out
