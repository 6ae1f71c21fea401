"""A typed number read strictly: what the user typed is kept, and anything that is not a plain number
is refused in words (never silently mangled, as the browser's number boxes do: ``1e-3`` typed key by
key became −13, a pasted ``0,3`` became 3 and ``1e400`` became 1400).

Accepted: an optional sign (``-``, ``+`` or the real minus ``−``), digits with at most one decimal
mark, and an optional exponent (``1e-3``, ``2.5E4``), surrounded by spaces. The decimal mark is the
language's: a point in English, a comma in Portuguese, Spanish and Polish (``0,3`` there simply means
0.3; a point is taken there too, unless it could be a thousands separator: ``1.234``). Refused, each
with its reason in the tab's language: a decimal comma in English (``0,3``: "use a point"), thousands
separators, ``nan``/``inf`` words, digits with ``_``, an empty box, and values beyond the field's bound
(``1e400`` is not finite; ``1e6`` m is beyond a lab arm).
"""

from __future__ import annotations

import math
import re

from .i18n import Translator, translations

__all__ = ["NumberError", "parse_number"]

_PLAIN = re.compile(r"[+\-\u2212]?(?:\d+\.?\d*|\.\d+)(?:[eE][+\-\u2212]?\d+)?")
_DECIMAL_COMMA = re.compile(r"[+\-\u2212]?\d*,\d+(?:[eE][+\-\u2212]?\d+)?")
_THOUSANDS_POINT = re.compile(r"[+\-\u2212]?[1-9]\d{0,2}\.\d{3}")
"""``1.234``: in a language with a decimal comma, a point before three digits groups thousands."""


class NumberError(ValueError):
    """A typed value that is not a usable number; the message says why, in words."""


def parse_number(
    value: object, bound: float = math.inf, unit: str = "", tr: Translator | None = None
) -> float:
    """``value`` (text as typed, or a number) as a float, or :class:`NumberError` naming what is wrong.

    Args:
        value: What the input holds: text, an int or a float (a bool is refused).
        bound: Largest magnitude accepted (in the field's unit).
        unit: The field's unit, for the message ("m", "°").
        tr: The tab's language: its decimal mark is accepted and its words explain a refusal
            (English when ``None``).

    Raises:
        NumberError: empty, not a plain number, not finite, or beyond ``bound``.
    """
    tr = tr or translations()
    _ = tr.gettext
    comma = tr.decimal_symbol == ","
    if isinstance(value, bool):
        raise NumberError(_("expected a number, got {value}").format(value=repr(value)))
    if isinstance(value, (int, float)):
        x = float(value)
    elif isinstance(value, str):
        text = value.strip()
        shown = text[:30]
        if not text:
            raise NumberError(_("the box is empty: type a number"))
        if _DECIMAL_COMMA.fullmatch(text):
            if not comma:
                raise NumberError(
                    _("“{text}”: use a point for decimals ({fixed})").format(
                        text=shown, fixed=text.replace(",", ".")
                    )
                )
            text = text.replace(",", ".")
        elif comma and _THOUSANDS_POINT.fullmatch(text):
            raise NumberError(
                _("“{text}”: write the decimals after a comma ({fixed}); do not group thousands").format(
                    text=shown, fixed=text.replace(".", ",")
                )
            )
        if not _PLAIN.fullmatch(text):
            raise NumberError(
                _("“{text}” is not a number (write e.g. {a}, {b} or {c})").format(
                    text=shown, a=tr.decimal("0.25"), b=tr.decimal("\u22121.5"), c="1e-3"
                )
            )
        try:
            x = float(text.replace("\u2212", "-"))
        except OverflowError:  # pragma: no cover - float() of digits returns inf, never raises
            x = math.inf
    else:
        raise NumberError(_("expected a number, got a {kind}").format(kind=type(value).__name__))
    if math.isnan(x):
        raise NumberError(_("expected a number, got NaN"))
    if not math.isfinite(x):
        raise NumberError(_("“{text}” is too large to be a number here").format(text=str(value)[:30]))
    if abs(x) > bound:
        b = tr.decimal(f"{bound:g}")
        limit = f"{b} {unit}" if unit and not unit.startswith("°") else f"{b}{unit}"
        raise NumberError(_("{value} is beyond ±{limit}").format(value=tr.decimal(f"{x:g}"), limit=limit))
    return x
