"""A robot file's texts in other languages: its ``translations`` tables, checked, read and written.

English is a robot file's own language: ``title``, ``description`` and each configuration's and
motion's ``description`` are English, and every file has them. A file may add the same texts in
the app's other languages (:data:`TEXT_LANGUAGES`)::

    [translations.pl]                 # top level: the title and the description
    title = "Unimation PUMA 560"
    description = "Klasyczny sześcioprzegubowy manipulator przemysłowy …"

    [[configurations]]
    name = "home"
    …
    translations.pl.description = "…"  # a configuration's (or a motion's) description

Either key may be left out, and any language: whoever shows the robot falls back to English
(a file a user uploads may have English only). Like the English texts, each is one paragraph.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .toml_values import check_table, key_text, one_of, string_text

__all__ = [
    "TEXT_LANGUAGES",
    "TOP_KEYS",
    "ENTRY_KEYS",
    "MOTION_KEYS",
    "check_translations",
    "read_translations",
    "translation_tables",
    "translation_lines",
]

TEXT_LANGUAGES = ("pt", "es", "pl")
"""The languages a robot file's ``translations`` may give (the app's, English aside: it is the file's own)."""
TOP_KEYS = ("title", "description")
"""The texts a top-level ``[translations.<language>]`` table may give."""
ENTRY_KEYS = ("description",)
"""The texts a configuration's ``translations.<language>`` may give (its name is an identifier)."""
MOTION_KEYS = ("name", "description")
"""The texts a motion's ``translations.<language>`` may give (its name is a phrase the menu shows)."""


def check_translations(table: dict[str, Any], keys: tuple[str, ...], where: str) -> None:
    """Nothing if ``table``'s optional ``translations`` maps languages of :data:`TEXT_LANGUAGES` to
    tables of strings under ``keys``, else RobotDefinitionError naming ``where`` and the language."""
    for code, texts in table.get("translations", {}).items():
        one_of(code, TEXT_LANGUAGES, f"{where}, key 'translations' (a language)")
        check_table(texts, {}, dict.fromkeys(keys, str), f"{where}, translations.{code}")


def read_translations(table: dict[str, Any]) -> dict[str, dict[str, str]]:
    """A checked table's ``translations``, each text one paragraph (its line breaks become spaces)."""
    return {
        code: {key: " ".join(text.split()) for key, text in texts.items()}
        for code, texts in table.get("translations", {}).items()
    }


def translation_tables(translations: Mapping[str, Mapping[str, str]]) -> list[str]:
    """The top level's translations as ``[translations.<language>]`` tables (each then a blank line)."""
    out: list[str] = []
    for code, texts in translations.items():
        out += [
            f"[translations.{key_text(code)}]",
            *(f"{k} = {string_text(v)}" for k, v in texts.items()),
            "",
        ]
    return out


def translation_lines(translations: Mapping[str, Mapping[str, str]]) -> list[str]:
    """An entry's translations as dotted keys (``translations.pl.description = "…"``)."""
    return [
        f"translations.{key_text(code)}.{key_text(k)} = {string_text(v)}"
        for code, texts in translations.items()
        for k, v in texts.items()
    ]
