"""The library's words a user reads (a derivation's name in a menu, a step's caption): marked for the
app's catalogs.

The library speaks English and never imports the app; the app shows these words in a tab's
language. :func:`N_` marks a string for ``pybabel extract`` (``babel.cfg`` maps the library's
modules that hold such words) and returns it unchanged: the app translates it where it shows it
(``tr.gettext(method.label)``). :func:`words` makes a caption whose English is ``msgid`` filled with
its arguments and which keeps both, so the app can say the same sentence in another language
(``tr.gettext(caption.msgid).format(**dict(caption.args))``).
"""

from __future__ import annotations

__all__ = ["N_", "Words", "words"]


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
