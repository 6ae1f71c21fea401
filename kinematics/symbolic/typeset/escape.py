"""Escaping of user-given text (robot, joint and link names, titles, sources, notes) for every output.

A robot file is user input: its names must come out of an export as text, never as
code or markup. One function per destination:

* :func:`plain`: printable text on one line (control characters, NUL, lone surrogates
  and line breaks removed), at most :data:`MAX_CHARS` long; every other function starts here;
* :func:`latex_text`: for ``\\text{...}`` and comments (``\\ { } $ % # & _ ^ ~`` escaped);
* :func:`xml_text`: for HTML and MathML element contents and attributes;
* :func:`py_literal`: a Python string literal (``ascii()``: quotes and backslashes escaped);
* :func:`py_docstring`: words safe inside a docstring or a C or MATLAB comment (letters, digits and
  punctuation but ``" \\ * <`` and a backtick; anything else becomes ``?``);
* :func:`py_identifier`: a valid Python identifier that is not a keyword.

JSON needs nothing more than ``json.dumps``.
"""

from __future__ import annotations

import html
import keyword
import re
import unicodedata

__all__ = [
    "MAX_CHARS",
    "NOTE_CHARS",
    "plain",
    "latex_text",
    "xml_text",
    "py_literal",
    "py_docstring",
    "py_identifier",
]

MAX_CHARS = 300
"""Longer names are cut (with "…") in the outputs."""

NOTE_CHARS = 20_000
"""Longer notes are cut."""

_LATEX = {
    "\\": "\\textbackslash{}",
    "{": "\\{",
    "}": "\\}",
    "$": "\\$",
    "%": "\\%",
    "#": "\\#",
    "&": "\\&",
    "_": "\\_",
    "^": "\\textasciicircum{}",
    "~": "\\textasciitilde{}",
}
_LATEX_RE = re.compile("|".join(re.escape(c) for c in _LATEX))


def plain(text: object, max_chars: int = MAX_CHARS) -> str:
    """``text`` as one printable line: controls, separators and surrogates become spaces, runs of
    spaces one space, and more than ``max_chars`` characters are cut with "…"."""
    chars = []
    for c in str(text):
        cat = unicodedata.category(c)
        chars.append(" " if cat in ("Cc", "Cs", "Co", "Cn", "Zl", "Zp") or c in "\ufeff\ufffe\uffff" else c)
    out = " ".join("".join(chars).split())
    return out if len(out) <= max_chars else out[: max_chars - 1] + "…"


def latex_text(text: object, max_chars: int = MAX_CHARS) -> str:
    """``text`` for LaTeX text mode (``\\text{}``) or a comment: TeX's special characters escaped."""
    return _LATEX_RE.sub(lambda m: _LATEX[m.group(0)], plain(text, max_chars))


def xml_text(text: object, max_chars: int = MAX_CHARS) -> str:
    """``text`` for HTML / MathML contents or a quoted attribute (``& < > " '`` escaped)."""
    return html.escape(plain(text, max_chars), quote=True)


def py_literal(text: object) -> str:
    """A Python string literal of ``text`` (all of it, escaped by ``ascii()``), safe anywhere in code."""
    return ascii(str(text))


def py_docstring(text: object, max_chars: int = MAX_CHARS) -> str:
    """``text`` reduced to characters harmless in a Python docstring, a C or a MATLAB comment: letters,
    digits, space and ``_.,:;()+-/=>[]{}'#&@$%^~!|`` stay (a joint's name, ``rpy (...) -> rpy (...)``
    in a note); anything else (a double quote, a backslash, ``*``, ``<`` (no tag ever), a backtick,
    non-ASCII) becomes ``?``."""
    return re.sub(r"[^A-Za-z0-9 _.,:;()+\-/=>\[\]{}'#&@$%^~!|]", "?", plain(text, max_chars))


def py_identifier(text: object, fallback: str = "name") -> str:
    """A valid, non-keyword Python identifier made from ``text`` (non-word characters become ``_``)."""
    out = re.sub(r"\W", "_", plain(text), flags=re.ASCII) or fallback
    if out[0].isdigit():
        out = "_" + out
    return out + "_" if keyword.iskeyword(out) or keyword.issoftkeyword(out) else out
