"""Targeted trigonometric simplification with a deadline.

``sympy.simplify`` on a 7-joint Jacobian can run for minutes and cannot be
interrupted. Entries of a Jacobian are polynomials in cᵢ = cos qᵢ and
sᵢ = sin qᵢ (and in prismatic joint values and link parameters), so a few
cheap, predictable steps do what a person does by hand:

1. :func:`normal_form`: expand into cᵢ, sᵢ and reduce modulo sᵢ² + cᵢ² − 1
   (a Gröbner basis, so the remainder is canonical: an expression is
   identically zero exactly when its normal form is 0, see :func:`is_zero`),
   on SymPy's sparse polynomials over ℚ rather than on expressions;
2. :func:`collapse`: sums of angles collapsed, c₂c₃ − s₂s₃ → c₂₃ (SymPy's
   ``fu`` rule TR10i, with an index of the pairs that can combine (:mod:`.tr10i`),
   keeping only collapses into sums of joint angles);
3. :func:`nest`: common factors pulled out, greedily, outermost joints first.

:mod:`.simplify` runs them entry by entry within a :class:`Deadline`.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Callable, Sequence
from typing import Any

import sympy as sp
from sympy.polys.domains import QQ
from sympy.polys.orderings import lex
from sympy.polys.rings import PolyRing

from .tr10i import tr10i

__all__ = [
    "Deadline",
    "normal_form",
    "normal_form_sympy",
    "is_zero",
    "collapse",
    "nest",
    "AngleShift",
    "MAX_TERMS",
]

MAX_TERMS = 600
"""Entries with more terms than this in normal form are not nested (too slow to be worth it)."""

Progress = Callable[[str], None]


clock: Callable[[], float] = time.perf_counter
"""The time source of every :class:`Deadline` [s]: the wall clock (a user waits for the result). The
test suite sets ``time.process_time``, the work done, so that a machine busy with other jobs cannot
cut a test's symbolic work short (tests/conftest.py)."""


class Deadline:
    """A point in time after which optional work is skipped.

    Args:
        seconds: Time budget [s] from now (on :data:`clock`); ``None`` for no limit.
    """

    def __init__(self, seconds: float | None) -> None:
        self.seconds = seconds
        self.start = clock()

    def expired(self) -> bool:
        """True once the budget is spent."""
        return self.seconds is not None and clock() - self.start > self.seconds

    def remaining(self) -> float:
        """Seconds left [s] (``inf`` without a limit, 0 once expired)."""
        if self.seconds is None:
            return float("inf")
        return max(0.0, self.seconds - (clock() - self.start))

    def allows(self, seconds: float) -> bool:
        """True if a step expected to take ``seconds`` [s] fits in what is left."""
        return self.remaining() >= seconds

    def elapsed(self) -> float:
        """Seconds since the deadline was created."""
        return clock() - self.start


def _single_angle(expr: sp.Expr, q: Sequence[sp.Symbol]) -> bool:
    qs = set(q)
    return all(f.args[0] in qs or not (f.args[0].free_symbols & qs) for f in expr.atoms(sp.sin, sp.cos))


def trig_angles(expr: sp.Expr, q: Sequence[sp.Symbol]) -> list[sp.Expr]:
    """The angles whose sine and cosine act as polynomial variables: the joints ``q`` and any
    angle free of q (a link twist α = 3/10 or a symbol α₁), whose sin and cos obey s² + c² = 1 too."""
    qs = set(q)
    const = {f.args[0] for f in expr.atoms(sp.sin, sp.cos) if not (f.args[0].free_symbols & qs)}
    return [*q, *sorted(const, key=sp.default_sort_key)]


def normal_form(expr: sp.Expr, q: Sequence[sp.Symbol]) -> sp.Expr:
    """Expanded form of ``expr`` in sin qᵢ, cos qᵢ with no sin² qᵢ (replaced by 1 − cos² qᵢ).

    Canonical: two expressions are equal for all q exactly when their normal
    forms are identical. For a Jacobian entry it is the expansion of degree at
    most one in each (cᵢ, sᵢ) pair. Sines and cosines of constant angles (a
    link twist that is not a multiple of π/2) are reduced the same way.

    Computed with SymPy's sparse polynomials over ℚ (sᵢ, cᵢ, the other symbols and the square
    roots of integers as generators, reduced modulo sᵢ² + cᵢ² − 1 and r² − n), never expanding
    the expression itself: the same result as :func:`normal_form_sympy` (tested), 4–5× faster.
    Expressions that are not polynomials in those generators take :func:`normal_form_sympy`.

    Args:
        expr: A polynomial in sines and cosines of sums of joint angles.
        q: The joint symbols.
    """
    if not _single_angle(expr, q):
        expr = sp.expand_trig(expr)
    angles = trig_angles(expr, q)
    roots = sorted(
        {p for p in expr.atoms(sp.Pow) if p.exp is sp.S.Half and p.base.is_Integer and p.base > 1},
        key=sp.default_sort_key,
    )
    others = sorted(expr.free_symbols, key=sp.default_sort_key)
    # lex with every sᵢ first: sᵢ² leads sᵢ² + cᵢ² − 1
    atoms = [*(sp.sin(a) for a in angles), *(sp.cos(a) for a in angles), *others, *roots]
    ring = PolyRing([sp.Dummy() for _ in atoms], QQ, lex)
    try:
        p = _ring_element(expr, dict(zip(atoms, ring.gens, strict=True)), ring)
    except _NotPolynomial:
        return normal_form_sympy(expr, q)
    n, k = len(angles), len(atoms) - len(roots)
    g = ring.gens
    divisors = [g[i] ** 2 + g[n + i] ** 2 - 1 for i in range(n)]
    divisors += [g[k + i] ** 2 - int(root.base) for i, root in enumerate(roots)]
    if divisors:
        p = p.rem(divisors)
    return sp.expand(p.as_expr(*atoms))


class _NotPolynomial(Exception):
    pass


def _ring_element(expr: sp.Expr, gens: dict[sp.Expr, Any], ring: Any) -> Any:
    """``expr`` as an element of ``ring``, ``gens`` the expressions that are its generators (shared
    subexpressions built once); raises :class:`_NotPolynomial` for anything but sums, products,
    powers ≥ 2, rationals and generators."""
    memo: dict[sp.Expr, Any] = {}

    def build(e: sp.Expr) -> Any:
        out = memo.get(e)
        if out is not None:
            return out
        if e in gens:
            out = gens[e]
        elif e.is_Add:
            out = ring.zero
            for t in e.args:
                out = out + build(t)
        elif e.is_Mul:
            out = ring.one
            for t in e.args:
                out = out * build(t)
        elif e.is_Pow and e.exp.is_Integer and e.exp > 1:
            out = build(e.base) ** int(e.exp)
        elif e.is_Rational:
            out = ring(QQ.convert(e))
        else:
            raise _NotPolynomial(e)
        memo[e] = out
        return out

    return build(expr)


def normal_form_sympy(expr: sp.Expr, q: Sequence[sp.Symbol]) -> sp.Expr:
    """:func:`normal_form` with SymPy's ``expand`` and ``reduced`` on expressions (the reference)."""
    if not _single_angle(expr, q):
        expr = sp.expand_trig(expr)
    expr = sp.expand(expr)
    fwd, pairs = {}, []
    for a in trig_angles(expr, q):
        s, c = sp.Dummy(f"s{a}"), sp.Dummy(f"c{a}")
        fwd[sp.sin(a)], fwd[sp.cos(a)] = s, c
        pairs.append((s, c))
    poly = expr.xreplace(fwd)
    pairs = [(s, c) for s, c in pairs if poly.has(s)]
    if pairs:
        gens = [s for s, _ in pairs] + [c for _, c in pairs]
        _, poly = sp.reduced(poly, [s**2 + c**2 - 1 for s, c in pairs], *gens, order="lex")
    back = {v: k for k, v in fwd.items()}
    return sp.expand(poly.xreplace(back))


def is_zero(expr: sp.Expr, q: Sequence[sp.Symbol]) -> bool:
    """True if ``expr`` vanishes for every q (exact test via :func:`normal_form`)."""
    return bool(normal_form(expr, q) == 0)


def _is_joint_sum(arg: sp.Expr, q: Sequence[sp.Symbol]) -> bool:
    """True for ±qᵢ ± qⱼ ± … (integer coefficients, no constant): the angles a person writes."""
    coeffs = sp.Add.make_args(arg)
    qs = set(q)
    return all(
        (t in qs) or (t.is_Mul and len(t.args) == 2 and t.args[0].is_Integer and t.args[1] in qs)
        for t in coeffs
    )


def collapse(expr: sp.Expr, q: Sequence[sp.Symbol]) -> sp.Expr:
    """Collapse sums of products into functions of angle sums: c₂c₃ − s₂s₃ → cos(q₂ + q₃).

    Collapses that would introduce a phase (s₁ + c₁ → √2 sin(q₁ + π/4)) are undone.
    """
    out = tr10i(expr)
    bad = {
        f: sp.expand_trig(f)
        for f in out.atoms(sp.sin, sp.cos)
        if f.args[0].free_symbols
        and not _is_joint_sum(f.args[0], q)
        and not (f.args[0].free_symbols - set(q))
        and f not in expr.atoms(sp.sin, sp.cos)
    }
    if bad:
        out = sp.expand(out.xreplace(bad))
    return out


def _factor_key(f: sp.Expr, order: dict[sp.Symbol, int]) -> tuple[Any, ...]:
    syms = [order.get(s, len(order)) for s in f.free_symbols]
    trig = isinstance(f, (sp.sin, sp.cos))
    return (trig, -min(syms, default=len(order)), isinstance(f, sp.cos))


def _factors(term: sp.Expr) -> set[sp.Expr]:
    out = set()
    for f in sp.Mul.make_args(term):
        base, exp = f.as_base_exp()
        if not base.is_Number and exp.is_Integer and exp > 0:
            out.add(base)
    return out


def nest(expr: sp.Expr, q: Sequence[sp.Symbol]) -> sp.Expr:
    """Pull out common factors greedily: a·c₁·x + b·c₁·y → c₁ (a x + b y), recursively.

    The factor shared by most terms goes first (ties: trigonometric factors of
    the earliest joint), which gives the nested form of a hand derivation,
    e.g. c₁ (a₂ c₂ + a₃ c₂₃) rather than a₂ c₁ c₂ + a₃ c₁ c₂₃.
    """
    terms = sp.Add.make_args(expr)
    if len(terms) < 2:
        return expr
    counts: Counter[Any] = Counter()
    for t in terms:
        counts.update(_factors(t))
    if not counts:
        return expr
    order = {s: i for i, s in enumerate(q)}
    best = max(counts, key=lambda f: (counts[f], *_factor_key(f, order)))
    if counts[best] < 2:
        return expr
    inner = [t / best for t in terms if best in _factors(t)]
    rest = [t for t in terms if best not in _factors(t)]
    inside = nest(sp.Add(*inner), q)
    negative = sum(t.could_extract_minus_sign() for t in sp.Add.make_args(inside))
    if inside.is_Add and 2 * negative > len(inside.args):
        nested = -best * (-inside)  # -c1 (a s2 + b s23) rather than c1 (-a s2 - b s23)
    else:
        nested = best * inside
    return sp.Add(nested, nest(sp.Add(*rest), q)) if rest else nested


class AngleShift:
    """Work in θᵢ = qᵢ + offsetᵢ for joints whose DH offset is not a multiple of π/2.

    sin(q₂ + 1/5) expanded is sin q₂ cos(1/5) + cos q₂ sin(1/5): with many such
    offsets the normal form explodes. In θᵢ the offsets disappear; the result is
    written back in qᵢ (sin(q₂ + 1/5) stays whole).

    Args:
        q: Joint symbols.
        offsets: Joint symbol → its constant offset (only the joints to shift).
    """

    def __init__(self, q: Sequence[sp.Symbol], offsets: dict[sp.Symbol, sp.Expr] | None = None) -> None:
        offsets = offsets or {}
        t = {qi: sp.Dummy(f"theta_{qi}", real=True) for qi in offsets}
        self.fwd = {qi: t[qi] - off for qi, off in offsets.items()}
        self.back = {t[qi]: qi + off for qi, off in offsets.items()}
        self.vars = tuple(t.get(qi, qi) for qi in q)

    def apply(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` in the shifted angles."""
        return expr.xreplace(self.fwd) if self.fwd else expr

    def undo(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` back in the joint symbols."""
        return expr.xreplace(self.back) if self.back else expr
