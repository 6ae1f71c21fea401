"""The robot files' translated texts (issue 27) in each course's words and numbers: every translation of
a text that names a glossary term (app/locale/glossary.toml) uses the course's word for it and none the
course would not use ("junta", never "articulação", in pt), decimals are written with a comma, and the
translated languages are the app's."""

from __future__ import annotations

import re

import pytest
from i18n_words import glossary_problems

import robots
from app.core.i18n import CODES
from robots.texts import TEXT_LANGUAGES


def pairs(name: str, code: str) -> list[tuple[str, str, str]]:
    """(where, English, translation) of every text robot ``name``'s file translates into ``code``."""
    robot = robots.load(name)
    out = [
        (f"{name} {key}", getattr(robot, key), text) for key, text in robot.translations.get(code, {}).items()
    ]
    out += [
        (f"{name} configuration {c.name}", c.description, c.translations[code]["description"])
        for c in robot.configurations
        if code in c.translations
    ]
    out += [
        (f"{name} motion {m.name}", m.description, m.translations[code]["description"])
        for m in robots.motions(name)
        if code in m.translations
    ]
    return out


def problems_of(code: str, where: str, english: str, text: str) -> list[str]:
    out = [f"{where}: {problem}" for problem in glossary_problems(code, english, text)]
    if re.search(r"\d\.\d", text):
        out.append(f"{where}: a decimal point where {code} writes a comma: {text!r}")
    return out


def test_the_languages_of_robot_files_are_the_apps():
    assert ("en", *TEXT_LANGUAGES) == CODES


@pytest.mark.parametrize("code", TEXT_LANGUAGES)
def test_every_robot_text_says_the_courses_words_and_writes_decimal_commas(code):
    problems = []
    for name in robots.names():
        for where, english, text in pairs(name, code):
            problems += problems_of(code, where, english, text)
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize(
    "name",
    robots.names(),
)
@pytest.mark.parametrize("code", TEXT_LANGUAGES)
def test_the_course_robots_are_translated_in_full(name, code):
    """Every library robot: title, description, every configuration and motion."""
    robot = robots.load(name)
    assert set(robot.translations[code]) == {"title", "description"}
    assert all(code in c.translations for c in robot.configurations)
    assert all(code in m.translations for m in robots.motions(name))
    english = {robot.description, *(c.description for c in robot.configurations)}
    assert not english & {text for _, _, text in pairs(name, code)}  # translated, not copied


def test_the_check_finds_a_word_the_course_would_not_use():
    """The check can fail: a Portuguese "articulação", a Polish "narzędzie", a decimal point."""
    english = "All joints at zero: the tool moves 0.1 m."
    assert problems_of("pt", "x", english, "Todas as articulações em zero: a garra anda 0,1 m.")
    assert problems_of("pl", "x", english, "Wszystkie przeguby w zerze: narzędzie przesuwa się o 0,1 m.")
    assert problems_of("es", "x", english, "Todas las articulaciones en cero: el extremo avanza 0.1 m.")
    assert not problems_of("pt", "x", english, "Todas as juntas em zero: a garra anda 0,1 m.")
