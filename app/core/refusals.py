"""Why a motion stopped or was refused, said in a tab's language.

The state keeps ``stopped`` in English (it is the state's, shared with a presenter's followers, who may
read another language), written by :mod:`app.core.motion_rules`, by the kinematics' resolved-rate step
(``kinematics`` never imports ``app``) and by the nearest-singularity search. Each such sentence is one
of :data:`TEMPLATES` with its values filled in; :func:`say` finds the template, translates it and fills
in the same values, their numbers written as the language writes them (``−110°`` stays, ``0.42`` reads
``0,42``) and the singularity's kinds in its words. A sentence no template matches is shown as it is.
"""

from __future__ import annotations

import functools
import re

from .i18n import N_, Translator
from .words import kind_word

__all__ = ["TEMPLATES", "say"]

TEMPLATES: tuple[str, ...] = (
    # app.core.motion_rules
    N_("set a joint rate q̇ first"),
    N_("set a tool velocity v first (or choose a preset)"),
    N_("{robot} has no redundancy to climb with"),
    N_("stopped: {joints} reached the end of its range"),
    N_("w of the held rows ({held}) reached a maximum with the tool held: w = {w}"),
    N_("self-motion stops here: {joints} would leave its range"),
    # kinematics.motion.resolved_rate (its Stop.message), after motion_rules' "stopped: "
    N_("stopped: joint {number} {name} would pass its upper limit {value}"),
    N_("stopped: joint {number} {name} would pass its lower limit {value}"),
    N_("stopped: joint {number} {name} would need {need}"),
    # app.core.reducer (the null motion, Ker J)
    N_("the null motion {motion} moved the joints; the tool stood still"),
    # app.core.tool_path (the course's Jacobian IK along a path)
    N_("the tool followed the line: q̇ = J⁺ẏ(t) held the error below {error} m"),
    N_("the tool followed the circle: q̇ = J⁺ẏ(t) held the error below {error} m"),
    N_("the tool left the line near a singularity: the error reached {error} m, a joint rate {rate} rad/s"),
    N_("the tool left the circle near a singularity: the error reached {error} m, a joint rate {rate} rad/s"),
    # app.tab.commands, while the search runs
    N_("looking for the nearest singularity…"),
    # app.services.background.nearest_path
    N_("found: a singularity here (σmin/σmax = {ratio})"),
    N_("closest found: σmin/σmax = {ratio} (a singularity nearby)"),
    N_("found: {kinds} singularity here (σmin/σmax = {ratio})"),
    N_("closest found: σmin/σmax = {ratio} ({kinds} singularity nearby)"),
)
"""Every sentence ``stopped`` may hold, in English, as the code that writes it formats it (the
placeholders are its values); the most specific first."""

_NUMBER = re.compile(r"(?<![\w.])[+\-−]?\d+\.\d+(?![\d.])")
"""A decimal number in a value (a mantissa too: "1.0" of "1.0e-07")."""


@functools.cache
def _pattern(template: str) -> re.Pattern[str]:
    parts = re.split(r"\{(\w+)\}", template)
    regex = "".join(re.escape(p) if i % 2 == 0 else f"(?P<{p}>.+?)" for i, p in enumerate(parts))
    return re.compile(regex)


def _value(name: str, text: str, tr: Translator) -> str:
    if name == "kinds":  # "wrist and elbow": the course's words for each kind
        return tr.gettext(" and ").join(kind_word(k, tr) for k in text.split(" and "))
    return _NUMBER.sub(lambda m: tr.decimal(m.group(0)), text)


def say(text: str, tr: Translator) -> str:
    """``text`` (a ``stopped`` sentence, English) in ``tr``'s language: its template translated with
    the same values; ``text`` itself when no template matches (and English needs nothing)."""
    if not text or tr.code == "en":
        return text
    for template in TEMPLATES:
        match = _pattern(template).fullmatch(text)
        if match is not None:
            values = {k: _value(k, v, tr) for k, v in match.groupdict().items()}
            return tr.gettext(template).format(**values)
    return tr.gettext(text)
