"""The pieces both handout writers share: captions, the DH table cells, the worked example's
numbers and the singular sets, in LaTeX or MathML (see :mod:`.handout_render`, :mod:`.handout_tex`)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import sympy as sp

from ..steps.step import Step, lhs_mathml, step_notation
from ..typeset.printing import Notation
from ..typeset.render import KIND_TEXT
from .content import ROW_NAMES, TITLES, Example, Handout, angle_parts, degrees_text

__all__ = [
    "handout_title",
    "intro",
    "jacobian_sentence",
    "contents",
    "contents_sentence",
    "RESULT_TITLE",
    "ASSEMBLED",
    "example_lines",
    "example_math",
    "dh_cell",
    "singular_texts",
    "handout_notation",
]


def _fmt(x: float, digits: int) -> str:
    text = f"{x:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def _digits(M: np.ndarray) -> int:
    return 3 if np.abs(M).max(initial=0.0) >= 1 else 4


def handout_title(h: Handout) -> str:
    r = h.robot
    return f"The Jacobian of {r.title or r.name}, step by step"


def intro(h: Handout) -> list[str]:
    r = h.robot
    axes = "base" if h.frame == "base" else "tool"
    out = [
        f"Robot {r.name}: {r.dof} joints ("
        + ", ".join(
            f"{i + 1} {'revolute' if k == 'revolute' else 'prismatic'}" for i, k in enumerate(r.joint_types)
        )
        + f"). J has rows [v; ω] in the {axes} axes: v is the velocity of the tool origin [m/s], ω the "
        "angular velocity [rad/s], per unit joint rate. Compact notation: cᵢ = cos θᵢ, sᵢ = sin θᵢ, "
        "cᵢⱼ = cos(θᵢ + θⱼ), sᵢⱼ = sin(θᵢ + θⱼ).",
    ]
    if h.symbolic_params:
        out.append(
            "Link lengths and offsets are kept as symbols (their values are in the notation at the end)."
        )
    if r.description:
        out.append(r.description)
    if r.source:
        out.append(f"Source: {r.source}")
    return out


def jacobian_sentence(h: Handout) -> str:
    """What the result section says of J: how the derivation that follows reaches it."""
    if len(h.methods) > 1:
        agree = (
            "give this same J (checked numerically at random configurations)" if h.same_J else "do NOT agree"
        )
        return f"The {len(h.methods)} methods derived below {agree}."
    return "Derived step by step below."


def contents(h: Handout) -> list[tuple[int, str]]:
    """The handout's numbered sections after the result (§1): (number, title) of the derivation, then
    the worked example."""
    out = [(2, "The Denavit–Hartenberg table"), (3, "Link transforms"), (4, "The frames in the base")]
    out += [(5 + k, TITLES[m]) for k, m in enumerate(h.methods)]
    out.append((5 + len(h.methods), "Worked example"))
    return out


def contents_sentence(h: Handout) -> str:
    """The line under the result: where the derivation is."""
    parts = ", ".join(f"§{n} {title}" for n, title in contents(h))
    return f"The derivation follows: {parts}."


RESULT_TITLE = "1. The result: J(q) and det J"
ASSEMBLED = "These steps give the J(q) of §1."


def example_lines(ex: Example, robot_kinds: tuple[str, ...]) -> list[str]:
    q = ", ".join(
        f"{degrees_text(sp.Float(v))}°" if k == "revolute" else f"{_fmt(v, 3).rstrip('0').rstrip('.')} m"
        for v, k in zip(ex.q, robot_kinds, strict=True)
    )
    where = f"the configuration “{ex.name}”" if ex.name else "the middle of the joint ranges"
    out = [f"At {where}, q = ({q})." + (f" {ex.description}" if ex.description else "")]
    rows = ", ".join(ROW_NAMES[r] for r in ex.rows)
    out.append(f"J(q), task rows ({rows}):")
    return out


def _rate_text(v: float, kind: str, digits: int = 3) -> str:
    if kind == "revolute":
        return f"{_fmt(np.degrees(v), 2)}°/s"
    return f"{_fmt(v, digits)} m/s"


# ---------------------------------------------------------------------------------- numbers
def _num_latex(M: np.ndarray, digits: int) -> str:
    M = np.atleast_2d(M)
    return (
        "\\begin{bmatrix}"
        + "\\\\".join(" & ".join(_fmt(x, digits) for x in row) for row in M)
        + "\\end{bmatrix}"
    )


def _num_mathml(M: np.ndarray, digits: int) -> str:
    M = np.atleast_2d(M)
    rows = "".join(
        "<mtr>" + "".join(f"<mtd><mn>{_fmt(x, digits).replace('-', '−')}</mn></mtd>" for x in row) + "</mtr>"
        for row in M
    )
    return f"<mrow><mo>[</mo><mtable>{rows}</mtable><mo>]</mo></mrow>"


def _rates(v: np.ndarray, kinds: tuple[str, ...]) -> str:
    return ", ".join(_rate_text(x, k) for x, k in zip(v, kinds, strict=True))


def _units(units: list[str], latex: bool) -> str:
    """A column of units, set beside a column vector (one per row: a joint's rad/s or m/s)."""
    if latex:
        return r"\;\begin{matrix}" + r"\\".join(rf"\text{{{u}}}" for u in units) + r"\end{matrix}"
    rows = "".join(f"<mtr><mtd><mtext>{u}</mtext></mtd></mtr>" for u in units)
    return f'<mspace width="0.4em"/><mtable columnalign="left">{rows}</mtable>'


def _joint_units(kinds: tuple[str, ...]) -> list[str]:
    return ["rad/s" if k == "revolute" else "m/s" for k in kinds]


def _row_units(rows: tuple[int, ...]) -> list[str]:
    return ["m/s" if r < 3 else "rad/s" for r in rows]


def example_math(ex: Example, kinds: tuple[str, ...], latex: bool) -> list[tuple[str, str]]:
    """(caption, formula) pairs of the worked example."""
    num = _num_latex if latex else _num_mathml

    def col(v: npt.ArrayLike) -> np.ndarray:
        return np.asarray(v).reshape(-1, 1)

    lhs = (lambda t: t) if latex else lhs_mathml
    eq = " = " if latex else "<mo>=</mo>"
    J_q, det_q, w_q, qd, Jqd, J_inv, v, solved = (
        lhs(t)
        for t in (
            "J(q)",
            "\\det J(q)",
            "w(q)",
            "\\dot{q}",
            "J \\dot{q}",
            "J^{-1}(q)",
            "v",
            "\\dot{q} = J^{-1} v",
        )
    )
    out = [("", f"{J_q}{eq}{num(ex.J, _digits(ex.J))}")]
    if ex.square:
        out.append(("", f"{det_q}{eq}{_scalar(ex.det, latex)}"))
    else:
        out.append(("Manipulability √det(J Jᵀ):", f"{w_q}{eq}{_scalar(ex.det, latex)}"))
    joint_units, row_units = _units(_joint_units(kinds), latex), _units(_row_units(ex.rows), latex)
    if ex.rates is not None and ex.velocity is not None:
        out.append(
            (
                f"With the joint rates q̇ = ({_rates(ex.rates, kinds)}):",
                f"{qd}{eq}{num(col(ex.rates), 4)}{joint_units}",
            )
        )
        out.append(("the tool velocity (task rows) is", f"{Jqd}{eq}{num(col(ex.velocity), 3)}{row_units}"))
    if ex.inverse is not None:
        out.append(("J is square and regular here; its inverse:", f"{J_inv}{eq}{num(ex.inverse, 4)}"))
    elif ex.square:
        out.append(("J is singular here (det J = 0): it has no inverse.", ""))
    if ex.twist is not None:
        out.append(("For the tool velocity (task rows)", f"{v}{eq}{num(col(ex.twist), 3)}{row_units}"))
        if ex.solved is not None:
            out.append(
                (
                    f"the joints must move at q̇ = ({_rates(ex.solved, kinds)}):",
                    f"{solved}{eq}{num(col(ex.solved), 4)}{joint_units}",
                )
            )
    return out


def _scalar(x: float, latex: bool) -> str:
    text = f"{x:.6g}" if abs(x) >= 1e-4 or x == 0 else f"{x:.3e}"
    return text if latex else f"<mn>{text.replace('-', '−')}</mn>"


# ----------------------------------------------------------------------------------- DH table
def dh_cell(N: Notation, e: sp.Expr, angle: bool, latex: bool) -> str:
    show = N.latex if latex else N.mathml
    if not angle:
        return show(e)
    var, const = angle_parts(e)
    if const == 0:
        return show(var) if var != 0 else ("0" if latex else "<mn>0</mn>")
    deg = degrees_text(const)
    neg = deg.startswith("-")
    mag = deg.lstrip("-")
    c = f"{mag}^{{\\circ}}" if latex else f"<mn>{mag}°</mn>"
    if var == 0:
        return ("-" if latex else "<mo>−</mo>") * neg + c
    sign = (" - " if neg else " + ") if latex else ("<mo>−</mo>" if neg else "<mo>+</mo>")
    return f"{show(var)}{sign}{c}"


def singular_texts(N: Notation, det: Step, latex: bool) -> list[str]:
    show = N.latex if latex else N.mathml
    out = []
    for s in det.singular:
        text = f"{show(s.factor)} = 0" if latex else f"{show(s.factor)}<mo>=</mo><mn>0</mn>"
        if s.solutions is not None and len(s.joints) == 1 and s.factor != s.joints[0]:
            sol = show(sp.FiniteSet(*s.solutions))
            text += (
                f" \\;\\Rightarrow\\; {show(s.joints[0])} \\in {sol}"
                if latex
                else f"<mo>⇒</mo>{show(s.joints[0])}<mo>∈</mo>{sol}"
            )
        if s.kind:
            text += (
                f" \\quad \\text{{({KIND_TEXT[s.kind]})}}"
                if latex
                else f'<mspace width="1em"/><mtext>({KIND_TEXT[s.kind]})</mtext>'
            )
        out.append(text)
    return out


# ---------------------------------------------------------------------------------------- HTML
def handout_notation(h: Handout) -> Notation:
    model = (h.transforms or h.result)[0].model
    return step_notation(model, names=h.names)
