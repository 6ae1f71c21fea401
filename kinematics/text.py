"""The library's words a user reads (a derivation's name in a menu, a step's caption): marked for the
app's catalogs.

The library speaks English and never imports the app; the app shows these words in a tab's
language. :func:`N_` marks a string for ``pybabel extract`` (``babel.cfg`` maps the library's
modules that hold such words) and returns it unchanged: the app translates it where it shows it
(``tr.gettext(method.label)``). :func:`words` makes a caption whose English is ``msgid`` filled with
its arguments and which keeps both, so the app can say the same sentence in another language:
:func:`translated` (the Derive tab and the handouts both use it).
"""

from __future__ import annotations

import re
from typing import Protocol

__all__ = ["N_", "Words", "words", "Translating", "fill", "translated"]


def N_(message: str) -> str:  # noqa: N802 - gettext's name for "mark for extraction, translate later"
    """``message`` itself, marked for the catalogs (the app translates it where it is shown)."""
    return message


class Words(str):
    """An English sentence (the ``str`` itself) that remembers its catalog id and named arguments.

    Attributes:
        msgid: The sentence with its ``{name}`` placeholders, as the catalogs hold it.
        args: The placeholders' values (names, symbols, numbers: never words to translate).
    """

    msgid: str
    args: tuple[tuple[str, str], ...]


def words(msgid: str, **args: object) -> Words:
    """The sentence ``msgid`` (marked with :func:`N_`) with ``args`` filled in, remembering both."""
    text = Words(msgid.format(**args))
    text.msgid = msgid
    text.args = tuple((k, str(v)) for k, v in args.items())
    return text


class Translating(Protocol):
    """A language (the app's ``Translator``, a handout's ``Words``): msgids in, its words out, and a plain
    number's text (``"0.5"``) as it writes it (``"0,5"``)."""

    def gettext(self, message: str) -> str: ...

    def decimal(self, text: str) -> str: ...


_PLACEHOLDER = re.compile(r"\{(\w+)\}")
_DECIMAL_POINT = re.compile(r"(?<=\d)\.(?=\d)")


def fill(template: str, **values: object) -> str:
    """``template`` (a translated msgid) with its named placeholders (``{robot}``) replaced by
    ``values``; any other brace is text (a catalog's words are data: never a format string that a
    stray ``{`` could break, and a value is never read as a template again)."""
    return _PLACEHOLDER.sub(lambda m: str(values[m[1]]) if m[1] in values else m[0], template)


def translated(text: str, tr: Translating) -> str:
    """``text`` in ``tr``'s language: a :func:`words` caption's msgid translated and filled with its
    arguments, their decimal points written as the language writes them (``0,432``); any other string
    translated whole (itself when the catalogs do not hold it). Plain text: escape it for the output."""
    msgid = getattr(text, "msgid", None)
    if not msgid:
        return tr.gettext(str(text))
    comma = tr.decimal("0.5")[1:-1]
    args = {k: _DECIMAL_POINT.sub(comma, v) for k, v in getattr(text, "args", ())}
    return fill(tr.gettext(msgid), **args)
