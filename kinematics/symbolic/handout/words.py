"""The words and numbers of a handout in a language: what the handout asks of a translator.

The kinematics never import the app, so a handout takes its language as a :class:`Words`: anything
with the language's ``code``, ``gettext`` / ``ngettext`` (English msgids in, the language out) and
``decimal`` (a plain number's text, ``"0.432"``, as the language writes it: ``"0,432"`` in pt, es and
pl). The app's :class:`app.core.i18n.Translator` is one; :data:`ENGLISH` speaks the msgids
themselves. Every English string the handout shows is a msgid in a :func:`say` / :func:`say_n` call
(context ``"handout"``) with named placeholders; ``app/core/handout_words.py`` lists them for the
catalogs (tests/kinematics/test_handout_languages.py holds the two lists equal). The methods' titles and
introductions come from :mod:`kinematics.steps` and are asked for with ``gettext`` (their catalog
entries are the Derive tab's).
"""

from __future__ import annotations

import re
from typing import Protocol

from ...text import fill

__all__ = [
    "Words",
    "ENGLISH",
    "CONTEXT",
    "say",
    "say_n",
    "fill",
    "mathml_decimals",
    "latex_decimals",
    "number",
    "latex_number",
    "list_separator",
]

CONTEXT = "handout"
"""The catalogs' context (msgctxt) of every handout word: its own entries, never another view's."""


class Words(Protocol):
    """A language for a handout (see the module's docstring)."""

    code: str

    def gettext(self, message: str) -> str: ...

    def pgettext(self, context: str, message: str) -> str: ...

    def npgettext(self, context: str, singular: str, plural: str, n: int) -> str: ...

    def decimal(self, text: str) -> str: ...


class _English:
    code = "en"

    def gettext(self, message: str) -> str:
        return message

    def pgettext(self, context: str, message: str) -> str:
        return message

    def npgettext(self, context: str, singular: str, plural: str, n: int) -> str:
        return singular if n == 1 else plural

    def decimal(self, text: str) -> str:
        return text


ENGLISH: Words = _English()
"""English, the handout's source language."""


def say(words: Words, message: str, **values: object) -> str:
    """``message`` (a handout msgid) in ``words``' language, its placeholders filled (:func:`fill`)."""
    return fill(words.pgettext(CONTEXT, message), **values)


def say_n(words: Words, singular: str, plural: str, n: int, **values: object) -> str:
    """The form of a handout phrase with a count ``n`` (Polish has three), ``{n}`` and the other
    placeholders filled (:func:`fill`)."""
    return fill(words.npgettext(CONTEXT, singular, plural, n), n=n, **values)


_E_NOTATION = re.compile(r"([-+]?[0-9.]+)e([-+]?[0-9]+)")


def number(words: Words, text: str) -> str:
    """A number's text (``"-0.432"``, ``"1.5e-05"``) as the language writes it (``"-0,432"``)."""
    m = _E_NOTATION.fullmatch(text)
    if m:
        return f"{words.decimal(m.group(1))}e{m.group(2)}"
    return words.decimal(text)


def latex_number(words: Words, text: str) -> str:
    """:func:`number` for LaTeX maths: a decimal comma braced (``0{,}432``) so it is not spaced as
    punctuation."""
    return number(words, text).replace(",", "{,}")


_MN = re.compile(r"<mn>([^<]*)</mn>")
_DECIMAL_POINT = re.compile(r"(?<=\d)\.(?=\d)")


def mathml_decimals(words: Words, mathml: str) -> str:
    """A formula's MathML with every number (``<mn>0.4318</mn>``) written as the language writes it."""
    if words.decimal("0.5") == "0.5":
        return mathml
    comma = words.decimal("0.5")[1:-1]
    return _MN.sub(lambda m: f"<mn>{_DECIMAL_POINT.sub(comma, m[1])}</mn>", mathml)


def latex_decimals(words: Words, latex: str) -> str:
    """A LaTeX formula with every decimal point between digits (``0.4318``) written as the language
    writes it, a comma braced (``0{,}4318``: not spaced as punctuation in maths mode)."""
    if words.decimal("0.5") == "0.5":
        return latex
    return _DECIMAL_POINT.sub(words.decimal("0.5")[1:-1].replace(",", "{,}"), latex)


def list_separator(words: Words) -> str:
    """What separates the numbers of a list in text: ``", "``, or ``"; "`` where a comma is decimal."""
    return "; " if words.decimal("0.5") != "0.5" else ", "
