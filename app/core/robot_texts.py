"""A robot's texts in a tab's language: its title, description and each configuration's and motion's
description as the robot file translates them (``[translations.<language>]``, see
:mod:`robots.texts`), else in English, the file's own language (a file a user uploads may have only
English; a URDF has no translations at all).

The texts are data, never format strings: a view escapes them where it shows them.
"""

from __future__ import annotations

from collections.abc import Mapping

from kinematics import NamedConfiguration, Robot
from robots import MotionPreset

from .i18n import Translator

__all__ = [
    "text_in",
    "robot_title",
    "robot_description",
    "configuration_description",
    "motion_name",
    "motion_description",
]


def text_in(translations: Mapping[str, Mapping[str, str]], key: str, english: str, code: str) -> str:
    """The ``key`` text of ``translations`` in language ``code``, else ``english``."""
    texts = translations.get(code, {}) if code != "en" else {}
    return texts.get(key) or english


def robot_title(robot: Robot, tr: Translator) -> str:
    """The robot's title in ``tr``'s language (else English; the robot's name when it has no title)."""
    return text_in(robot.translations, "title", robot.title, tr.code) or robot.name


def robot_description(robot: Robot, tr: Translator) -> str:
    """The robot's description in ``tr``'s language (else English)."""
    return text_in(robot.translations, "description", robot.description, tr.code)


def configuration_description(conf: NamedConfiguration, tr: Translator) -> str:
    """A named configuration's description in ``tr``'s language (else English)."""
    return text_in(conf.translations, "description", conf.description, tr.code)


def motion_name(motion: MotionPreset, tr: Translator) -> str:
    """A motion preset's name in ``tr``'s language (else its own, English)."""
    return text_in(motion.translations, "name", motion.name, tr.code)


def motion_description(motion: MotionPreset, tr: Translator) -> str:
    """A motion preset's description in ``tr``'s language (else English)."""
    return text_in(motion.translations, "description", motion.description, tr.code)
