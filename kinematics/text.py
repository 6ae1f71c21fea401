"""The library's words a user reads (a derivation's name in a menu): marked for the app's catalogs.

The library speaks English and never imports the app; the app shows these words in a tab's
language. :func:`N_` marks a string for ``pybabel extract`` (``babel.cfg`` maps the library's
modules that hold such words) and returns it unchanged: the app translates it where it shows it
(``tr.gettext(method.label)``).
"""

from __future__ import annotations

__all__ = ["N_"]


def N_(message: str) -> str:  # noqa: N802 - gettext's name for "mark for extraction, translate later"
    """``message`` itself, marked for the catalogs (the app translates it where it is shown)."""
    return message
