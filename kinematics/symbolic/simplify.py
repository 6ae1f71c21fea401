"""Entry-by-entry simplification of a symbolic matrix, within a deadline, dropping float noise.

Each entry goes through :func:`.trig.normal_form` (expanded, canonical), loses the terms
that are negligible against its largest (:func:`drop_negligible`), then
:func:`.trig.collapse` (sums of angles) and :func:`.trig.nest` (common factors).
SymPy's steps cannot be interrupted, so the deadline is checked between entries and
between steps, and a step is started only if its expected cost fits in the time left:
collapsing costs about :data:`COLLAPSE_COST` · terms² seconds, and entries longer than
:data:`COLLAPSE_MAX` terms are never collapsed (they stay expanded). Past the deadline the
remaining entries keep their exact, unsimplified form; the notes say so, and the indices of
those entries are returned so that a later call with more time can resume where this one
stopped.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import sympy as sp

from .trig import MAX_TERMS, AngleShift, Deadline, Progress, collapse, nest, normal_form

__all__ = [
    "NEGLIGIBLE",
    "COLLAPSE_MAX",
    "COLLAPSE_COST",
    "drop_negligible",
    "simplify_entry",
    "simplify_matrix",
    "Simplified",
]

NEGLIGIBLE = 1e-12
"""Terms smaller than this fraction of the largest term of their entry are dropped."""

COLLAPSE_MAX = 64
"""Entries with more terms than this (in normal form) are not collapsed: TR10i is quadratic in the
terms (SymPy's own: 120 terms, 18 s on a 2-core machine) and finds little in such sums."""

COLLAPSE_COST = 3e-4
"""Expected seconds of collapsing per squared term: the largest measured with :mod:`.tr10i` on the
entries of 20–64 terms of the Panda, iiwa14, Centauro and xArm7 (2.5e-4; typically 3e-5; SymPy's
own TR10i: 1.5e-3)."""


def _magnitude(term: sp.Expr, q: Sequence[sp.Symbol], values: dict[sp.Symbol, float]) -> float:
    """Size of one term: |coefficient| with every sin/cos of a joint, every joint value and every
    symbol without a value taken as 1, and parameters at their values."""
    ones = {f: sp.Integer(1) for f in term.atoms(sp.sin, sp.cos) if f.has(*q)}
    t = sp.sympify(sp.sympify(term).xreplace(ones)).xreplace({k: sp.Float(v) for k, v in values.items()})
    t = t.xreplace({s: sp.Integer(1) for s in t.free_symbols})
    try:
        return abs(complex(t.evalf(15)))
    except (TypeError, ValueError):
        return float("inf")


def drop_negligible(
    expr: sp.Expr,
    q: Sequence[sp.Symbol],
    values: dict[sp.Symbol, float] | None = None,
    rel: float = NEGLIGIBLE,
) -> tuple[sp.Expr, int]:
    """Drop the terms of an expanded sum smaller than ``rel`` times its largest term.

    Exact arithmetic on snapped values leaves no such terms; they come from numbers of a robot
    file that could not be snapped (e.g. a rotation with 5 digits that is not a multiple of π/12).

    Args:
        expr: An expanded sum (e.g. a :func:`.trig.normal_form`).
        q: The joint symbols.
        values: Parameter symbols → values, to size terms that contain parameters.
        rel: Threshold relative to the largest term.

    Returns:
        The sum without the negligible terms, and how many were dropped.
    """
    terms = sp.Add.make_args(expr)
    if len(terms) < 2:
        return expr, 0
    sizes = [_magnitude(t, q, values or {}) for t in terms]
    cut = rel * max(sizes)
    kept = [t for t, m in zip(terms, sizes, strict=True) if m >= cut]
    if len(kept) == len(terms):
        return expr, 0
    return sp.Add(*kept), len(terms) - len(kept)


def simplify_entry(
    expr: sp.Expr,
    q: Sequence[sp.Symbol],
    shift: AngleShift | None = None,
    deadline: Deadline | None = None,
    values: dict[sp.Symbol, float] | None = None,
) -> tuple[sp.Expr, int, bool]:
    """Normal form, negligible terms dropped, collapsed and nested: what a person would write.

    Args:
        expr: An exact entry.
        q: The joint symbols.
        shift: Joint offsets to work around (see :class:`.trig.AngleShift`).
        deadline: Collapsing is skipped when its expected cost does not fit in the time left.
        values: Parameter values, to size terms (see :func:`drop_negligible`).

    Returns:
        The entry, the number of terms dropped, and whether it was collapsed and nested
        (False: left expanded, because it is long or time is short).
    """
    shift = shift or AngleShift(q)
    v = shift.vars
    out, dropped = drop_negligible(normal_form(shift.apply(expr), v), v, values)
    n = len(sp.Add.make_args(out))
    done = n <= 1
    if 1 < n <= COLLAPSE_MAX and (deadline is None or deadline.allows(COLLAPSE_COST * n * n)):
        out, done = collapse(out, v), True
    if done and len(sp.Add.make_args(out)) <= MAX_TERMS and (deadline is None or not deadline.expired()):
        out = nest(out, v)
    return shift.undo(out), dropped, done


class Simplified:
    """What :func:`simplify_matrix` did.

    Attributes:
        matrix: The matrix, entry by entry simplified, expanded or left as given.
        pending: (i, j) of the entries left as given at the deadline.
        expanded: (i, j) of the entries only expanded (too long, or too little time, to collapse).
        dropped: Number of negligible terms dropped.
        notes: Human-readable notes on the above.
    """

    def __init__(
        self,
        matrix: sp.Matrix,
        pending: Iterable[tuple[int, int]],
        expanded: Iterable[tuple[int, int]],
        dropped: int,
        notes: list[str],
    ) -> None:
        self.matrix = matrix
        self.pending: tuple[tuple[int, int], ...] = tuple(pending)
        self.expanded: tuple[tuple[int, int], ...] = tuple(expanded)
        self.dropped = dropped
        self.notes = notes


def simplify_matrix(
    M: sp.Matrix,
    q: Sequence[sp.Symbol],
    deadline: Deadline | None = None,
    progress: Progress | None = None,
    label: str = "J",
    shift: AngleShift | None = None,
    *,
    only: Sequence[tuple[int, int]] | None = None,
    values: dict[sp.Symbol, float] | None = None,
) -> Simplified:
    """Simplify the entries of ``M`` with :func:`simplify_entry`, within ``deadline``.

    Args:
        M: Matrix of exact expressions.
        q: Joint symbols.
        deadline: Checked before every entry and step; once expired, the remaining entries
            are left as given.
        progress: Called with a short message before each entry.
        label: Name of the matrix in messages and notes.
        shift: Joint offsets to work around (see :class:`.trig.AngleShift`).
        only: Simplify only these (i, j) (the others are taken as already done).
        values: Parameter values, to size terms.
    """
    out = M.copy()
    todo = [divmod(k, M.cols) for k in range(M.rows * M.cols)] if only is None else list(only)
    pending, expanded, dropped = [], [], 0
    for k, (i, j) in enumerate(todo):
        if deadline is not None and deadline.expired():
            pending.append((i, j))
            continue
        if progress is not None:
            progress(f"simplifying {label}: entry {k + 1}/{len(todo)}")
        out[i, j], n, done = simplify_entry(M[i, j], q, shift, deadline, values)
        dropped += n
        if not done:
            expanded.append((i, j))
    notes = []
    if pending:
        notes.append(
            f"time limit of {deadline.seconds:g} s reached while simplifying {label}: "  # type: ignore[union-attr]
            f"{len(pending)} of {M.rows * M.cols} entries are shown unsimplified (exact, but long); "
            "raise the timeout to simplify them all"
        )
    if expanded:
        notes.append(
            f"{len(expanded)} entries of {label} are shown expanded, not collapsed into sums of angles "
            f"(longer than {COLLAPSE_MAX} terms, or too little time left)"
        )
    if dropped:
        notes.append(
            f"{dropped} terms of {label} smaller than {NEGLIGIBLE:g} of the largest term of their entry "
            "were dropped (float noise of the robot's numbers)"
        )
    return Simplified(out, pending, expanded, dropped, notes)
