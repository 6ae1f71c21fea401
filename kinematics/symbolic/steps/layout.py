"""Matrices of a :class:`.step.Step` typeset never wider than a given width.

Entries are broken over lines the way :func:`.layout.mathml_lines` breaks them (after a term of
a sum, or inside the parentheses of a product with one long sum), in MathML and, with the same
breaks, in LaTeX (``\\begin{aligned}`` inside the matrix cell, which amsmath and KaTeX both
typeset). An entry that still does not fit (an unsimplified product left at the time limit) or
that is too long to typeset at all is shown as ∗ and counted, so the caller can say so.
"""

from __future__ import annotations

import sympy as sp

from ..typeset.layout import mathml_lines, text_width, too_long
from ..typeset.printing import Notation

__all__ = ["latex_lines", "mathml_cells", "latex_cells", "OMITTED"]

OMITTED = "entries too long to typeset at this width are shown as ∗ (the exports hold them in full)"


def latex_lines(N: Notation, expr: sp.Expr, width: float) -> list[str]:
    """``expr`` as LaTeX lines, broken where :func:`.layout.mathml_lines` breaks the MathML (widths
    measured on the MathML); a line may still be wider than ``width`` when it cannot be broken."""
    if text_width(N.mathml(expr)) <= width:
        return [N.latex(expr)]
    if expr.is_Add:
        lines: list[str] = []
        used = 0.0
        for k, t in enumerate(N.ordered_terms(expr)):
            neg = t.could_extract_minus_sign()
            body = -t if neg else t
            sub = latex_lines(N, body, width - 2)
            sign = "- " if neg else ("" if k == 0 else "+ ")
            w = text_width(N.mathml(body)) + 2
            if lines and used + w <= width and len(sub) == 1:
                lines[-1] += f" {sign}{sub[0]}"
                used += w
            else:
                lines.append(sign + sub[0])
                lines += sub[1:]
                used = w if len(sub) == 1 else width
        return lines
    if expr.is_Mul:
        sums = [f for f in expr.args if f.is_Add]
        if len(sums) == 1:
            rest = sp.Mul(*[f for f in expr.args if f is not sums[0]])
            neg = rest.could_extract_minus_sign()
            head = ("- " if neg else "") + ("" if rest in (1, -1) else N.latex(-rest if neg else rest) + " ")
            inner = latex_lines(N, sums[0], width - 2)
            inner[0] = f"{head}\\left({inner[0]}\\right."
            inner[1:] = [f"\\left.{line}\\right." for line in inner[1:]]
            inner[-1] = inner[-1][: -len("\\right.")] + "\\right)"
            return inner
    return [N.latex(expr)]


def product_lines(N: Notation, expr: sp.Expr, width: float, latex: bool) -> list[str] | None:
    """A product of several factors broken between its factors, and inside a factor that is a long
    sum (``None`` if ``expr`` is not a product)."""
    if not expr.is_Mul or len(expr.args) < 2:
        return None
    coeff, factors = expr.as_coeff_mul()
    pieces: list[tuple[str, float, bool]] = []  # (text, width, may join the previous line)
    for f in sorted(factors, key=N.factor_key):
        w = text_width(N.mathml(f)) + 2
        if f.is_Add and w > width:
            sub = latex_lines(N, f, width - 2) if latex else mathml_lines(N, f, width - 2)
            if latex:
                sub = [f"\\left.{x}\\right." for x in sub]
                sub[0] = "\\left(" + sub[0][len("\\left.") :]
                sub[-1] = sub[-1][: -len("\\right.")] + "\\right)"
            else:
                sub[0], sub[-1] = "<mo>(</mo>" + sub[0], sub[-1] + "<mo>)</mo>"
            pieces += [(x, width, k == 0) for k, x in enumerate(sub)]
        elif latex:
            pieces.append((f"\\left({N.latex(f)}\\right)" if f.is_Add else N.latex(f), w, True))
        else:
            pieces.append((f"<mo>(</mo>{N.mathml(f)}<mo>)</mo>" if f.is_Add else N.mathml(f), w, True))
    if coeff != 1:
        sign = ("- " if latex else "<mo>−</mo>") if coeff < 0 else ""
        rest = abs(coeff)
        shown = "" if rest == 1 else (N.latex(rest) + " " if latex else N.mathml(rest))
        text, w, join = pieces[0]
        pieces[0] = (sign + shown + text, w + text_width(N.mathml(rest)), join)
    lines: list[str] = []
    used = 0.0
    for text, w, join in pieces:
        if lines and join and used + w <= width:
            lines[-1] += (" " if latex else "<mo>&#x2062;</mo>") + text
            used += w
        else:
            lines.append(text)
            used = w
    return lines


def _mml_lines(N: Notation, e: sp.Expr, wrap: float) -> list[str]:
    lines = mathml_lines(N, e, wrap)
    if max(map(text_width, lines)) > wrap:
        alt = product_lines(N, e, wrap, False)
        if alt is not None and max(map(text_width, alt)) < max(map(text_width, lines)):
            return alt
    return lines


def _fits(lines_width: float, budget: float | None) -> bool:
    return budget is None or lines_width <= budget


def mathml_cells(N: Notation, M: sp.Matrix, wrap: float, budget: float | None) -> tuple[list[list[str]], int]:
    """MathML of every entry (wrapped at ``wrap`` characters) and how many were shown as ∗
    (too long, or wider than ``budget`` characters even when wrapped)."""
    out, omitted = [], 0
    for i in range(M.rows):
        row = []
        for j in range(M.cols):
            e = M[i, j]
            lines = None if too_long(e) else _mml_lines(N, e, wrap)
            if lines is None or not _fits(max(map(text_width, lines)), budget):
                row.append("<mo>∗</mo>")
                omitted += 1
            elif len(lines) == 1:
                row.append(lines[0])
            else:
                indent = '<mspace width="1em"/>'
                rows = "".join(
                    f"<mtr><mtd>{x if k == 0 else indent + x}</mtd></mtr>" for k, x in enumerate(lines)
                )
                row.append(f'<mtable columnalign="left" rowspacing="0.1em">{rows}</mtable>')
        out.append(row)
    return out, omitted


def latex_cells(
    N: Notation, M: sp.Matrix, wrap: float | None, budget: float | None
) -> tuple[list[list[str]], int]:
    """LaTeX of every entry (broken into ``aligned`` lines at ``wrap`` characters, if given) and how
    many were shown as ``\\ast``."""
    out, omitted = [], 0
    for i in range(M.rows):
        row = []
        for j in range(M.cols):
            e = M[i, j]
            if too_long(e):
                row.append("\\ast")
                omitted += 1
                continue
            if wrap is None:
                row.append(N.latex(e))
                continue
            lines = latex_lines(N, e, wrap)
            mml = _mml_lines(N, e, wrap)
            widest = max(text_width(x) for x in mml)
            if mml != mathml_lines(N, e, wrap):  # broken between the factors of a product
                lines = product_lines(N, e, wrap, True) or lines
            if not _fits(widest, budget):
                row.append("\\ast")
                omitted += 1
            elif len(lines) == 1:
                row.append(lines[0])
            else:
                row.append("\\begin{aligned}&" + "\\\\&\\quad ".join(lines) + "\\end{aligned}")
        out.append(row)
    return out, omitted
