"""SymPy's ``fu.TR10i`` (sums of products → functions of sums) with an index of the pairs that can combine.

``TR10i`` tries every pair of terms of a sum with ``fu.trig_split`` (about a millisecond per pair,
thousands of pairs for a 7-joint arm's entry): on a Panda it was more than half of the cold
symbolic Jacobian. :func:`tr10i` is the same algorithm, in the same order, taking the same first
pair that works, so its result is identical; it only skips the pairs that ``trig_split`` would
reject anyway. Two terms ``a``, ``b`` combine only if, after their common factors are divided
out, each keeps one sine/cosine of the same angle (times numbers and square roots), or two of
the same two angles (``trig_split``): so both share the key "the term without one (two) of its
sines/cosines, numbers and square roots, and the angle(s) of what was left out". Every term is
indexed by all those keys; a pair is tried only if the two terms share one.
"""

from __future__ import annotations

import importlib
from collections import Counter, defaultdict
from itertools import combinations
from typing import Any

import sympy as sp
from sympy.core.sorting import ordered
from sympy.core.traversal import bottom_up

_fu: Any = importlib.import_module("sympy.simplify.fu")  # `sympy.simplify.fu` is shadowed by a function

__all__ = ["tr10i", "pair_keys"]


def pair_keys(term: sp.Expr) -> frozenset[Any] | None:
    """Keys of ``term``: two terms can combine in TR10i only if they share one (None: any term)."""
    rest: Counter[Any] = Counter()
    trig: list[sp.Expr] = []
    for f in sp.Mul.make_args(term):
        base, exp = f.as_base_exp()
        if isinstance(base, (sp.sin, sp.cos)):
            if not (exp.is_Integer and exp > 0):
                return None
            trig += [base] * int(exp)
        elif not f.free_symbols or exp == sp.S.Half:
            continue  # numbers and square roots may stay on either side
        elif exp.is_Integer:
            rest[(base, exp)] += 1
        else:
            return None
    fixed = frozenset(rest.items())
    units = Counter(trig)
    keys = set()
    for size in (1, 2):
        for drop in combinations(range(len(trig)), size):
            left = units - Counter(trig[k] for k in drop)
            angles = frozenset(trig[k].args[0] for k in drop)
            keys.add((fixed, frozenset(left.items()), size, angles))
    return frozenset(keys)


def _can_pair(a: frozenset[Any] | None, b: frozenset[Any] | None) -> bool:
    return a is None or b is None or not a.isdisjoint(b)


def tr10i(rv: sp.Expr) -> sp.Expr:
    """``sympy.simplify.fu.TR10i(rv)``, the same result, without trying pairs that cannot combine."""
    trig_split, cos, sin = _fu.trig_split, sp.cos, sp.sin
    S, Add = sp.S, sp.Add

    def f(rv: sp.Expr) -> sp.Expr:
        if not rv.is_Add:
            return rv

        def do(rv: sp.Expr, first: bool = True) -> sp.Expr:
            if not rv.is_Add:
                return rv
            args: list[Any] = list(ordered(rv.args))
            if len(args) != 2:
                keys = [pair_keys(a) for a in args]
                hit = False
                for i in range(len(args)):
                    ai = args[i]
                    if ai is None:
                        continue
                    for j in range(i + 1, len(args)):
                        aj = args[j]
                        if aj is None or not _can_pair(keys[i], keys[j]):
                            continue
                        was = ai + aj
                        new = do(was)
                        if new != was:
                            args[i] = new
                            args[j] = None
                            hit = True
                            break
                if hit:
                    rv = Add(*[_f for _f in args if _f])
                    if rv.is_Add:
                        rv = do(rv)
                return rv

            split = trig_split(*args, two=True)
            if not split:
                return rv
            gcd, n1, n2, a, b, same = split
            if same:
                gcd = n1 * gcd
                if n1 == n2:
                    return gcd * cos(a - b)
                return gcd * cos(a + b)
            gcd = n1 * gcd
            if n1 == n2:
                return gcd * sin(a + b)
            return gcd * sin(b - a)

        rv = _fu.process_common_addends(rv, do, lambda x: tuple(ordered(x.free_symbols)))

        while rv.is_Add:
            byrad: defaultdict[Any, list[Any]] = defaultdict(list)
            for a in rv.args:
                hit = 0
                if a.is_Mul:
                    for ai in a.args:
                        if ai.is_Pow and ai.exp is S.Half and ai.base.is_Integer:
                            byrad[ai].append(a)
                            hit = 1
                            break
                if not hit:
                    byrad[S.One].append(a)
            args = []
            for a in byrad:
                for b in [_fu._ROOT3() * a, _fu._invROOT3()]:
                    if b in byrad:
                        for i in range(len(byrad[a])):
                            if byrad[a][i] is None:
                                continue
                            for j in range(len(byrad[b])):
                                if byrad[b][j] is None:
                                    continue
                                was = Add(byrad[a][i] + byrad[b][j])
                                new = do(was)
                                if new != was:
                                    args.append(new)
                                    byrad[a][i] = None
                                    byrad[b][j] = None
                                    break
            if args:
                rv = Add(*(args + [Add(*[_f for _f in v if _f]) for v in byrad.values()]))
            else:
                rv = do(rv)
                break
        return rv

    return bottom_up(rv, f)
