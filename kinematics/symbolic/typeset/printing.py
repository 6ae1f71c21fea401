"""The course's compact notation in LaTeX and MathML: cᵢ, sᵢ, cᵢⱼ, sᵢⱼ with a legend.

``cos(q2 + q3)`` prints as c₂₃, ``sin(q1)`` as s₁; joint variables print as θᵢ
(revolute) or dᵢ (prismatic); rationals with a finite decimal expansion print
as decimals (2159/5000 → 0.4318); in a product, numbers, parameters and
trigonometric factors come first and parenthesised sums last
(``s_1 (a_2 c_2 + a_3 c_{23})``). A :class:`Notation` remembers which
abbreviations it used, so its legend lists exactly those.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from decimal import Decimal, localcontext
from typing import Any, Literal, cast

import sympy as sp
from sympy.printing.latex import LatexPrinter
from sympy.printing.mathml import MathMLPresentationPrinter
from sympy.printing.precedence import PRECEDENCE, precedence

from ...text import N_, Translating
from .escape import latex_text, xml_text

__all__ = ["Notation", "decimal_text"]


def decimal_text(r: sp.Rational, max_digits: int = 12) -> str | None:
    """``r`` as an exact decimal if its expansion is finite and has at most ``max_digits`` significant
    digits (2159/5000 → "0.4318", 26673/3200000000 → "0.0000083353125"), else None."""
    q = int(r.q)
    for f in (2, 5):
        while q % f == 0:
            q //= f
    if q != 1:
        return None
    with localcontext() as ctx:
        ctx.prec = 60
        text = format((Decimal(int(r.p)) / Decimal(int(r.q))).normalize(), "f")
    significant = text.replace("-", "").replace(".", "").lstrip("0")
    return text if len(significant) <= max_digits else None


class Notation:
    """Printer state for one robot: symbols, display names and the abbreviations used so far.

    Args:
        q: Joint symbols ``q1 … qn``.
        display: LaTeX display names of joint and parameter symbols.
        joint_kinds: ``"revolute"`` / ``"prismatic"`` per joint.
        params: Symbolic parameters → values [m] / [rad], listed in the legend.
        joint_names: The robot's joint names, listed in the legend (escaped) unless they are
            the default ``q1 … qn``.
    """

    def __init__(
        self,
        q: Sequence[sp.Symbol],
        display: Mapping[sp.Symbol, str],
        joint_kinds: Sequence[str],
        params: Mapping[sp.Symbol, float] | None = None,
        joint_names: Sequence[str] = (),
    ) -> None:
        self.q = tuple(q)
        self.index = {s: i + 1 for i, s in enumerate(self.q)}
        self.display = dict(display)
        self.joint_kinds = tuple(joint_kinds)
        self.params = dict(params or {})
        default = tuple(f"q{i + 1}" for i in range(len(self.q)))
        self.joint_names = tuple(joint_names) if tuple(joint_names) != default else ()
        self.used: set[tuple[str, tuple[int, ...]]] = set()

    # ---------------------------------------------------------------- helpers
    def compact(self, f: sp.Expr) -> tuple[str, str] | None:
        """("c" or "s", subscript) for cos/sin of a plain sum of joint angles, else None."""
        terms = sp.Add.make_args(f.args[0])
        if not all(t in self.index for t in terms):
            return None
        idx = tuple(sorted(self.index[t] for t in terms))
        if len(set(idx)) != len(idx):
            return None
        letter = "c" if isinstance(f, sp.cos) else "s"
        self.used.add((letter, idx))
        sep = "," if len(self.q) > 9 else ""
        return letter, sep.join(str(i) for i in idx)

    def factor_key(self, f: sp.Expr) -> tuple[Any, ...]:
        """Order of factors in a product: constants, parameters, joint values, trig by joint, sums."""
        base = f.as_base_exp()[0]
        if base.is_Add:
            return (5, 0, "")
        if not base.free_symbols:
            return (0, 0, "")
        if base.is_Symbol:
            return (2, self.index[base], "") if base in self.index else (1, 0, _natural(base.name))
        if isinstance(base, (sp.sin, sp.cos)):
            joints = sorted(self.index.get(s, 99) for s in base.free_symbols)
            return (3, tuple(joints), "c" if isinstance(base, sp.cos) else "s")
        return (4, 0, str(base))

    # ------------------------------------------------------------------ LaTeX
    def latex(self, expr: sp.Basic) -> str:
        """LaTeX of an expression or matrix (matrices as ``bmatrix``)."""
        return cast(str, _Latex(self).doprint(expr))

    def _legend(self) -> tuple[list[str], list[Literal["revolute", "prismatic"]], list[sp.Symbol]]:
        """What the legend lists: index patterns of the abbreviations used ("i", "ij", …),
        the joint kinds present, and the parameters."""
        sizes = sorted({len(idx) for _, idx in self.used})
        patterns = ["ijkl"[:k] if k <= 4 else "i…" for k in sizes]
        kinds = [k for k in ("revolute", "prismatic") if k in self.joint_kinds]
        return patterns, kinds, sorted(self.params, key=lambda s: _natural(str(s)))

    def _unit(self, s: sp.Symbol) -> str:
        return "rad" if str(s).startswith(("alpha", "theta")) else "m"

    def latex_legend(self) -> str:
        """LaTeX legend of the abbreviations used so far and of the parameters (a ``\\text`` line)."""
        return "\\text{where } " + ", \\quad ".join(self.latex_legend_items())

    def latex_legend_items(self, tr: Translating | None = None) -> list[str]:
        """The LaTeX legend's items, its words in ``tr``'s language (English without it), escaped."""
        say = (lambda m: m) if tr is None else tr.gettext
        patterns, kinds, params = self._legend()
        out = []
        for sub in patterns:
            sub = sub.replace("…", "\\ldots ")
            arg = (
                f"\\theta_{{{sub}}}"
                if len(sub) == 1
                else "(" + " + ".join(f"\\theta_{{{c}}}" for c in sub) + ")"
            )
            out.append(f"c_{{{sub}}} = \\cos {arg}, \\; s_{{{sub}}} = \\sin {arg}")
        joint = {
            "revolute": f"\\theta_{{i}}\\text{{: {latex_text(say(JOINT_LEGEND['revolute']))}}}",
            "prismatic": f"d_{{i}}\\text{{: {latex_text(say(JOINT_LEGEND['prismatic']))}}}",
        }
        out += [joint[k] for k in kinds]
        out += [f"{self.display[s]} = {self.params[s]:.6g}\\,\\mathrm{{{self._unit(s)}}}" for s in params]
        if self.joint_names:
            names = ", ".join(
                f"{self.display[q]}\\text{{: {latex_text(n)}}}"
                for q, n in zip(self.q, self.joint_names, strict=True)
            )
            out.append(latex_around(say(JOINTS_LEGEND), "names", names))
        return out

    # ----------------------------------------------------------------- MathML
    def mathml(self, expr: sp.Basic) -> str:
        """Presentation MathML (the inner element, without ``<math>``) of an expression or matrix."""
        return cast(str, _MathML(self).doprint(expr)).replace("<mo>-</mo>", "<mo>\u2212</mo>")

    def ordered_terms(self, expr: sp.Expr) -> list[sp.Expr]:
        """The terms of a sum in the order the printers show them."""
        return list(_MathML(self)._as_ordered_terms(expr, order=None))

    def mathml_legend(self) -> str:
        """The legend as presentation MathML: one ``<mrow>`` of ``<mtext>`` and formulas ("" if empty)."""
        out = self.mathml_legend_items()
        if not out:
            return ""
        sep = '<mo separator="true">,</mo><mspace width="1em"/>'
        return "<mrow><mtext>where&#xa0;</mtext>" + sep.join(out) + "</mrow>"

    def mathml_legend_items(self, tr: Translating | None = None) -> list[str]:
        """The legend's items, each a MathML fragment (the joint names escaped), for wrapping text; its
        words in ``tr``'s language (English without it)."""
        say = (lambda m: m) if tr is None else tr.gettext
        patterns, kinds, params = self._legend()

        def theta(i: str) -> str:
            return f"<msub><mi>θ</mi><mi>{i}</mi></msub>"

        out = []
        for sub in patterns:
            arg = (
                theta(sub)
                if len(sub) == 1
                else "<mo>(</mo>" + "<mo>+</mo>".join(map(theta, sub)) + "<mo>)</mo>"
            )
            out += [
                f"<msub><mi>{ab}</mi><mi>{sub}</mi></msub><mo>=</mo><mi>{fn}</mi><mo>&#x2061;</mo>{arg}"
                for ab, fn in (("c", "cos"), ("s", "sin"))
            ]
        joint = {
            "revolute": f"{theta('i')}<mtext>: {xml_text(say(JOINT_LEGEND['revolute']))}</mtext>",
            "prismatic": "<msub><mi>d</mi><mi>i</mi></msub>"
            f"<mtext>: {xml_text(say(JOINT_LEGEND['prismatic']))}</mtext>",
        }
        out += [joint[k] for k in kinds]
        out += [
            f"{_mathml_name(self.display[s])}<mo>=</mo><mn>{self.params[s]:.6g}</mn>"
            f"<mtext>&#xa0;{self._unit(s)}</mtext>"
            for s in params
        ]
        if self.joint_names:
            out += [
                f"{_mathml_name(self.display[q])}<mtext>:&#xa0;{xml_text(n)}</mtext>"
                for q, n in zip(self.q, self.joint_names, strict=True)
            ]
        return out


JOINT_LEGEND = {
    "revolute": N_("angle of revolute joint i [rad]"),
    "prismatic": N_("extension of prismatic joint i [m]"),
}
"""The legend's words for a joint variable (θᵢ, dᵢ), marked for the catalogs."""
JOINTS_LEGEND = N_("joints: {names}")
"""The legend's line of joint names (``{names}``: the joints' symbols and names)."""


def latex_around(sentence: str, key: str, maths: str) -> str:
    """LaTeX maths of a (translated) ``sentence`` whose placeholder ``{key}`` stands for ``maths``: its
    words escaped in ``\\text{}`` on either side, a space kept between words and maths."""
    before, _, after = sentence.partition(f"{{{key}}}")
    head = f"\\text{{{latex_text(before)}}}\\ " if before.strip() else ""
    tail = f"\\ \\text{{{latex_text(after)}}}" if after.strip() else ""
    return f"{head}{maths}{tail}"


def _natural(name: str) -> tuple[Any, ...]:
    m = re.match(r"([^\d]*)(\d*)(.*)", name)
    return (m.group(1), int(m.group(2) or 0), m.group(3))  # type: ignore[union-attr]


_GREEK = {"alpha": "α", "theta": "θ", "beta": "β", "gamma": "γ"}
_DOT = re.compile(r"^\\dot\{(\\?[A-Za-z]+)\}(.*)$")
_DISPLAY = re.compile(r"^\\?([A-Za-z]+)(?:_\{(?:\\mathrm\{)?([A-Za-z0-9]+)\}?\})?(?:\^\{(\w+)\})?$")


def _mathml_name(latex: str) -> str:
    """MathML of one of our display names (``\\theta_{2}``, ``a_{3}``, ``x_{\\mathrm{t}}``, ``d_{3}^{0}``)."""
    dot = _DOT.match(latex)  # a rate: \dot{\theta}_{2}
    if dot is not None:
        latex = dot.group(1) + dot.group(2)
    m = _DISPLAY.match(latex)
    if m is None:
        return f"<mi>{xml_text(latex)}</mi>"
    name, sub, sup = m.groups()
    head = f"<mi>{_GREEK.get(name, name)}</mi>"
    if dot is not None:
        head = f'<mover accent="true">{head}<mo>&#x2D9;</mo></mover>'
    sub_el = (
        f"<mn>{sub}</mn>" if sub and sub.isdigit() else f'<mi mathvariant="normal">{sub}</mi>' if sub else ""
    )
    if sub and sup:
        return f"<msubsup>{head}{sub_el}<mn>{sup}</mn></msubsup>"
    if sub:
        return f"<msub>{head}{sub_el}</msub>"
    return f"<msup>{head}<mn>{sup}</mn></msup>" if sup else head


class _Latex(LatexPrinter):  # type: ignore[misc]  # sympy has no type information
    def __init__(self, notation: Notation) -> None:
        super().__init__({"mat_str": "bmatrix", "mat_delim": "", "symbol_names": notation.display})
        self.notation = notation

    def _print_trig(self, expr: sp.Expr, exp: str | None = None) -> str:
        c = self.notation.compact(expr)
        if c is None:  # sin(θ₂ + 0.2): written out (LatexPrinter would dispatch back here)
            power = f"^{{{exp}}}" if exp else ""
            return f"\\{type(expr).__name__}{power}{{\\left({self._print(expr.args[0])} \\right)}}"
        letter, sub = c
        return f"{letter}_{{{sub}}}" + (f"^{{{exp}}}" if exp else "")

    _print_sin = _print_trig
    _print_cos = _print_trig

    def _print_Rational(self, expr: sp.Rational) -> str:
        text = decimal_text(expr)
        return text if text is not None else super()._print_Rational(expr)

    def _print_Mul(self, expr: sp.Mul) -> str:
        coeff, factors = expr.as_coeff_mul()
        if any(f.as_base_exp()[1].could_extract_minus_sign() for f in factors) or not factors:
            return cast(str, super()._print_Mul(expr))
        ordered = sorted(factors, key=self.notation.factor_key)
        body = " ".join(
            f"\\left({self._print(f)}\\right)" if precedence(f) < PRECEDENCE["Mul"] else self._print(f)
            for f in ordered
        )
        if coeff == 1:
            return body
        if coeff == -1:
            return "- " + body
        return f"{self._print(coeff)} {body}"


class _MathML(MathMLPresentationPrinter):  # type: ignore[misc]  # sympy has no type information
    def __init__(self, notation: Notation) -> None:
        super().__init__({"mat_delim": "["})
        self.notation = notation

    def _element(self, xml: str) -> Any:  # parse one of our own small, well-formed snippets
        from xml.dom.minidom import parseString

        return parseString(f"<mrow>{xml}</mrow>").documentElement

    def _print_trig(self, expr: sp.Expr) -> Any:
        c = self.notation.compact(expr)
        if c is None:
            return super()._print_Function(expr)
        letter, sub = c
        return self._element(f"<msub><mi>{letter}</mi><mn>{sub}</mn></msub>")

    _print_sin = _print_trig
    _print_cos = _print_trig

    def _print_Pi(self, expr: sp.Expr) -> Any:  # the character, not the HTML-only entity &pi;
        return self._element("<mi>π</mi>")

    def _print_Symbol(self, sym: sp.Symbol, style: str = "plain") -> Any:
        if sym in self.notation.display:
            return self._element(_mathml_name(self.notation.display[sym]))
        return super()._print_Symbol(sym, style)

    def _print_Rational(self, expr: sp.Rational) -> Any:
        text = decimal_text(expr)
        if text is None:
            return super()._print_Rational(expr)
        sign = "<mo>-</mo>" if text.startswith("-") else ""
        return self._element(f"{sign}<mn>{text.lstrip('-')}</mn>")

    def _print_Mul(self, expr: sp.Mul) -> Any:
        coeff, factors = expr.as_coeff_mul()
        if any(f.as_base_exp()[1].could_extract_minus_sign() for f in factors) or not factors:
            return super()._print_Mul(expr)
        mrow = self.dom.createElement("mrow")
        if coeff.could_extract_minus_sign():
            mo = self.dom.createElement("mo")
            mo.appendChild(self.dom.createTextNode("-"))
            mrow.appendChild(mo)
            coeff = -coeff
        if coeff != 1:
            mrow.appendChild(self._print(coeff))
        for f in sorted(factors, key=self.notation.factor_key):
            if mrow.childNodes and mrow.lastChild.nodeName != "mo":
                mo = self.dom.createElement("mo")
                mo.appendChild(self.dom.createTextNode("\u2062"))  # invisible times
                mrow.appendChild(mo)
            mrow.appendChild(self.parenthesize(f, PRECEDENCE["Mul"]))
        return mrow
