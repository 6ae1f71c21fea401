"""The room's questions: made by the lab from what the presenter shows, answered on every student's screen.

Peer instruction asks the room before the picture settles it. Every question here is made from the robot
and configuration on screen, and its right answer is the lab's own computation, never typed by hand:

* ``"kind"``: is this configuration singular, and of which kind (regular / wrist / elbow / shoulder /
  boundary / other)? Right: the kinds :func:`kinematics.singularity.assess` finds, in the course's word
  where the robot file names one (002's TRR *boundary*);
* ``"blowup"``: which joint's rate blows up first on a preset's motion? Right: the joints whose |q̇ᵢ| is at
  least half the largest when the motion q̇ = J⁻¹ v (the preset's own twist) stops at the singularity (the
  Puma's wrist: q̇₄ and q̇₆ together, q̇₄ = −q̇₆);
* ``"lost"``: which direction is lost? Four arrows, one a lost direction exactly as the view draws it
  (the snapshot's losses: the wrist's lost rotation axis or the arm's lost translation at the wrist
  centre, decoupled as the course teaches, or the tool's); a pointed direction counts when it lies
  within :data:`LOST_ANGLE` of a lost direction of the same part;
* ``"number"``: det J or κ of the task rows, typed as the student's language writes numbers, right within
  the question's stated tolerance;
* ``"custom"``: the teacher's own prompt and choices (plain text, checked for length; the views escape it).

Pure: functions of ``(robot, q)`` and of the text a teacher typed; :mod:`app.core.poll` keeps a round's
answers and counts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from kinematics import Robot
from kinematics.analysis import task_rows
from kinematics.motion import resolved_rate
from kinematics.numeric import jacobian
from kinematics.singularity import assess

from .i18n import N_
from .snapshot.losses import Loss
from .words import course_kinds

__all__ = [
    "QuestionError",
    "QuestionKind",
    "Question",
    "Arrow",
    "KIND_CHOICES",
    "LOST_ANGLE",
    "NUMBER_REL_TOL",
    "kind_question",
    "blowup_question",
    "lost_question",
    "number_question",
    "custom_question",
    "direction_is_right",
    "ASKABLE",
    "make",
]

QuestionKind = Literal["kind", "blowup", "lost", "number", "custom"]
KIND_CHOICES = ("regular", "wrist", "elbow", "shoulder", "boundary", "other")
"""The choices of a ``"kind"`` question (the course's words; "boundary" is 002's stretched TRR; "other":
singular, of a kind the lab's geometric tests do not name, e.g. the Panda's aligned axes)."""
LOST_ANGLE = math.radians(20.0)
"""A pointed lost direction counts within 20° of the lab's (sign-free: a lost line has no sense)."""
NUMBER_REL_TOL = 0.05
"""A typed det J or κ counts within 5 % of the lab's (or an absolute floor, see :func:`number_question`)."""
_DISTINCT = math.radians(30.0)
_END_ON = math.radians(35.0)
"""Candidate arrows of a ``"lost"`` question are at least 30° apart, so each is told from the others."""
_GROWTH = 3.0
"""A motion's joint rates "blow up" when the largest |q̇ᵢ| at its end is at least 3 times that at its start."""
_HALF = 0.5
"""Joints whose |q̇ᵢ| reaches half the largest at the stop count as blowing up together."""
MAX_PROMPT = 300
MAX_CHOICE = 120
MAX_CHOICES = 6


class QuestionError(ValueError):
    """A question that cannot be asked here; the message (a catalog msgid, filled in) says why."""


@dataclass(frozen=True)
class Arrow:
    """A candidate of a ``"lost"`` question: a line through the tool, as a translation or a rotation axis.

    Attributes:
        part: ``"translation"`` or ``"rotation"``.
        direction: Unit vector (3,) in base axes (sign irrelevant).
        point: Where it is drawn (3,) [m]: the loss's point (wrist centre or tool point).
    """

    part: Literal["translation", "rotation"]
    direction: tuple[float, float, float]
    point: tuple[float, float, float]


@dataclass(frozen=True)
class Question:
    """One question of the room, frozen when the presenter opens it.

    Attributes:
        kind: What is asked (see the module's list).
        prompt: The question's words: a catalog msgid for the lab's questions, the teacher's text for
            ``"custom"``.
        choices: What a follower may answer, as ids (``"wrist"``, ``"q4"``, ``"A"``, or a custom choice's
            text); empty for a ``"number"`` question.
        right: The ids of the right choices (several when the lab finds several, e.g. q4 and q6).
        value: A ``"number"`` question's right value (det J or κ of the task rows); 0.0 otherwise.
        tolerance: A ``"number"`` answer counts when within this of ``value``.
        quantity: ``"det"`` or ``"kappa"`` for a ``"number"`` question, else "".
        arrows: A ``"lost"`` question's candidates, one per choice (``choices[i]`` names ``arrows[i]``).
        lost: A ``"lost"`` question's lost directions (every one of a multi-rank loss).
        robot: The robot's name, q the configuration asked about (the reveal goes back there).
    """

    kind: QuestionKind
    prompt: str
    choices: tuple[str, ...]
    right: frozenset[str]
    robot: str
    q: tuple[float, ...]
    value: float = 0.0
    tolerance: float = 0.0
    quantity: str = ""
    arrows: tuple[Arrow, ...] = ()
    lost: tuple[Arrow, ...] = ()


def _q(robot: Robot, q: object) -> tuple[np.ndarray, tuple[float, ...]]:
    qa = np.asarray(q, dtype=float).reshape(-1)
    if qa.shape != (robot.dof,) or not np.isfinite(qa).all():
        raise QuestionError(N_("the configuration does not fit the robot"))
    return qa, tuple(float(x) for x in qa)


def kind_question(robot: Robot, q: object, configuration: str = "") -> Question:
    """ "Is this configuration singular? Which kind?", answered by :func:`assess` (at ``configuration``,
    the robot file's word for its kind wins, as the status line says it)."""
    qa, qt = _q(robot, q)
    report = assess(robot, qa)
    if report.status == "regular":
        right = frozenset({"regular"})
    else:
        named = next((c.singular for c in robot.configurations if c.name == configuration), "")
        word = named or course_kinds(robot).get(tuple(report.kinds), "")
        right = frozenset(k for k in (*report.kinds, word) if k in KIND_CHOICES) or frozenset({"other"})
    return Question(
        "kind", N_("Is this configuration singular? Which kind?"), KIND_CHOICES, right, robot.name, qt
    )


def blowup_question(
    robot: Robot, q: object, twist: object, *, frame: str = "base", dt: float = 1e-3, steps: int = 20000
) -> Question:
    """ "Which joint's rate blows up first?" on the motion q̇ = J⁻¹ v from ``q`` with the preset's ``twist``:
    followed (as :func:`kinematics.motion.resolved_rate.resolved_rate`) until it stops (near the
    singularity, at the rate bound, or where a joint meets its limit, as the app's Play does); right are
    the joints whose |q̇ᵢ| at the stop is at least half the largest."""
    qa, qt = _q(robot, q)
    v = np.asarray(twist, dtype=float).reshape(-1)
    if v.shape != (6,) or not np.isfinite(v).all() or not np.any(v):
        raise QuestionError(N_("the motion has no tool velocity: choose a preset first"))
    run = resolved_rate.resolved_rate(
        robot, qa, v, dt=dt, steps=steps, frame="tool" if frame == "tool" else "base", rows=task_rows(robot)
    )
    qd = np.abs(np.asarray(run.qd))
    top = float(qd[-1].max()) if len(qd) else 0.0
    if len(qd) == 0 or top < _GROWTH * max(float(qd[0].max()), 1e-12):
        raise QuestionError(N_("this motion meets no singularity: no joint rate blows up"))
    rates = qd[-1]
    right = frozenset(f"q{i + 1}" for i in range(robot.dof) if rates[i] >= _HALF * top)
    choices = tuple(f"q{i + 1}" for i in range(robot.dof))
    return Question("blowup", N_("Which joint's rate blows up first?"), choices, right, robot.name, qt)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """The angle between two lines (sign-free) [rad]."""
    c = abs(float(np.dot(a, b))) / max(float(np.linalg.norm(a) * np.linalg.norm(b)), 1e-300)
    return math.acos(min(1.0, c))


def _arrow(loss: Loss) -> Arrow:
    part: Literal["translation", "rotation"] = "translation" if loss.translation_share >= 0.5 else "rotation"
    u = loss.translation if part == "translation" else loss.rotation
    p = loss.point
    return Arrow(part, (float(u[0]), float(u[1]), float(u[2])), (float(p[0]), float(p[1]), float(p[2])))


def lost_question(
    robot: Robot,
    q: object,
    losses: tuple[Loss, ...],
    seed: int = 0,
    count: int = 4,
    sight: object = None,
) -> Question:
    """ "Which direction is lost?": ``count`` arrows A, B, … one of them a lost direction the view draws
    (``losses``: the snapshot's, the wrist's lost rotation axis at the wrist centre, the arm's lost
    translation there, or the tool's), the others lines of the base axes and of the joint axes at least
    30° from every other arrow of the same part, all at the first loss's point, and none within 35° of the
    presenter's line of ``sight`` (its camera's look direction: a line seen end-on is a dot); their order
    drawn from ``seed`` (the round's number, so every worker draws the same)."""
    _, qt = _q(robot, q)
    if not losses:
        raise QuestionError(N_("nothing is lost in a regular configuration: go to a singularity first"))
    lost = tuple(_arrow(x) for x in losses)
    answer = lost[0]
    axes = [np.eye(3)[i] for i in range(3)]
    J = jacobian(robot, np.array(qt))
    axes += [J[3:, i] / np.linalg.norm(J[3:, i]) for i in range(robot.dof) if np.linalg.norm(J[3:, i]) > 1e-9]
    pool: list[Arrow] = []
    line_of_sight = None if sight is None else np.asarray(sight, dtype=float).reshape(-1)
    if line_of_sight is not None and (line_of_sight.shape != (3,) or not np.linalg.norm(line_of_sight) > 0):
        line_of_sight = None
    other: Literal["translation", "rotation"] = "rotation" if answer.part == "translation" else "translation"
    for part in (answer.part, other):
        for a in axes:
            taken = [*lost, *pool]
            end_on = line_of_sight is not None and _angle(line_of_sight, a) < _END_ON
            if not end_on and all(
                x.part != part or _angle(np.array(x.direction), a) >= _DISTINCT for x in taken
            ):
                pool.append(Arrow(part, (float(a[0]), float(a[1]), float(a[2])), answer.point))
    rng = np.random.default_rng(seed)
    picked = sorted(int(i) for i in rng.choice(len(pool), size=min(count - 1, len(pool)), replace=False))
    arrows = [answer, *(pool[i] for i in picked)]
    arrows = [arrows[int(i)] for i in rng.permutation(len(arrows))]
    letters = tuple("ABCDEF"[: len(arrows)])
    right = frozenset(
        letters[i] for i, a in enumerate(arrows) if direction_is_right(lost, a.part, a.direction)
    )
    prompt = N_("Which direction is lost?")
    return Question("lost", prompt, letters, right, robot.name, qt, arrows=tuple(arrows), lost=lost)


def direction_is_right(lost: tuple[Arrow, ...], part: str, direction: object) -> bool:
    """A pointed line counts when within :data:`LOST_ANGLE` of a lost direction of the same part."""
    d = np.asarray(direction, dtype=float).reshape(-1)
    if d.shape != (3,) or not np.isfinite(d).all() or float(np.linalg.norm(d)) < 1e-12:
        return False
    return any(a.part == part and _angle(np.array(a.direction), d) <= LOST_ANGLE for a in lost)


def number_question(robot: Robot, q: object, quantity: str) -> Question:
    """ "What is det J here?" (square task rows only) or "What is κ here?" (finite only), right within
    5 % of the lab's value, or an absolute floor (det: 1 % of the product of the singular values at
    home; κ: 0.5), so that det J = 0 at a singularity is answered by a small number too."""
    qa, qt = _q(robot, q)
    rows = list(task_rows(robot))
    Jt = jacobian(robot, qa)[rows]
    if quantity == "det":
        if Jt.shape[0] != Jt.shape[1]:
            raise QuestionError(N_("det J needs as many task rows as joints: ask for κ instead"))
        value = float(np.linalg.det(Jt))
        scale = float(np.prod(np.linalg.svd(jacobian(robot, robot.home)[rows], compute_uv=False)))
        floor = 0.01 * scale if scale > 0 else 1e-3
        prompt = N_("What is det J here?")
    elif quantity == "kappa":
        s = np.linalg.svd(Jt, compute_uv=False)
        if s[-1] <= 1e-9 * max(float(s[0]), 1.0):
            raise QuestionError(N_("κ is infinite at a singularity: ask for det J instead"))
        value = float(s[0] / s[-1])
        floor = 0.5
        prompt = N_("What is κ here?")
    else:
        raise QuestionError(N_("a number question asks for det J or κ"))
    tolerance = max(NUMBER_REL_TOL * abs(value), floor)
    return Question("number", prompt, (), frozenset(), robot.name, qt, value, tolerance, quantity)


def _clean(text: object, most: int) -> str:
    if not isinstance(text, str):
        raise QuestionError(N_("a question's text must be text"))
    cleaned = " ".join("".join(ch for ch in text if ch.isprintable()).split())
    if not cleaned:
        raise QuestionError(N_("the question or one of its choices is empty"))
    if len(cleaned) > most:
        raise QuestionError(N_("the question or one of its choices is too long"))
    return cleaned


def custom_question(robot: Robot, q: object, prompt: object, choices: object, right: object) -> Question:
    """The teacher's question: a prompt (≤ 300 characters), 2–6 distinct choices (≤ 120 each) and the
    indices of the right ones (none: an opinion poll, nobody is told right or wrong)."""
    _, qt = _q(robot, q)
    text = _clean(prompt, MAX_PROMPT)
    if not isinstance(choices, (list, tuple)) or not 2 <= len(choices) <= MAX_CHOICES:
        raise QuestionError(N_("a question needs 2 to 6 choices"))
    options = tuple(_clean(c, MAX_CHOICE) for c in choices)
    if len(set(options)) != len(options):
        raise QuestionError(N_("two choices are the same"))
    if not isinstance(right, (list, tuple)) or not all(
        isinstance(i, int) and not isinstance(i, bool) and 0 <= i < len(options) for i in right
    ):
        raise QuestionError(N_("the right answer must be one of the choices"))
    return Question("custom", text, options, frozenset(options[i] for i in right), robot.name, qt)


ASKABLE = ("kind", "blowup", "lost", "det", "kappa", "custom")
"""What the presenter's menu offers (:class:`app.core.commands.AskRoom`'s ``kind``)."""


def make(
    kind: str,
    robot: Robot,
    q: object,
    *,
    configuration: str = "",
    losses: tuple[Loss, ...] = (),
    twist: object = None,
    frame: str = "base",
    prompt: object = "",
    choices: object = (),
    right: object = (),
    seed: int = 0,
    sight: object = None,
) -> Question:
    """The question ``kind`` (one of :data:`ASKABLE`) about ``robot`` at ``q``, as the presenter shows it:
    ``losses`` the snapshot's, ``twist``/``frame`` the motion a "blowup" question is about."""
    if kind == "kind":
        return kind_question(robot, q, configuration)
    if kind == "blowup":
        return blowup_question(robot, q, np.zeros(6) if twist is None else twist, frame=frame)
    if kind == "lost":
        return lost_question(robot, q, losses, seed=seed, sight=sight)
    if kind in ("det", "kappa"):
        return number_question(robot, q, kind)
    if kind == "custom":
        return custom_question(robot, q, prompt, choices, right)
    raise QuestionError(N_("that is not a question the lab asks"))
