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

__all__ = ["course_kinds", "status_words"]


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


def status_words(robot: Robot, status: str, kinds: tuple[str, ...], configuration: str = "") -> str:
    """The status line's words: "regular", "near singular: elbow", or the course's "singular: boundary
    (elbow)" where the robot file names the kind (at ``configuration``, or at any pose where the
    geometry finds the kinds of a named one)."""
    if status == "regular":
        return status
    named = next((c.singular for c in robot.configurations if c.name == configuration), "")
    word = (named if status == "singular" else "") or course_kinds(robot).get(tuple(kinds), "")
    found = " + ".join(kinds)
    if word and found and word not in kinds:
        return f"{status}: {word} ({found})"
    return f"{status}: {word or found}" if (word or found) else status
