"""A room question as JSON-ready data, for the room's hub between worker processes (never a pickle):
:func:`to_wire` writes it, :func:`from_wire` reads and checks it (a malformed one raises
:class:`~app.core.questions.QuestionError`)."""

from __future__ import annotations

import math

from .questions import MAX_CHOICE, MAX_PROMPT, Arrow, Question, QuestionError

__all__ = ["to_wire", "from_wire"]


def to_wire(question: Question) -> dict[str, object]:
    """``question`` as JSON-ready data (the room's hub carries it to the other workers)."""

    def arrow(a: Arrow) -> list[object]:
        return [a.part, list(a.direction), list(a.point)]

    return {
        "kind": question.kind,
        "prompt": question.prompt,
        "choices": list(question.choices),
        "right": sorted(question.right),
        "robot": question.robot,
        "q": list(question.q),
        "value": question.value,
        "tolerance": question.tolerance,
        "quantity": question.quantity,
        "arrows": [arrow(a) for a in question.arrows],
        "lost": [arrow(a) for a in question.lost],
    }


def _triple(x: object) -> tuple[float, float, float]:
    if not isinstance(x, list) or len(x) != 3:
        raise QuestionError("a wire arrow needs three numbers")
    a, b, c = (float(v) for v in x)
    if not all(math.isfinite(v) for v in (a, b, c)):
        raise QuestionError("a wire arrow needs finite numbers")
    return a, b, c


def _wire_arrow(x: object) -> Arrow:
    if not isinstance(x, list) or len(x) != 3 or x[0] not in ("translation", "rotation"):
        raise QuestionError("a wire arrow is [part, direction, point]")
    return Arrow(x[0], _triple(x[1]), _triple(x[2]))


def from_wire(data: object) -> Question:
    """The question :func:`to_wire` wrote, checked (a malformed one raises :class:`QuestionError`)."""
    if not isinstance(data, dict) or data.get("kind") not in ("kind", "blowup", "lost", "number", "custom"):
        raise QuestionError("not a question")
    choices = data.get("choices")
    right = data.get("right")
    q = data.get("q")
    if not (isinstance(choices, list) and isinstance(right, list) and isinstance(q, list)):
        raise QuestionError("a question's choices, right answers and q are lists")
    if len(choices) > 8 or not all(isinstance(c, str) and len(c) <= MAX_CHOICE for c in choices):
        raise QuestionError("a question's choices are at most 8 short texts")
    if not set(right) <= set(choices) or not isinstance(data.get("prompt"), str):
        raise QuestionError("a question's right answers are among its choices")
    values = [float(v) for v in (data.get("value", 0.0), data.get("tolerance", 0.0), *q)]
    if not all(math.isfinite(v) for v in values):
        raise QuestionError("a question's numbers are finite")
    arrows, lost = data.get("arrows", []), data.get("lost", [])
    if not (isinstance(arrows, list) and isinstance(lost, list)) or len(arrows) > 8 or len(lost) > 6:
        raise QuestionError("a question's arrows are lists")
    return Question(
        kind=data["kind"],
        prompt=str(data["prompt"])[:MAX_PROMPT],
        choices=tuple(choices),
        right=frozenset(right),
        robot=str(data.get("robot", ""))[:200],
        q=tuple(values[2:]),
        value=values[0],
        tolerance=values[1],
        quantity=str(data.get("quantity", ""))[:10],
        arrows=tuple(_wire_arrow(a) for a in arrows),
        lost=tuple(_wire_arrow(a) for a in lost),
    )
