"""The robot dropdown's entries: a library robot by its title and file name ("Unimation PUMA 560
(puma560)"), any other robot (a file, an upload, the Build tab's) by its name.

The dropdown shows labels and the app works with names: :func:`robot_menu` gives both ways, one
label per name (a label that would repeat another gets a number), so a picked label names exactly
one robot and a value that is neither a label nor a name is refused where it enters.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import robots

__all__ = ["RobotMenu", "robot_menu", "robot_label"]


@functools.cache  # bounded: the library's names times the languages
def _title(name: str, code: str) -> str:
    info = robots.info(name)
    translated = info.get("translations", {}).get(code, {}).get("title", "") if code != "en" else ""
    return str(translated or info.get("title") or "").strip()


def robot_label(name: str, code: str = "en") -> str:
    """``name``'s entry in the menu: "<title> (<name>)" for a library robot with a title (in language
    ``code`` where its file translates it, else English), else ``name``."""
    title = _title(name, code) if name in robots.names() else ""
    return f"{title} ({name})" if title else name


@dataclass(frozen=True)
class RobotMenu:
    """The dropdown's labels, in the order of the names, and each label's robot name."""

    labels: tuple[str, ...]
    names: dict[str, str]

    def label_of(self, name: str) -> str:
        """The label shown for robot ``name`` (``name`` itself when it is not listed)."""
        return next((label for label, n in self.names.items() if n == name), name)

    def name_of(self, value: object) -> str | None:
        """The robot a picked ``value`` names (a label, or a robot's own name), or ``None``."""
        text = str(value)
        if text in self.names:
            return self.names[text]
        return text if text in self.names.values() else None


def robot_menu(names: Sequence[str], code: str = "en") -> RobotMenu:
    """The menu of the robots ``names`` (the tab's catalogue, its own robots first), its titles in
    language ``code``."""
    labels: dict[str, str] = {}
    for name in names:
        label, k = robot_label(name, code), 2
        while label in labels:  # a file robot named like a library robot's label
            label, k = f"{robot_label(name, code)} [{k}]", k + 1
        labels[label] = name
    return RobotMenu(labels=tuple(labels), names=labels)
