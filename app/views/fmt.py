"""Numbers for humans: significant digits, real minus signs, units, ∞ and no NaN.

Everything the panel shows goes through these functions, so no ``nan`` or
``inf`` text can reach the page: an infinite value reads ``∞`` and a NaN
(which should never happen) reads ``—``. Given the tab's translator (``tr``), a number is written as
its language writes it (``0,432`` in Portuguese, Spanish and Polish); the digits, the real minus sign,
``×10ⁿ`` and the units stay.
"""

from __future__ import annotations

import html
import math
import re

from ..core.i18n import Translator

__all__ = ["number", "quantity", "fixed", "escape", "cleaned", "MINUS", "joint_label", "joint_words"]

MINUS = "\u2212"
_SUPERSCRIPT = str.maketrans(
    "-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079"
)


def number(x: float, digits: int = 3, tr: Translator | None = None) -> str:
    """``x`` with ``digits`` significant digits: ``0.432``, ``12.3``, ``1.23×10⁴``, ``∞``.

    Magnitudes in [1e-3, 1e5) are written plainly; others in scientific form.
    A value that rounds to zero is written ``0``. ``tr``: the language's decimal mark (a point when None).
    """
    try:
        x = float(x)
    except (TypeError, ValueError):
        return "—"
    if math.isnan(x):
        return "—"
    if math.isinf(x):
        return "∞" if x > 0 else f"{MINUS}∞"
    if x == 0.0 or abs(x) < 1e-12:
        return "0"
    mag = abs(x)
    if 1e-3 <= mag < 1e5:
        decimals = max(0, digits - 1 - int(math.floor(math.log10(mag))))
        text = f"{mag:.{decimals}f}"
        if "." in text:
            text = text.rstrip("0").rstrip(".")
        text = tr.decimal(text) if tr else text
    else:
        mantissa, exponent = f"{mag:.{digits - 1}e}".split("e")
        if "." in mantissa:
            mantissa = mantissa.rstrip("0").rstrip(".")
        mantissa = tr.decimal(mantissa) if tr else mantissa
        text = f"{mantissa}×10{str(int(exponent)).translate(_SUPERSCRIPT)}"
    return (MINUS if x < 0 else "") + text


def quantity(x: float, unit: str = "", digits: int = 3, tr: Translator | None = None) -> str:
    """``number(x)`` followed by a thin space and ``unit`` (no space before ``°``)."""
    text = number(x, digits, tr)
    if not unit or text == "—":
        return text
    return f"{text}{unit}" if unit.startswith("°") else f"{text}\u2009{unit}"


def fixed(x: float, decimals: int = 3, tr: Translator | None = None) -> str:
    """``x`` with a fixed number of decimals, for aligned matrix entries (``−0.432``, ``0``).

    Values that round to zero are written ``0`` (no ``−0.000``); non-finite values as in :func:`number`.
    """
    try:
        x = float(x)
    except (TypeError, ValueError):
        return "—"
    if not math.isfinite(x):
        return number(x)
    if abs(x) < 0.5 * 10.0**-decimals:
        return "0"
    if abs(x) >= 1e5:
        return number(x, tr=tr)
    text = f"{abs(x):.{decimals}f}"
    text = tr.decimal(text) if tr else text
    return (MINUS if x < 0 else "") + text


def escape(text: str) -> str:
    """HTML-escape ``text`` for the panel."""
    return html.escape(text, quote=True)


def cleaned(values: object, rel: float = 1e-9) -> list[float]:
    """``values`` with float noise set to 0: entries below ``rel`` × the largest magnitude.

    A joint rate of −5.4×10⁻¹² °/s next to 200 °/s is round-off, not a rate: it reads ``0``.
    """
    xs = [float(x) for x in values]  # type: ignore[attr-defined]
    finite = [abs(x) for x in xs if math.isfinite(x)]
    big = max(finite, default=0.0)
    return [0.0 if math.isfinite(x) and abs(x) <= rel * big else x for x in xs]


_SYMBOL = re.compile(r"(?:[A-Za-zθ]{1,6}_?\d+|joint|link)", re.IGNORECASE)


def joint_words(name: str, robot_name: str = "") -> str:
    """The describing words of a joint's name, without the symbol it carries: "d3 boom" → "boom",
    "A1" → "", "elbow_joint" → "elbow", "panda_joint4" (robot "panda") → "", "q4 wrist 1" → "wrist 1".

    The app calls every joint qᵢ (the columns of J, the bars, the charts); a name's own symbol
    (d3, A1, joint4) would be a second name for the same joint on the same screen.
    """
    words = [w for w in re.split(r"[\s_]+", name) if w]
    drop = {robot_name.lower()} if robot_name else set()
    kept = [w for w in words if not _SYMBOL.fullmatch(w) and w.lower() not in drop]
    return " ".join(kept)


def joint_label(i: int, name: str, robot_name: str = "", width: int = 13) -> str:
    """Joint ``i``'s one name on screen: "q3" and the describing words of its own name, cut at a word
    to at most ``width`` characters ("q1 shoulder pan", "q3 boom", "q1")."""
    label = f"q{i + 1}"
    words = joint_words(name, robot_name).split()
    shown: list[str] = []
    for w in words:
        if len(" ".join([*shown, w])) > width:
            break
        shown.append(w)
    return f"{label} {' '.join(shown)}" if shown else label
