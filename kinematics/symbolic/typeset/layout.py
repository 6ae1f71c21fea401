"""Matrices typeset entry by entry: within a deadline, long entries left out or wrapped over lines.

Printing a 7-joint arm's unsimplified J can take longer than deriving it, and a long entry
makes a matrix wider than any screen. Here every entry is printed on its own, so that

* the deadline is checked between entries: past it only short entries are typeset, and
  entries longer than :data:`MAX_PRINT_TERMS` terms never are; the others are shown as ∗
  (the Python and JSON exports hold them);
* in MathML, an entry wider than ``width`` (in characters, about 10 px each) is broken
  into lines: a sum after a term (continuation lines start with + or −), a product with a
  long sum inside its parentheses, so that J never needs sideways scrolling in a panel of
  about 600 px.
"""

from __future__ import annotations

import re
from collections.abc import Callable

import sympy as sp

from ..trig import Deadline
from .printing import Notation

__all__ = [
    "MAX_PRINT_TERMS",
    "MATHML_WIDTH",
    "latex_matrix",
    "mathml_matrix",
    "mathml_lines",
    "text_width",
    "too_long",
]

MAX_PRINT_TERMS = 400
"""Entries with more terms than this (expanded) are not typeset: nobody reads them."""

LATE_NODES = 200
"""Past the deadline, only entries of at most this many tree nodes are still typeset."""

MATHML_WIDTH = 44
"""Widest line of a MathML entry, in characters (a 600 px panel at the app's font size)."""

_TAG = re.compile(r"<[^>]+>")
_ENTITY = re.compile(r"&#?\w+;")
_INVISIBLE = ("\u2061", "\u2062")


def text_width(mathml: str) -> float:
    """Rough width of a MathML fragment in characters (subscripts count 0.7, invisible operators 0)."""
    width = 0.0
    for sub in re.findall(r"<msub>.*?</msub>", mathml):
        width -= 0.3 * max(0, len(_TAG.sub("", sub)) - 1)
    text = _ENTITY.sub("x", _TAG.sub("", mathml))
    return width + sum(0 if c in _INVISIBLE else 1 for c in text)


def _terms(N: Notation, expr: sp.Expr) -> list[sp.Expr]:
    return N.ordered_terms(expr) if expr.is_Add else [expr]


def _pack(pieces: list[str], width: float) -> list[str]:
    lines: list[str] = []
    for p in pieces:
        if lines and text_width(lines[-1]) + text_width(p) <= width:
            lines[-1] += p
        else:
            lines.append(p)
    return lines


def mathml_lines(N: Notation, expr: sp.Expr, width: float = MATHML_WIDTH) -> list[str]:
    """``expr`` as MathML lines of at most ``width`` characters where it can be broken.

    A sum breaks before a + or −; a product whose widest factor is a sum breaks inside its
    parentheses; anything else is one line (however wide).
    """
    whole = N.mathml(expr)
    if text_width(whole) <= width:
        return [whole]
    if expr.is_Add:
        pieces: list[str] = []
        for k, t in enumerate(_terms(N, expr)):
            sub = mathml_lines(N, -t if t.could_extract_minus_sign() else t, width - 2)
            sign = "<mo>\u2212</mo>" if t.could_extract_minus_sign() else ("" if k == 0 else "<mo>+</mo>")
            pieces += [sign + sub[0], *sub[1:]]
        return _pack(pieces, width)
    if expr.is_Mul:
        sums = [f for f in expr.args if f.is_Add]
        if len(sums) == 1:
            rest = sp.Mul(*[f for f in expr.args if f is not sums[0]])
            head = "<mo>\u2212</mo>" if rest == -1 else "" if rest == 1 else None
            if head is None:
                neg = rest.could_extract_minus_sign()
                head = ("<mo>\u2212</mo>" if neg else "") + N.mathml(-rest if neg else rest)
            inner = mathml_lines(N, sums[0], width - 2)
            inner[0] = f"{head}<mo>(</mo>{inner[0]}"
            inner[-1] += "<mo>)</mo>"
            return inner
    return [whole]


def _entry_mathml(N: Notation, expr: sp.Expr, width: float) -> str:
    lines = mathml_lines(N, expr, width)
    if len(lines) == 1:
        return lines[0]
    indent = '<mspace width="1em"/>'
    rows = "".join(
        f"<mtr><mtd>{line if k == 0 else indent + line}</mtd></mtr>" for k, line in enumerate(lines)
    )
    return f'<mtable columnalign="left" rowspacing="0.1em">{rows}</mtable>'


def _larger_than(expr: sp.Expr, nodes: int) -> bool:
    """True if the expression tree has more than ``nodes`` nodes (stops counting there)."""
    for k, _ in enumerate(sp.preorder_traversal(expr)):
        if k >= nodes:
            return True
    return False


def too_long(expr: sp.Expr) -> bool:
    """True for an entry too long to typeset: more than :data:`MAX_PRINT_TERMS` terms, or a tree of
    more than 20× as many nodes."""
    return len(sp.Add.make_args(expr)) > MAX_PRINT_TERMS or _larger_than(expr, 20 * MAX_PRINT_TERMS)


def _entries(
    M: sp.Matrix, deadline: Deadline | None, show: Callable[[sp.Expr], str]
) -> tuple[list[list[str | None]], list[tuple[int, int]]]:
    rows, skipped = [], []
    for i in range(M.rows):
        row: list[str | None] = []
        for j in range(M.cols):
            e = M[i, j]
            late = deadline is not None and deadline.expired()
            if too_long(e) or (late and _larger_than(e, LATE_NODES)):
                skipped.append((i, j))
                row.append(None)
            else:
                row.append(show(e))
        rows.append(row)
    return rows, skipped


def latex_matrix(
    N: Notation, M: sp.Matrix, deadline: Deadline | None = None
) -> tuple[str, list[tuple[int, int]]]:
    """``\\begin{bmatrix}…\\end{bmatrix}`` of ``M`` and the (i, j) shown as ∗ (not typeset)."""
    rows, skipped = _entries(M, deadline, N.latex)
    body = "\\\\".join(" & ".join("\\ast" if e is None else e for e in row) for row in rows)
    return f"\\begin{{bmatrix}}{body}\\end{{bmatrix}}", skipped


def mathml_matrix(
    N: Notation, M: sp.Matrix, deadline: Deadline | None = None, width: float | None = MATHML_WIDTH
) -> tuple[str, list[tuple[int, int]]]:
    """``[ mtable ]`` of ``M`` (long entries wrapped when ``width`` is set) and the (i, j) shown as ∗."""
    show = N.mathml if width is None else (lambda e: _entry_mathml(N, e, width))
    rows, skipped = _entries(M, deadline, show)
    body = "".join(
        "<mtr>" + "".join(f"<mtd>{'<mo>∗</mo>' if e is None else e}</mtd>" for e in row) + "</mtr>"
        for row in rows
    )
    return f"<mrow><mo>[</mo><mtable>{body}</mtable><mo>]</mo></mrow>", skipped
