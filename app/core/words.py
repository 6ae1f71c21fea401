"""The course's words for what the app finds: a singularity's kind as the robot file names it.

The library classifies a singularity geometrically (wrist, elbow, shoulder:
:func:`kinematics.singularity.assess`); a robot file names its singular configurations in the
words of its course (002 calls the TRR's stretched arm a *boundary* singularity, at the edge of
the workspace, where the geometry says the elbow is straight). Where a file names a kind, the
status shows the file's word.
"""

from __future__ import annotations

import functools

from kinematics import Robot
from kinematics.singularity import assess

from .i18n import Translator, translations

__all__ = ["course_kinds", "status_words", "kind_word", "status_word"]


def status_word(status: str, tr: Translator) -> str:
    """The status's words in ``tr``'s language ("regular", "near singular", "singular")."""
    if status == "regular":
        return tr.pgettext("status", "regular")
    if status == "near singular":
        return tr.pgettext("status", "near singular")
    if status == "singular":
        return tr.pgettext("status", "singular")
    return status


def kind_word(kind: str, tr: Translator) -> str:
    """A singularity's kind in ``tr``'s language: the library's (wrist, elbow, shoulder) and the
    course's words robot files use (boundary); any other word as the file writes it."""
    words = {
        "wrist": tr.pgettext("singularity", "wrist"),
        "elbow": tr.pgettext("singularity", "elbow"),
        "shoulder": tr.pgettext("singularity", "shoulder"),
        "boundary": tr.pgettext("singularity", "boundary"),
    }
    return words.get(kind, kind)


@functools.lru_cache(maxsize=64)  # bounded: every edit of a DH table makes a new robot
def course_kinds(robot: Robot) -> dict[tuple[str, ...], str]:
    """The geometric kinds found at each named singular configuration → the file's word for them,
    where that word differs and no two configurations with the same kinds use different words."""
    seen: dict[tuple[str, ...], set[str]] = {}
    for c in robot.configurations:
        if not c.singular:
            continue
        kinds = tuple(assess(robot, c.q).kinds)
        if kinds:
            seen.setdefault(kinds, set()).add(c.singular)
    return {k: next(iter(w)) for k, w in seen.items() if len(w) == 1 and next(iter(w)) not in k}


def status_words(
    robot: Robot, status: str, kinds: tuple[str, ...], configuration: str = "", tr: Translator | None = None
) -> str:
    """The status line's words: "regular", "near singular: elbow", or the course's "singular: boundary
    (elbow)" where the robot file names the kind (at ``configuration``, or at any pose where the
    geometry finds the kinds of a named one); in ``tr``'s language (English when None)."""
    tr = tr or translations()
    shown = status_word(status, tr)
    if status == "regular":
        return shown
    named = next((c.singular for c in robot.configurations if c.name == configuration), "")
    word = (named if status == "singular" else "") or course_kinds(robot).get(tuple(kinds), "")
    found = " + ".join(kind_word(k, tr) for k in kinds)
    if word and found and word not in kinds:
        return tr.gettext("{status}: {word} ({kinds})").format(
            status=shown, word=kind_word(word, tr), kinds=found
        )
    if word or found:
        return tr.gettext("{status}: {kinds}").format(status=shown, kinds=kind_word(word, tr) or found)
    return shown
