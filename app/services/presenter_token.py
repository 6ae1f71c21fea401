"""The presenter token: a random one, a weak one named, the presenter link, and the limits on tries
(kept out of :mod:`app.services.classroom`, which re-exports them)."""

from __future__ import annotations

import math
import secrets
import urllib.parse

__all__ = [
    "presenter_link",
    "random_token",
    "token_weakness",
    "TOKEN_TRIES",
    "RANDOM_TOKEN_BYTES",
    "STRONG_BITS",
    "MAX_TOKEN_LENGTH",
]

TOKEN_TRIES = 5
"""Wrong tokens one connection (a tab, until it reloads) may type; its later tries are refused unread.
Counted per connection only: no address, and no room-wide count, so no tab can lock another out."""
RANDOM_TOKEN_BYTES = 16
"""Random bytes of the token ``--presenter`` alone makes: 128 bits, out of reach of guessing at any rate."""
STRONG_BITS = 64
"""A token given by hand with less estimated randomness than this [bits] is warned about."""
MAX_TOKEN_LENGTH = 200


def random_token() -> str:
    """A fresh presenter token: 128 random bits in 22 URL-safe characters (never typed on the projector:
    ``serve`` prints a presenter link that fills it in)."""
    return secrets.token_urlsafe(RANDOM_TOKEN_BYTES)


def presenter_link(url: str, token: str) -> str:
    """The presenter link ``serve`` prints, for the lab at ``url`` (``http://host:port``), by every path
    (one process or workers): ``url/?presenter=TOKEN``. In the query, never the fragment: viser's page
    opens its websocket at its own address minus the query, and a WebSocket address with a fragment is
    refused (the page would never connect). The page's script drops it from the address bar."""
    return f"{url.rstrip('/')}/?presenter={urllib.parse.quote(token, safe='')}"


def token_weakness(token: str) -> str:
    """Why ``token`` is easy to guess (short, or little randomness for its characters), or ``""``.

    The estimate is generous (length × log₂ of the character classes used): a dictionary word with a
    digit (``lecture-7``) is weak; :func:`random_token`'s are strong.
    """
    pool = sum(
        size
        for size, present in (
            (26, any(c.islower() for c in token)),
            (26, any(c.isupper() for c in token)),
            (10, any(c.isdigit() for c in token)),
            (33, any(not c.isalnum() for c in token)),
        )
        if present
    )
    bits = len(token) * math.log2(max(pool, 2))
    if len(token) < 12 or bits < STRONG_BITS:
        return (
            f"the presenter token {len(token)} characters long is easy to guess (about {bits:.0f} bits; "
            f"use at least {STRONG_BITS}, or --presenter alone for a random one)"
        )
    return ""
