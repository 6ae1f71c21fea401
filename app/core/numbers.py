"""A typed number read strictly: what the user typed is kept, and anything that is not a plain number
is refused in words (never silently mangled, as the browser's number boxes do: ``1e-3`` typed key by
key became −13, a pasted ``0,3`` became 3 and ``1e400`` became 1400).

Accepted: an optional sign (``-``, ``+`` or the real minus ``−``), digits with at most one decimal
point, and an optional exponent (``1e-3``, ``2.5E4``), surrounded by spaces. Refused, each with its
reason: a decimal comma (``0,3``: "use a point"), thousands separators, ``nan``/``inf`` words, digits
with ``_``, an empty box, and values beyond the field's bound (``1e400`` is not finite; ``1e6`` m is
beyond a lab arm).
"""

from __future__ import annotations

import math
import re

__all__ = ["NumberError", "parse_number"]

_PLAIN = re.compile(r"[+\-\u2212]?(?:\d+\.?\d*|\.\d+)(?:[eE][+\-\u2212]?\d+)?")
_DECIMAL_COMMA = re.compile(r"[+\-\u2212]?\d*,\d+")


class NumberError(ValueError):
    """A typed value that is not a usable number; the message says why, in words."""


def parse_number(value: object, bound: float = math.inf, unit: str = "") -> float:
    """``value`` (text as typed, or a number) as a float, or :class:`NumberError` naming what is wrong.

    Args:
        value: What the input holds: text, an int or a float (a bool is refused).
        bound: Largest magnitude accepted (in the field's unit).
        unit: The field's unit, for the message ("m", "°").

    Raises:
        NumberError: empty, not a plain number, not finite, or beyond ``bound``.
    """
    if isinstance(value, bool):
        raise NumberError(f"expected a number, got {value!r}")
    if isinstance(value, (int, float)):
        x = float(value)
    elif isinstance(value, str):
        text = value.strip()
        shown = text[:30]
        if not text:
            raise NumberError("the box is empty: type a number")
        if _DECIMAL_COMMA.fullmatch(text):
            raise NumberError(f"“{shown}”: use a point for decimals ({text.replace(',', '.')})")
        if not _PLAIN.fullmatch(text):
            raise NumberError(f"“{shown}” is not a number (write e.g. 0.25, −1.5 or 1e-3)")
        try:
            x = float(text.replace("\u2212", "-"))
        except OverflowError:  # pragma: no cover - float() of digits returns inf, never raises
            x = math.inf
    else:
        raise NumberError(f"expected a number, got a {type(value).__name__}")
    if math.isnan(x):
        raise NumberError("expected a number, got NaN")
    if not math.isfinite(x):
        raise NumberError(f"“{str(value)[:30]}” is too large to be a number here")
    if abs(x) > bound:
        limit = f"{bound:g} {unit}" if unit and not unit.startswith("°") else f"{bound:g}{unit}"
        raise NumberError(f"{x:g} is beyond ±{limit}")
    return x
