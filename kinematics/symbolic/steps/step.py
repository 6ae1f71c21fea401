"""One step of a derivation (:class:`Step`) and the symbolic DH table (:class:`DHRow`).

A :class:`Step` is one line of working a teacher writes on the board: a left-hand side
(``{}^{0}T_{2}``, ``z_{1}``, ``J_{2}``), its symbolic value, and a caption in the course's
notation. It prints itself in LaTeX and MathML in the compact notation of :mod:`.printing`
(long matrices split into groups of columns that fit a given width) and evaluates itself at
a configuration (lambdified once, then cached).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import sympy as sp

from ..model import SymbolicModel
from ..singular import SingularSet
from ..typeset.escape import xml_text
from ..typeset.layout import MATHML_WIDTH, mathml_lines, text_width, too_long
from ..typeset.printing import Notation
from ..typeset.render import MATH_STYLE
from .layout import latex_cells, mathml_cells

__all__ = ["Step", "DHRow", "DH_COLUMNS", "step_notation", "PX_PER_CHAR"]

PX_PER_CHAR = 10.0
"""Rough width of one character of typeset MathML [px] at the default font size (16 px)."""

DH_COLUMNS = {
    "standard": ("\\theta_{i}", "d_{i}", "a_{i}", "\\alpha_{i}"),
    "modified": ("\\alpha_{i-1}", "a_{i-1}", "d_{i}", "\\theta_{i}"),
}
"""LaTeX headers of the DH table's four columns per convention, in the order :meth:`DHRow.cells` gives."""


def step_notation(
    model: SymbolicModel, inputs: Sequence[sp.Symbol] = (), names: dict[sp.Symbol, str] | None = None
) -> Notation:
    """A :class:`Notation` for the symbols of ``model`` and the display ``names`` of step inputs."""
    display = {**model.display, **(names or {})}
    robot = model.robot
    return Notation(model.q, display, robot.joint_types, model.params, robot.joint_names)


@dataclass(frozen=True, eq=False)
class Step:
    """One step of a derivation.

    Attributes:
        key: Stable id: ``"A1"``, ``"T0_2"``, ``"whitney.z0"``, ``"whitney.col1"``, ``"diff.col1"``,
            ``"prop.w2"``, ``"prop.v2"``, ``"force.tau1"``, ``"J"``, ``"detJ"`` … (see
            :func:`.steps.derivation_steps`).
        title: Plain-text caption in the course's notation (user names inside are not escaped:
            escape it for the output).
        lhs: LaTeX of the left-hand side (no user text in it).
        expr: The symbolic value (simplified within the time limit).
        joint: 0-based joint this step belongs to; ``None`` for whole-chain steps.
        model: The symbolic model whose symbols ``expr`` uses.
        section: ``"transforms"``, ``"whitney"``, ``"differentiation"``, ``"propagation"``,
            ``"force"`` or ``"result"``.
        inputs: Symbols of ``expr`` other than joints and parameters: the joint rates q̇
            (propagation) or the wrench [f; n] (force), in the order :meth:`numeric` takes them.
        names: LaTeX display names of ``inputs``.
        notes: Plain-text notes (time limit reached, …).
        singular: For ``"detJ"``: the singular sets of the determinant.
    """

    key: str
    title: str
    lhs: str
    expr: sp.Matrix
    joint: int | None
    model: SymbolicModel = field(repr=False)
    section: str = ""
    inputs: tuple[sp.Symbol, ...] = ()
    names: dict[sp.Symbol, str] = field(default_factory=dict, repr=False)
    notes: tuple[str, ...] = ()
    singular: tuple[SingularSet, ...] = ()

    # ------------------------------------------------------------------ printing
    def notation(self) -> Notation:
        """A fresh :class:`Notation` for this step (its legend lists what the step used)."""
        return step_notation(self.model, self.inputs, self.names)

    def _scalar(self) -> bool:
        return bool(self.expr.shape == (1, 1))

    def column_groups(self, width_chars: float) -> list[tuple[int, int]]:
        """[start, stop) column ranges whose wrapped entries fit ``width_chars`` characters together."""
        if self._scalar() or self.expr.cols == 1:
            return [(0, self.expr.cols)]
        N = self.notation()
        width = []
        for j in range(self.expr.cols):
            lines = [
                max(map(text_width, mathml_lines(N, e, MATHML_WIDTH)))
                for e in self.expr[:, j]
                if not too_long(e)
            ]
            width.append(max(lines, default=1.0) + 2.0)
        budget = max(width_chars - text_width(self.lhs) - 8.0, 10.0)
        groups, start, used = [], 0, 0.0
        for j, w in enumerate(width):
            if j > start and used + w > budget:
                groups.append((start, j))
                start, used = j, 0.0
            used += w
        groups.append((start, self.expr.cols))
        return groups

    def _label(self, a: int, b: int, latex: bool) -> str:
        if b - a == self.expr.cols:
            return ""
        cols = f"{a + 1}" if b - a == 1 else f"{a + 1}\u2013{b}"
        word = "column" if b - a == 1 else "columns"
        return f"\\quad\\text{{({word} {cols})}}" if latex else f"<mtext>&#xa0;({word} {cols})</mtext>"

    def latex(self, notation: Notation | None = None) -> str:
        """``lhs = expr`` in LaTeX, compact notation (a 1×1 value printed as a scalar)."""
        return self.latex_blocks(None, notation)[0]

    def latex_blocks(self, width_chars: float | None = None, notation: Notation | None = None) -> list[str]:
        """``lhs = expr`` as one LaTeX formula, or, given a width, one per group of columns that fit
        it, long entries broken into ``aligned`` lines and any still too wide shown as ``\\ast``."""
        N = notation or self.notation()
        wrap = None if width_chars is None else min(MATHML_WIDTH, max(width_chars - 10.0, 16.0))
        budget = None if width_chars is None else max(width_chars - text_width(self.lhs) - 6.0, 16.0)
        if self._scalar():
            cells, _ = latex_cells(N, self.expr, wrap, budget)
            return [f"{self.lhs} = {cells[0][0]}"]
        groups = [(0, self.expr.cols)] if width_chars is None else self.column_groups(width_chars)
        out = []
        for a, b in groups:
            cells, _ = latex_cells(N, self.expr[:, a:b], wrap, budget)
            body = "\\\\".join(" & ".join(row) for row in cells)
            out.append(f"{self.lhs}{self._label(a, b, True)} = \\begin{{bmatrix}}{body}\\end{{bmatrix}}")
        return out

    def mathml_lhs(self) -> str:
        """The left-hand side as MathML (a small translation of :attr:`lhs`)."""
        return lhs_mathml(self.lhs)

    def mathml(self, width_px: float = 400, notation: Notation | None = None) -> str:
        """``lhs = expr`` as ``<math display="block">`` element(s) that fit ``width_px`` when possible.

        Entries are wrapped over lines; a matrix whose columns together are still too wide is
        split into groups of columns, one ``<math>`` each.
        """
        N = notation or self.notation()
        chars = width_px / PX_PER_CHAR
        wrap = min(MATHML_WIDTH, max(chars - 10.0, 16.0))
        lhs = self.mathml_lhs()
        budget = max(chars - text_width(lhs) - 6.0, 16.0)
        if self._scalar():
            cells, _ = mathml_cells(N, self.expr, wrap, budget)
            return _block(f"{lhs}<mo>=</mo>{cells[0][0]}")
        out = []
        for a, b in self.column_groups(chars):
            cells, _ = mathml_cells(N, self.expr[:, a:b], wrap, budget)
            body = "".join("<mtr>" + "".join(f"<mtd>{e}</mtd>" for e in row) + "</mtr>" for row in cells)
            M = f"<mrow><mo>[</mo><mtable>{body}</mtable><mo>]</mo></mrow>"
            out.append(_block(f"{lhs}{self._label(a, b, False)}<mo>=</mo>{M}"))
        return "\n".join(out)

    def title_html(self) -> str:
        """The caption escaped for HTML."""
        return xml_text(self.title, 2000)

    # ------------------------------------------------------------------ numbers
    @functools.cached_property
    def _function(self) -> Callable[..., Any]:
        expr = self.expr.xreplace(self.model.numeric_values())
        f: Callable[..., Any] = sp.lambdify(
            [list(self.model.q), list(self.inputs)], expr, modules="numpy", cse=True
        )
        return f

    def numeric(self, q: object, inputs: object = None) -> np.ndarray:
        """The step's value at ``q`` (n,) [rad | m], shape of :attr:`expr`.

        ``inputs``: the values of :attr:`inputs` (joint rates [rad/s | m/s] for propagation
        steps, the wrench [N; N m] for force steps); required when the step has any.
        """
        qa = np.asarray(q, dtype=float).reshape(-1)
        if qa.shape != (self.model.dof,):
            raise ValueError(f"q must have shape ({self.model.dof},), got {qa.shape}")
        if self.inputs and inputs is None:
            raise ValueError(f"step {self.key!r} needs the values of {', '.join(map(str, self.inputs))}")
        xa = np.asarray(inputs if inputs is not None else [], dtype=float).reshape(-1)
        if xa.shape != (len(self.inputs),):
            raise ValueError(f"inputs must have shape ({len(self.inputs)},), got {xa.shape}")
        out = np.asarray(self._function(qa, xa), dtype=float)
        return np.broadcast_to(out, self.expr.shape).copy() if out.shape != self.expr.shape else out


def _block(inner: str) -> str:
    return f'<math display="block" style="{MATH_STYLE}"><mrow>{inner}</mrow></math>'


_LHS_MML = {
    "\\omega": "<mi>ω</mi>",
    "\\tau": "<mi>τ</mi>",
    "\\det": "<mi>det</mi><mo>&#x2061;</mo>",
    "\\partial": "<mo>∂</mo>",
    "\\sum": "<mo>∑</mo>",
    "\\mathrm{tool}": "<mtext>tool</mtext>",
    "\\mathrm{base}": "<mtext>base</mtext>",
    "\\theta": "<mi>θ</mi>",
    "\\alpha": "<mi>α</mi>",
    "-": "<mo>−</mo>",
    "+": "<mo>+</mo>",
    "(": "<mo>(</mo>",
    ")": "<mo>)</mo>",
    "\\times": "<mo>×</mo>",
}


def lhs_mathml(latex: str) -> str:
    """MathML of the small LaTeX the steps use on their left-hand sides.

    Understands ``{}^{a}X_{b}``, ``X_{b}``, ``X^{T}``, ``\\frac{A}{B}``, ``\\dot{x}`` and the
    commands of :data:`_LHS_MML`; anything else is shown as text (escaped).
    """
    return _LhsParser(latex).parse()


class _LhsParser:
    def __init__(self, text: str) -> None:
        self.s = text
        self.i = 0

    def parse(self) -> str:
        out = []
        while self.i < len(self.s):
            out.append(self.atom_with_scripts())
        return "<mrow>" + "".join(o for o in out if o) + "</mrow>"

    def group(self) -> str:
        if self.i < len(self.s) and self.s[self.i] == "{":
            depth, start = 1, self.i + 1
            self.i += 1
            while self.i < len(self.s) and depth:
                depth += {"{": 1, "}": -1}.get(self.s[self.i], 0)
                self.i += 1
            return _LhsParser(self.s[start : self.i - 1]).parse()
        return self.atom()

    def atom(self) -> str:
        s = self.s
        c = s[self.i]
        if c == "\\":
            j = self.i + 1
            while j < len(s) and s[j].isalpha():
                j += 1
            cmd = s[self.i : j]
            self.i = j
            if cmd == "\\frac":
                return f"<mfrac>{self.group()}{self.group()}</mfrac>"
            if cmd == "\\dot":
                return f'<mover accent="true">{self.group()}<mo>&#x2D9;</mo></mover>'
            if cmd in ("\\mathrm", "\\text"):
                return _text_group(self)
            if cmd in (",", "\\,", "\\;", "\\quad"):
                return ""
            return _LHS_MML.get(cmd, f"<mtext>{xml_text(cmd)}</mtext>")
        self.i += 1
        if c == "{":
            self.i -= 1
            return self.group()
        if c.isspace():
            return ""
        if c.isdigit():
            return f"<mn>{c}</mn>"
        if c.isalpha():
            return f"<mi>{c}</mi>"
        return _LHS_MML.get(c, f"<mo>{xml_text(c)}</mo>")

    def atom_with_scripts(self) -> str:
        if self.s.startswith("{}^", self.i):  # a left superscript: {}^{0}T_{2}
            self.i += 3
            pre = self.group()
            base = self.atom_with_scripts()
            return f"<mmultiscripts>{_strip(base)}<mprescripts/><none/>{pre}</mmultiscripts>"
        base = self.atom()
        sub: str | None = None
        sup: str | None = None
        while self.i < len(self.s) and self.s[self.i] in "_^":
            mark = self.s[self.i]
            self.i += 1
            if mark == "_":
                sub = self.group()
            else:
                sup = self.group()
        if sub and sup:
            return f"<msubsup>{base}{sub}{sup}</msubsup>"
        if sub:
            return f"<msub>{base}{sub}</msub>"
        return f"<msup>{base}{sup}</msup>" if sup else base


def _text_group(p: _LhsParser) -> str:
    start = p.i + 1
    p.group()
    return f"<mtext>{xml_text(p.s[start : p.i - 1])}</mtext>"


def _strip(mml: str) -> str:
    """<mmultiscripts> wants base, sub, sup: a subscripted base becomes base + its subscript."""
    if mml.startswith("<msub>") and mml.endswith("</msub>"):
        inner = mml[len("<msub>") : -len("</msub>")]
        return f"{inner}<none/>" if inner else mml
    return f"{mml}<none/><none/>"


@dataclass(frozen=True)
class DHRow:
    """One row of a robot's DH table, symbolic (θ or d holds the joint symbol).

    Attributes:
        index: Row number, from 1.
        joint: ``"revolute"`` or ``"prismatic"``.
        name: The joint's name from the robot file (user text: escape it).
        theta, d: θᵢ [rad] and dᵢ [m]; the joint variable is in θᵢ (revolute) or dᵢ (prismatic).
        a, alpha: aᵢ [m], αᵢ [rad] (standard) or a_{i−1}, α_{i−1} (modified, Craig).
        variable: The joint symbol ``q_i``.
        convention: ``"standard"`` or ``"modified"``.
    """

    index: int
    joint: str
    name: str
    theta: sp.Expr
    d: sp.Expr
    a: sp.Expr
    alpha: sp.Expr
    variable: sp.Symbol
    convention: str

    def cells(self) -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
        """The four values in the order of :data:`DH_COLUMNS` for the row's convention."""
        if self.convention == "modified":
            return (self.alpha, self.a, self.d, self.theta)
        return (self.theta, self.d, self.a, self.alpha)

    def is_angle(self) -> tuple[bool, bool, bool, bool]:
        """Which of :meth:`cells` are angles."""
        return (True, False, False, True) if self.convention == "modified" else (True, False, False, True)
