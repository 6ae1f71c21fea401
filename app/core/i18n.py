"""The app's languages: which one a tab speaks, its words (gettext catalogs) and how it writes numbers.

Every word a user sees goes through a :class:`Translator` (``tr.gettext``, ``tr.ngettext`` for a count
before a noun, ``tr.pgettext`` where one English word has two meanings). The words live in gettext
catalogs, one per language, in ``app/locale/<locale>/LC_MESSAGES/messages.po`` (compiled beside it
to ``messages.mo``, which is what is read here); English is the source language (the ``msgid``\\ s).
A string defined at import time (an option's label) is marked with :func:`N_` and translated where
it is shown. ``docs/architecture.md`` says how to add, extract, update, compile and check them.

The language is chosen by :func:`negotiate` from what a browser asks for (``Accept-Language``,
``navigator.language``, ``?lang=``): the language itself if the app has it, else the nearest one of
the same language (pt-PT → pt, es-MX → es), else English; never a mix.

Numbers: :meth:`Translator.decimal` writes a number already rounded by the caller (``"0.432"``) as the
language writes it (``"0,432"`` in pt, es and pl), from Babel's locale data.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

from babel import Locale, UnknownLocaleError
from babel.numbers import get_decimal_symbol
from babel.support import NullTranslations, Translations

__all__ = [
    "Language",
    "LANGUAGES",
    "CODES",
    "DEFAULT",
    "LOCALE_DIR",
    "DOMAIN",
    "Translator",
    "translations",
    "negotiate",
    "accepted",
    "is_language",
    "language_of",
    "N_",
]

LOCALE_DIR = Path(__file__).resolve().parents[1] / "locale"
"""``app/locale``: one folder per catalog locale, and the template ``messages.pot``."""
DOMAIN = "messages"
_SIGNS = ("-", "+", "\u2212")


@dataclass(frozen=True)
class Language:
    """One language of the app.

    Attributes:
        code: What the page address and the command line say (``?lang=pt``, ``serve --lang pt``).
        locale: The catalog's locale (its folder under ``app/locale``) and Babel's locale.
        name: The language's own name, as its Language menu shows it.
        course: The course document whose words the catalog uses ("" for none).
    """

    code: str
    locale: str
    name: str
    course: str


LANGUAGES: tuple[Language, ...] = (
    Language("en", "en", "English", "001"),
    Language("pt", "pt_BR", "Português (Brasil)", "000"),
    Language("es", "es_AR", "Español (Argentina)", "002"),
    Language("pl", "pl", "Polski", "004"),
)
CODES: tuple[str, ...] = tuple(lang.code for lang in LANGUAGES)
DEFAULT = "en"
_BY_CODE = {lang.code: lang for lang in LANGUAGES}


def N_(message: str) -> str:  # noqa: N802 - gettext's name for "mark for extraction, translate later"
    """``message`` itself: marks a string defined at import time for ``pybabel extract``; the view that
    shows it translates it (``tr.gettext(option.label)``)."""
    return message


def is_language(code: object) -> bool:
    """Whether ``code`` is one of :data:`CODES`."""
    return isinstance(code, str) and code in _BY_CODE


def _tag_language(tag: str) -> tuple[str, str]:
    """(language, territory) of a BCP 47 / POSIX tag ("pt-BR" → ("pt", "BR")), ("", "") if unreadable."""
    tag = tag.strip().replace("_", "-")
    if not tag or tag == "*" or len(tag) > 35:
        return "", ""
    try:
        loc = Locale.parse(tag, sep="-")
    except (ValueError, TypeError, UnknownLocaleError):
        parts = tag.split("-")
        return parts[0].lower(), (parts[1].upper() if len(parts) > 1 else "")
    return loc.language, loc.territory or ""


def accepted(header: str) -> list[str]:
    """The language tags of an ``Accept-Language`` header, most wanted first (``q=0`` left out).

    >>> accepted("pl;q=0.5, pt-PT, en;q=0.8, fr;q=0")
    ['pt-PT', 'en', 'pl']
    """
    weighted: list[tuple[float, int, str]] = []
    for index, part in enumerate(header[:1024].split(",")[:32]):
        tag, _, params = part.strip().partition(";")
        q = 1.0
        for param in params.split(";"):
            key, _, value = param.strip().partition("=")
            if key.strip() == "q":
                try:
                    q = float(value)
                except ValueError:
                    q = 0.0
        if tag.strip() and q > 0:
            weighted.append((-q, index, tag.strip()))
    return [tag for _, _, tag in sorted(weighted)]


def negotiate(wanted: str | list[str] | tuple[str, ...], default: str = DEFAULT) -> str:
    """The app's language code nearest to ``wanted`` (an Accept-Language header, or tags in order).

    The first wanted tag whose language the app has wins: its code ("pt-PT" and "pt-BR" → "pt",
    "es-MX" → "es", "pl-PL" → "pl", "en-GB" → "en"); ``default`` when none is ("fr", "", "*"):
    English unless given ("" says "none": the caller decides).

    >>> negotiate("fr-FR, es-MX;q=0.9"), negotiate(["pt-PT"]), negotiate("fr"), negotiate("de", "pl")
    ('es', 'pt', 'en', 'pl')
    """
    tags = accepted(wanted) if isinstance(wanted, str) else list(wanted)
    for tag in tags:
        language, _ = _tag_language(tag)
        if language in _BY_CODE:
            return language
    return default if default in _BY_CODE or default == "" else DEFAULT


class Translator:
    """One language's words and numbers. Build it with :func:`translations` (one per language, cached).

    Attributes:
        language: The :class:`Language` it speaks.
        decimal_symbol: What separates a number's decimals ("." or ",").
    """

    def __init__(self, language: Language, catalog: NullTranslations) -> None:
        self.language = language
        self.code = language.code
        self._catalog = catalog
        self._locale = Locale.parse(language.locale)
        self.decimal_symbol: str = get_decimal_symbol(self._locale)

    def gettext(self, message: str) -> str:
        """``message`` (English, the catalog's msgid) in this language."""
        return self._catalog.gettext(message)

    def ngettext(self, singular: str, plural: str, n: int) -> str:
        """The form of a phrase with a count ``n`` (Polish has three): format the result with ``n``."""
        return self._catalog.ngettext(singular, plural, n)

    def pgettext(self, context: str, message: str) -> str:
        """``message`` in ``context`` (one English word, two meanings: "joint" the noun in a label)."""
        return str(self._catalog.pgettext(context, message))

    def npgettext(self, context: str, singular: str, plural: str, n: int) -> str:
        """:meth:`ngettext` within a ``context``."""
        return str(self._catalog.npgettext(context, singular, plural, n))

    def decimal(self, text: str) -> str:
        """A plain number's text (``"-0.432"``, ``"12"``, ``"1.20"``: digits, at most one point), as
        this language writes it: "0,432" in pt, es and pl (the decimal symbol of Babel's locale data,
        read once). The digits are the caller's (rounded already); a sign is kept as the caller wrote
        it; text that is not a plain number is returned unchanged. No grouping: a lab's numbers are
        below 10⁵ and a matrix column stays aligned.

        One string replacement per number, not Babel's ``format_decimal`` (which parses a pattern and
        builds a Decimal each time: 4× the cost of a Polish J(q) tab's redraw, measured)."""
        if self.decimal_symbol == "." or "." not in text:
            return text
        digits = text[1:] if text[:1] in _SIGNS else text
        whole, _, fraction = digits.partition(".")
        if not (whole.isdigit() or not whole) or not fraction.isdigit():
            return text
        return text.replace(".", self.decimal_symbol, 1)

    def __repr__(self) -> str:
        return f"Translator({self.code!r})"


def translations(code: str = DEFAULT) -> Translator:
    """The :class:`Translator` of language ``code`` (English for an unknown code: never a mix), one
    per language.

    Reads the compiled catalog ``app/locale/<locale>/LC_MESSAGES/messages.mo``; English, the source
    language, speaks the msgids themselves.
    """
    return _translator(code if code in _BY_CODE else DEFAULT)


@functools.lru_cache(maxsize=len(LANGUAGES))
def _translator(code: str) -> Translator:
    language = _BY_CODE[code]
    catalog: NullTranslations
    if language.code == DEFAULT:
        catalog = NullTranslations()
    else:
        path = LOCALE_DIR / language.locale / "LC_MESSAGES" / f"{DOMAIN}.mo"
        with path.open("rb") as f:
            catalog = Translations(f, domain=DOMAIN)
    return Translator(language, catalog)


def language_of(code: str) -> Language:
    """The :class:`Language` of ``code`` (English for an unknown one)."""
    return _BY_CODE.get(code, _BY_CODE[DEFAULT])
