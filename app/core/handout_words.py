"""The handout's words, for the catalogs: every msgid :mod:`kinematics.symbolic.handout` asks its
:class:`~kinematics.symbolic.handout.Words` for (context ``"handout"``), marked here so that
``pybabel extract`` (which reads ``app/`` only: the kinematics never import the app) puts them in the
catalogs. ``jacobian-lab handout --lang`` passes the app's :class:`~app.core.i18n.Translator` as the
handout's words.

tests/kinematics/test_handout_languages.py holds :data:`MESSAGES` and :data:`PLURALS` equal to the
handout's own calls, so a sentence added there and not here fails a test, not a lecture.
"""

from __future__ import annotations

__all__ = ["MESSAGES", "PLURALS"]


def pgettext(context: str, message: str) -> str:
    """``message``: marks a handout msgid of ``context`` for ``pybabel extract`` (pgettext's name)."""
    return message


def npgettext(context: str, singular: str, plural: str) -> tuple[str, str]:
    """(``singular``, ``plural``): marks a handout phrase with a count for ``pybabel extract``."""
    return singular, plural


MESSAGES = frozenset(
    (
        pgettext("handout", "1. The result: J(q) and det J"),
        pgettext("handout", "At the configuration “{name}”, q = ({q})."),
        pgettext("handout", "At the middle of the joint ranges, q = ({q})."),
        pgettext(
            "handout",
            "Compact notation: cᵢ = cos θᵢ, sᵢ = sin θᵢ, cᵢⱼ = cos(θᵢ + θⱼ), sᵢⱼ = sin(θᵢ + θⱼ).",
        ),
        pgettext("handout", "Convention: modified (Craig's). Lengths in metres, angles in degrees."),
        pgettext(
            "handout",
            "Convention: modified, Craig's (Aᵢ = Rx(αᵢ₋₁) Tx(aᵢ₋₁) Rz(θᵢ) Tz(dᵢ)). "
            "Lengths in metres, angles in degrees.",
        ),
        pgettext(
            "handout",
            "Convention: standard (Aᵢ = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ)). Lengths in metres, angles in degrees.",
        ),
        pgettext("handout", "Convention: standard. Lengths in metres, angles in degrees."),
        pgettext("handout", "Derived step by step below."),
        pgettext("handout", "For the tool velocity (task rows)"),
        pgettext(
            "handout",
            "J has rows [v; ω] in the base axes: v is the velocity of the tool origin [m/s], "
            "ω the angular velocity [rad/s], per unit joint rate.",
        ),
        pgettext(
            "handout",
            "J has rows [v; ω] in the tool axes: v is the velocity of the tool origin [m/s], "
            "ω the angular velocity [rad/s], per unit joint rate.",
        ),
        pgettext("handout", "J is singular here (det J = 0): it has no inverse."),
        pgettext("handout", "J is square and regular here; its inverse:"),
        pgettext("handout", "From the closed-form inverse kinematics q = g(x) (course 002, the third way):"),
        pgettext("handout", "and at constant rates (q̈ = 0) the tool accelerates: ẍ = J q̈ + J̇ q̇ = J̇ q̇ ="),
        pgettext(
            "handout",
            "Course 000's per-joint J̇ᵢ holds for joint i moving alone; the sum of its terms "
            "(equal to J̇ q̇ only when one joint moves):",
        ),
        pgettext("handout", "J(q), task rows ({rows}):"),
        pgettext(
            "handout",
            "Link lengths and offsets are kept as symbols (their values are in the notation at the end).",
        ),
        pgettext("handout", "Link transforms"),
        pgettext("handout", "Manipulability √det(J Jᵀ):"),
        pgettext("handout", "Notation"),
        pgettext("handout", "Note: {note}"),
        pgettext("handout", "Singular configurations (a factor of the determinant vanishes):"),
        pgettext("handout", "Source: {source}"),
        pgettext("handout", "The Denavit–Hartenberg table"),
        pgettext("handout", "The Jacobian of {robot}, step by step"),
        pgettext("handout", "The derivation follows: {sections}."),
        pgettext("handout", "The frames in the base"),
        pgettext("handout", "These steps give the J(q) of §1."),
        pgettext(
            "handout",
            "This robot has no DH table (a URDF chain): its link and joint frames come from the URDF file.",
        ),
        pgettext("handout", "With the joint rates q̇ = ({rates}):"),
        pgettext("handout", "Worked example"),
        pgettext("handout", "elbow singularity"),
        pgettext("handout", "joint"),
        pgettext("handout", "shoulder singularity"),
        pgettext("handout", "the joints must move at q̇ = ({rates}):"),
        pgettext("handout", "the tool velocity (task rows) is"),
        pgettext("handout", "where {items}"),
        pgettext("handout", "wrist singularity"),
        pgettext("handout", "{i} prismatic"),
        pgettext("handout", "{i} revolute"),
    )
)
"""Every handout msgid (context ``"handout"``)."""

PLURALS = frozenset(
    (
        npgettext("handout", "Robot {name}: {n} joint ({kinds}).", "Robot {name}: {n} joints ({kinds})."),
        npgettext(
            "handout",
            "The {n} method derived below does NOT agree.",
            "The {n} methods derived below do NOT agree.",
        ),
        npgettext(
            "handout",
            "The {n} method derived below gives this same J (checked numerically at random configurations).",
            "The {n} methods derived below give this same J (checked numerically at random configurations).",
        ),
    )
)
"""Every handout phrase with a count, (singular, plural) (context ``"handout"``)."""
