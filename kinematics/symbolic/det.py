"""Polynomial machinery for determinants of Jacobians: shortest frame, exact det, factoring on the circle.

Entries of J are polynomials in cᵢ = cos qᵢ, sᵢ = sin qᵢ (and in prismatic
joint values and DH parameters). Here they are turned into genuine polynomials
(the cᵢ, sᵢ replaced by symbols), whose determinant SymPy's ``DomainMatrix``
computes exactly and fast, and whose factors are reduced modulo
sᵢ² + cᵢ² − 1 on the way back to trigonometric form.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any, cast

import sympy as sp
from sympy.core import random as _srandom
from sympy.polys.matrices import DomainMatrix

from .chain import relative_frames
from .derivations import whitney_columns
from .model import SymbolicModel
from .trig import Deadline, normal_form, trig_angles

__all__ = ["shortest_rows", "TrigPolynomials", "Factored", "MAX_FACTOR_TERMS"]

MAX_FACTOR_TERMS = 400
"""Polynomials with more terms than this are not factored (too slow to be worth it)."""

Factored = tuple[sp.Expr, tuple[tuple[sp.Expr, int], ...]]
"""(constant, ((factor, multiplicity), …)): the factors depend on q, the constant does not."""


def _size(M: sp.Matrix) -> int:
    return sum(len(sp.Add.make_args(e)) for e in M)


def shortest_rows(model: SymbolicModel, rows: Sequence[int], deadline: Deadline | None = None) -> sp.Matrix:
    """The rows ``rows`` of J, re-expressed where they are shortest, in normal form.

    All six rows: any frame of the chain and any joint origin as the velocity
    reference point (det J and det(J Jᵀ) do not change). Three linear or three
    angular rows: any frame (a rotation of the block). Other row sets: base
    axes only. Frames near the middle of the chain are tried.
    """
    rows = tuple(rows)
    m = len(model.kinds)
    whole_block = rows in ((0, 1, 2), (3, 4, 5), (0, 1, 2, 3, 4, 5))
    ks = sorted({k for k in (m // 2 - 1, m // 2, (m + 1) // 2) if 0 <= k <= m}) if whole_block else [0]
    if whole_block and m <= 3:
        ks = list(range(m + 1))
    best: tuple[int, sp.Matrix] | None = None
    for k in ks:
        if best is not None and deadline is not None and deadline.expired():
            break
        F = relative_frames(model, k)
        points = [F.tool[:3, 3]]
        if len(rows) == 6:
            points += [W[:3, 3] for W in F.joint]
        for P in points:
            J = whitney_columns(model, F, P)[list(rows), :].applyfunc(sp.expand)
            if best is None or _size(J) < best[0]:
                best = (_size(J), J)
            if deadline is not None and deadline.expired():
                break
    assert best is not None
    return best[1].applyfunc(lambda e: normal_form(e, model.q))


class TrigPolynomials:
    """Converts between trigonometric expressions in ``q`` and polynomials in symbols cᵢ, sᵢ."""

    def __init__(self, q: Sequence[sp.Symbol]) -> None:
        self.q = tuple(q)
        self.fwd: dict[sp.Expr, sp.Dummy] = {}
        for qi in self.q:
            self.fwd[sp.sin(qi)] = sp.Dummy(f"s{qi}")
            self.fwd[sp.cos(qi)] = sp.Dummy(f"c{qi}")
        self.back = {v: k for k, v in self.fwd.items()}

    def poly(self, expr: sp.Expr) -> sp.Expr:
        """Polynomial form of a normal-form trigonometric expression (constant angles get symbols too)."""
        expr = sp.expand(expr)
        for a in trig_angles(expr, self.q)[len(self.q) :]:
            if sp.sin(a) not in self.fwd:
                self.fwd[sp.sin(a)], self.fwd[sp.cos(a)] = sp.Dummy(f"s{a}"), sp.Dummy(f"c{a}")
                self.back.update({self.fwd[sp.sin(a)]: sp.sin(a), self.fwd[sp.cos(a)]: sp.cos(a)})
        return expr.xreplace(self.fwd)

    def trig(self, expr: sp.Expr) -> sp.Expr:
        """Trigonometric form of a polynomial, reduced modulo sᵢ² + cᵢ² − 1."""
        return normal_form(expr.xreplace(self.back), self.q)

    def det(self, M: sp.Matrix) -> sp.Expr:
        """Exact determinant of a square matrix of polynomials (fraction-free elimination)."""
        dM = DomainMatrix.from_Matrix(M)
        return sp.expand(dM.domain.to_sympy(dM.det()))

    def minors(
        self, M: sp.Matrix, deadline: Deadline | None = None
    ) -> list[tuple[tuple[int, ...], sp.Expr]] | None:
        """All maximal minors (Cauchy–Binet terms) of a non-square matrix, or None at the deadline."""
        k = min(M.shape)
        out = []
        wide = M.cols > M.rows
        for idx in itertools.combinations(range(max(M.shape)), k):
            if deadline is not None and deadline.expired():
                return None
            sub = M[:, list(idx)] if wide else M[list(idx), :]
            out.append((idx, self.det(sub)))
        return out

    def factor(self, expr: sp.Expr) -> Factored:
        """Factor a polynomial on the circle: (constant, ((trig factor, multiplicity), …)).

        Each factor over the rationals is reduced modulo sᵢ² + cᵢ² − 1 and factored
        again; q-free pieces go into the constant, and signs are normalised so that
        equal factors are merged. A polynomial with more than :data:`MAX_FACTOR_TERMS`
        terms is returned whole (one factor): multivariate factoring can take minutes.
        """
        if len(sp.Add.make_args(expr)) > MAX_FACTOR_TERMS:
            return sp.Integer(1), ((self.trig(expr), 1),)
        const = sp.Integer(1)
        found: dict[sp.Expr, int] = {}
        coeff, facs = _factor_list(expr)
        const *= coeff
        for f, mult in facs:
            reduced = self.trig(f)
            c2, sub = (
                _factor_list(self.poly(reduced)) if reduced.free_symbols & set(self.q) else (reduced, [])
            )
            const *= c2**mult
            for h, m2 in sub:
                ht = sp.expand(h.xreplace(self.back))
                if not ht.free_symbols & set(self.q):
                    const *= ht ** (m2 * mult)
                    continue
                if ht.could_extract_minus_sign():
                    ht, const = -ht, const * (-1) ** (m2 * mult)
                found[ht] = found.get(ht, 0) + m2 * mult
        return sp.factor(const), tuple(found.items())

    def common_factor(self, polys: Sequence[sp.Expr], deadline: Deadline | None = None) -> sp.Expr:
        """The greatest common divisor of ``polys`` (exact and deterministic; 1 at the deadline)."""
        nonzero = [p for p in polys if p != 0]
        if not nonzero:
            return sp.Integer(0)
        g = nonzero[0]
        for p in nonzero[1:]:
            if g == 1 or (deadline is not None and deadline.expired()):
                return sp.Integer(1)
            g = sp.gcd(g, p)
        return g


def _factor_list(expr: sp.Expr) -> tuple[sp.Expr, list[tuple[sp.Expr, int]]]:
    """``sympy.factor_list`` with SymPy's random generator seeded for the call.

    Wang's multivariate factoring draws random evaluation points; a fixed seed
    makes results and timings reproducible (some draws take minutes). The
    generator's state is restored afterwards.
    """
    state = _srandom.rng.getstate()
    _srandom.seed(20240601)
    try:
        return cast(tuple[Any, list[tuple[Any, int]]], sp.factor_list(expr))
    finally:
        _srandom.rng.setstate(state)
