"""What a controller needs of a robot, as straight-line programs for the code printers: the pose, J, J̇
and (optionally) ∂J/∂q.

* ``T`` = T_base_tool(q) (4×4), as :func:`.derive` simplified it;
* ``J`` (rows × n), the geometric Jacobian in the requested frame's axes;
* ``Jdot`` = dJ/dt = Σₖ (∂J/∂qₖ) q̇ₖ, in the joint symbols and the rate symbols ``qd``: in the base frame
  the J̇ of :func:`kinematics.jacobian_dot` (the acceleration map a = J q̈ + J̇ q̇); in the tool frame the
  derivative of the tool-axes J (the tool's axes turn with it);
* ``dJdq`` (when asked): ∂J/∂qₖ for each joint k.

Each is a :class:`Block`: assignments ``x = expr`` (common subexpressions, ``sympy.cse``) and the output
matrices in their terms. J̇ and ∂J/∂q are differentiated *through J's program* (forward mode: each
assignment gets its rate ``ẋ = Σ ∂expr/∂s · ṡ``), so their code grows like J's instead of like the
derivative of J's expanded entries (for an unsnapped xArm7, differentiating the entries and sharing
subexpressions took 29 s; forward mode through the shared program takes about one).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp

from ..model import SymbolicModel

__all__ = ["Block", "ControllerKinematics", "block", "controller_kinematics", "rate_symbols"]


@dataclass(frozen=True, eq=False)
class Block:
    """A straight-line program: ``reps`` (symbol, expression) in order, then ``outputs`` in their terms."""

    reps: tuple[tuple[sp.Symbol, Any], ...]
    outputs: tuple[Any, ...]

    def renamed(self, names: dict[Any, Any]) -> Block:
        """The same program with symbols replaced (``names``: symbol → symbol)."""
        return Block(
            tuple((s, e.xreplace(names)) for s, e in self.reps),
            tuple(M.xreplace(names) for M in self.outputs),
        )

    def pruned(self) -> Block:
        """The program without the assignments no output needs (their code would be dead)."""
        needed: set[Any] = set().union(*(M.free_symbols for M in self.outputs))
        kept = []
        for s, e in reversed(self.reps):
            if s in needed:
                kept.append((s, e))
                needed |= e.free_symbols
        return Block(tuple(reversed(kept)), self.outputs)

    def free_symbols(self) -> set[Any]:
        """The inputs of the program (symbols used but not assigned)."""
        used: set[Any] = set().union(
            *(e.free_symbols for _, e in self.reps), *(M.free_symbols for M in self.outputs)
        )
        return used - {s for s, _ in self.reps}


@dataclass(frozen=True, eq=False)
class ControllerKinematics:
    """The programs the generated code runs (see the module's docstring)."""

    T: Block
    J: Block
    Jdot: Block
    qd: tuple[sp.Symbol, ...]
    dJdq: Block | None = None

    @property
    def shape(self) -> tuple[int, int]:
        """J's (rows, n)."""
        rows, n = self.J.outputs[0].shape
        return rows, n


def rate_symbols(model: SymbolicModel) -> tuple[sp.Symbol, ...]:
    """The joint-rate symbols ``qd1 … qdn`` of ``model``."""
    return tuple(sp.Symbol(f"qd{k + 1}", real=True) for k in range(model.dof))


def _fresh(taken: set[Any]) -> Iterator[sp.Symbol]:
    return iter(sp.numbered_symbols("x", exclude=taken))


def block(matrices: Sequence[Any], share: bool = True) -> Block:
    """``matrices`` as a program: their common subexpressions assigned once (none if not ``share``)."""
    if not share:
        return Block((), tuple(matrices))
    used: set[Any] = set().union(*(M.free_symbols for M in matrices))
    reps, reduced = sp.cse(list(matrices), symbols=_fresh(used), optimizations="basic")
    return Block(tuple(reps), tuple(reduced))


def _rate(expr: Any, rates: dict[Any, Any]) -> Any:
    """d(expr)/dt = Σ ∂expr/∂s · ṡ over the symbols s that have a rate, in one pass over ``expr``: the
    derivative by ε of expr(s + ε ṡ) at ε = 0 (one ``diff`` per symbol would walk a long sum once per
    symbol)."""
    moving = expr.free_symbols & rates.keys()
    if not moving:
        return sp.Integer(0)
    if len(moving) == 1:
        s = moving.pop()
        return sp.diff(expr, s) * rates[s]
    eps = sp.Dummy("eps")
    return sp.diff(expr.xreplace({s: s + eps * rates[s] for s in moving}), eps).xreplace({eps: 0})


def _forward(program: Block, seeds: dict[Any, Any], fresh: Iterator[sp.Symbol]) -> tuple[list[Any], Any]:
    """(new assignments, rate of the first output) of ``program`` given the inputs' rates ``seeds``."""
    rates = dict(seeds)
    known = {e: s for s, e in program.reps}  # d cos(q1)/dt = -sin(q1) q̇1 reuses the x = sin(q1) of J
    new: list[tuple[Any, Any]] = []
    for s, e in program.reps:
        r = _rate(e, rates).xreplace(known)
        if r != 0:
            if r.is_Atom:
                rates[s] = r
            else:
                name = next(fresh)
                new.append((name, r))
                rates[s] = name
    M = program.outputs[0]
    return new, M.applyfunc(lambda e: _rate(e, rates).xreplace(known))


def controller_kinematics(
    T: Any, J: Any, model: SymbolicModel, dJdq: bool = False, share: bool = True
) -> ControllerKinematics:
    """The programs of T, J, J̇ (and ∂J/∂q if ``dJdq``) from a derivation's T and J in ``model``'s symbols.

    ``share``: compute common subexpressions (slow for huge unsimplified entries)."""
    qd = rate_symbols(model)
    Jb = block([J], share)
    taken = Jb.free_symbols() | {s for s, _ in Jb.reps} | set(qd)
    fresh = _fresh(taken)
    new, Jd = _forward(Jb, dict(zip(model.q, qd, strict=True)), fresh)
    Jdot = Block(Jb.reps + tuple(new), (Jd,)).pruned()
    partial = None
    if dJdq:
        reps, outs = list(Jb.reps), []
        for qk in model.q:
            new, D = _forward(Jb, {qk: sp.Integer(1)}, fresh)
            reps += new
            outs.append(D)
        partial = Block(tuple(reps), tuple(outs)).pruned()
    return ControllerKinematics(block([T], share), Jb, Jdot, qd, partial)
