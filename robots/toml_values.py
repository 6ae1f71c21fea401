"""TOML values of robot files: checking what was read, and writing strings, keys and numbers.

Reading: tables with required and optional keys of given types, finite numbers (not bools),
choices; each error names where it is.

Writing: a string is a TOML basic string: ``"`` and ``\\`` are escaped, and so is every control
character (U+0000–U+001F, U+007F), so no name can end the string, start a new line or table,
or inject a key. A lone surrogate cannot be written as UTF-8 and is refused.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence

from kinematics.errors import RobotDefinitionError

__all__ = [
    "check_table",
    "check_number",
    "check_numbers",
    "one_of",
    "short",
    "string_text",
    "key_text",
    "number_text",
]

_SHORT = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}
_ESCAPE = re.compile('["\\\\\x00-\x1f\x7f]')
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
_SURROGATE = re.compile("[\ud800-\udfff]")


def string_text(text: str) -> str:
    """``text`` as a TOML basic string (with its quotes)."""
    if not isinstance(text, str):
        raise RobotDefinitionError(f"expected a string to write, got {type(text).__name__}")
    if _SURROGATE.search(text):
        raise RobotDefinitionError(f"{text[:40]!r}: holds a lone surrogate, which UTF-8 cannot store")
    escaped = _ESCAPE.sub(lambda m: _SHORT.get(m.group(), f"\\u{ord(m.group()):04X}"), text)
    return f'"{escaped}"'


def key_text(key: str) -> str:
    """``key`` as a TOML key: bare when it is only letters, digits, ``_`` and ``-``, else quoted."""
    return key if _BARE_KEY.fullmatch(key) else string_text(key)


def number_text(x: float) -> str:
    """A finite float as TOML (the shortest text that reads back as the same float)."""
    x = float(x)
    if not math.isfinite(x):
        raise RobotDefinitionError(f"cannot write {x!r}: a robot file holds finite numbers only")
    return "0.0" if x == 0 else repr(x)


def check_table(
    table: object, required: Mapping[str, type], optional: Mapping[str, type], where: str
) -> None:
    """Nothing if ``table`` is a dict with every ``required`` key, no key outside ``required`` and
    ``optional``, and values of the type each names (``float``: a finite number), else
    RobotDefinitionError naming ``where`` and the key."""
    if not isinstance(table, dict):
        raise RobotDefinitionError(f"{where}: expected a table, got {short(table)}")
    missing = [k for k in required if k not in table]
    if missing:
        raise RobotDefinitionError(f"{where}: missing key(s) {', '.join(map(repr, missing))}")
    unknown = sorted(set(table) - set(required) - set(optional), key=repr)
    if unknown:
        bad, allowed = ", ".join(map(repr, unknown)), ", ".join([*required, *optional])
        raise RobotDefinitionError(f"{where}: unknown key(s) {bad}; allowed: {allowed}")
    for key, kind in {**required, **optional}.items():
        if key in table and kind is float:
            check_number(table[key], f"{where}, key {key!r}")
        elif key in table and not isinstance(table[key], kind):
            got = table[key]
            raise RobotDefinitionError(f"{where}, key {key!r}: expected a {kind.__name__}, got {short(got)}")


def check_number(x: object, where: str) -> None:
    """Nothing if ``x`` is a finite int or float (not a bool), else RobotDefinitionError naming ``where``."""
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise RobotDefinitionError(f"{where}: expected a number, got {short(x)}")
    try:
        finite = math.isfinite(float(x))
    except OverflowError:  # an integer beyond float range
        finite = False
    if not finite:
        raise RobotDefinitionError(f"{where}: expected a finite number within float range, got {short(x)}")


def short(x: object) -> str:
    """``repr(x)`` cut to 60 characters (a 400-digit integer is not a message)."""
    if isinstance(x, int) and x.bit_length() > 200:
        return f"an integer of about {int(x.bit_length() * 0.30103)} digits"
    text = repr(x)
    return text if len(text) <= 60 else text[:57] + "..."


def one_of(value: object, allowed: Sequence[str], where: str) -> None:
    """Nothing if ``value`` is one of ``allowed``, else RobotDefinitionError listing them."""
    if value not in allowed:
        raise RobotDefinitionError(f"{where}: expected one of {', '.join(allowed)}; got {short(value)}")


def check_numbers(x: list[object], length: int, where: str) -> None:
    """Nothing if ``x`` is ``length`` finite numbers, else RobotDefinitionError naming ``where``."""
    if len(x) != length:
        raise RobotDefinitionError(f"{where}: expected {length} numbers, got {len(x)}")
    for v in x:
        check_number(v, where)
