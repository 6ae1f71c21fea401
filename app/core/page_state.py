"""What a tab's page keeps across a reload or a server restart, read back as hostile input.

The page keeps the tab's robot, q, open tab and chosen language in its address
(``?robot=puma560&q=0,0.5,…&tab=Motion&lang=pt``) and a presenter's reconnect key in its local
storage; on every (re)connection its script reports them with the browser's languages
(``navigator.languages``) (:mod:`app.views.panel.page`). Anyone can edit an address, so everything
is checked like a widget value: a bounded JSON object of known keys, a robot of the catalogue, q of
the robot's joint count, finite, clamped to its slider ranges, and a tab of the panel's.
"""

from __future__ import annotations

import functools
import json
import math
import re
from dataclasses import dataclass
from urllib.parse import parse_qs, quote

from kinematics import Robot

from .ranges import joint_ranges

__all__ = ["PageReport", "PageError", "parse_report", "page_address", "checked_q", "MAX_REPORT"]

MAX_REPORT = 4096
"""Longest report a page may send [characters]."""
_SECRET = re.compile(r"[A-Za-z0-9_\-]{16,64}")
_NAME = re.compile(r"[^\x00-\x1f\x7f]{1,120}")
_TAG = re.compile(r"[A-Za-z]{1,8}(?:[-_][A-Za-z0-9]{1,8}){0,4}")
"""A language tag as a browser or an address writes it (``pt``, ``pt-BR``, ``zh-Hant-TW``)."""


class PageError(ValueError):
    """A report or an address that cannot be taken; the message says what is wrong, in words."""


@dataclass(frozen=True)
class PageReport:
    """One report of the page.

    Attributes:
        kind: "load" (the page (re)connected: restore), "tab" (the user opened a tab) or "view" (the
            window's size, on load and when it changes).
        resume: The presenter's reconnect key kept by the page ("" when none).
        robot: The robot named in the address ("" when none).
        q: The joint values of the address [rad | m] (unchecked against a robot), or ``None``.
        tab: The open tab's label ("" when none).
        lang: The language the address asks for (``?lang=``), as written there ("" when none; an
            unknown one is kept so the tab can say it speaks English instead).
        browser: The browser's languages (``navigator.languages``), most wanted first.
        window: A "view" report's window: (width, height) [CSS px] and whether it is a touch screen
            (None: not a size).
    """

    kind: str
    resume: str = ""
    robot: str = ""
    q: tuple[float, ...] | None = None
    tab: str = ""
    lang: str = ""
    browser: tuple[str, ...] = ()
    window: tuple[float, float, bool] | None = None


def parse_report(text: object, tabs: tuple[str, ...]) -> PageReport:
    """The page's report ``text`` (JSON), checked.

    Raises:
        PageError: not text, too long, not a JSON object, an unknown kind, a bad key, robot, q or tab.
    """
    if not isinstance(text, str) or len(text) > MAX_REPORT:
        raise PageError("the page's report is not text of at most 4096 characters")
    try:
        data = json.loads(text)
    except ValueError:
        raise PageError("the page's report is not JSON") from None
    if not isinstance(data, dict) or data.get("kind") not in ("load", "tab", "view"):
        raise PageError("the page's report is not a load, tab or view report")
    if data["kind"] == "view":
        return PageReport("view", window=_window(data))
    tab = data.get("tab", "")
    if not isinstance(tab, str) or (tab and tab not in tabs):
        raise PageError(f"there is no tab {str(tab)[:40]!r}")
    if data["kind"] == "tab":
        return PageReport("tab", tab=tab)
    resume = data.get("resume", "")
    if not isinstance(resume, str) or (resume and not _SECRET.fullmatch(resume)):
        resume = ""  # a stale or edited key is not an error: the tab simply does not present
    address = data.get("address", "")
    if not isinstance(address, str):
        raise PageError("the page's address is not text")
    robot, q, tab_in_address, lang = _address(address)
    if tab_in_address and tab_in_address not in tabs:
        tab_in_address = ""  # an edited tab name: the default tab
    browser = data.get("languages", [])
    if not isinstance(browser, list):
        browser = []
    tags = tuple(t for t in browser[:16] if isinstance(t, str) and _TAG.fullmatch(t))
    return PageReport("load", resume, robot, q, tab_in_address or tab, lang, tags)


def _window(data: dict) -> tuple[float, float, bool] | None:
    """A view report's window size [CSS px] (each 1 to 20000) and touch flag; None when it is not a
    size (nothing to tell the user: the labels stay placed for the camera's canvas)."""
    width, height = data.get("width"), data.get("height")
    for x in (width, height):
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not 1 <= x <= 20000:
            return None
    return float(width), float(height), data.get("touch") is True  # type: ignore[arg-type]


def _address(address: str) -> tuple[str, tuple[float, ...] | None, str, str]:
    fields = parse_qs(address.lstrip("?#"), keep_blank_values=False, max_num_fields=8)
    lang = fields.get("lang", [""])[0][:40]
    if lang and not _TAG.fullmatch(lang):
        lang = "?"  # not a language tag: unknown, spoken as English with a notice
    robot = fields.get("robot", [""])[0]
    if robot and not _NAME.fullmatch(robot):
        raise PageError("the address names no robot this lab can show")
    q: tuple[float, ...] | None = None
    if "q" in fields:
        parts = fields["q"][0].split(",")
        if len(parts) > 64:
            raise PageError("the address's q has more than 64 joints")
        try:
            q = tuple(float(p) for p in parts)
        except ValueError:
            raise PageError("the address's q is not a list of numbers") from None
        if not all(math.isfinite(x) for x in q):
            raise PageError("the address's q is not finite")
    return robot, q, fields.get("tab", [""])[0], lang


def checked_q(robot: Robot, q: tuple[float, ...]) -> tuple[float, ...]:
    """``q`` [rad | m] for ``robot``: its joint count, each value clamped to the joint's slider range.

    Raises:
        PageError: a joint count other than the robot's.
    """
    if len(q) != robot.dof:
        raise PageError(f"the address's q has {len(q)} values, {robot.name} has {robot.dof} joints")
    return tuple(r.clamp_si(x) for r, x in zip(joint_ranges(robot), q, strict=True))


def page_address(robot_name: str, q: tuple[float, ...] | list[float], lang: str = "") -> str:
    """The address fragment of a robot, q (6 decimals: µrad and µm) and the tab's chosen language
    (left out when "": the browser's), e.g. ``robot=trr&q=5,1.047198,…&lang=pt``. Kept for the last
    addresses asked for: a room's followers ask for the presenter's, each after each move."""
    return _page_address(robot_name, tuple(float(x) for x in q), lang)


@functools.lru_cache(maxsize=64)
def _page_address(robot_name: str, q: tuple[float, ...], lang: str) -> str:
    values = ",".join(_short(x) for x in q)
    chosen = f"&lang={quote(lang, safe='')}" if lang else ""
    return f"robot={quote(robot_name, safe='')}&q={values}{chosen}"


def _short(x: float) -> str:
    text = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text
