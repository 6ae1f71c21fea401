"""The pieces both handout writers share: captions, the DH table cells, the worked example's
numbers and the singular sets, in LaTeX or MathML (see :mod:`.handout_render`, :mod:`.handout_tex`)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import sympy as sp

from ..steps.step import Step, lhs_mathml, step_notation
from ..typeset.escape import latex_text, xml_text
from ..typeset.printing import Notation
from ..typeset.render import KIND_TEXT
from .content import ROW_NAMES, TITLES, Handout, angle_parts, degrees_text
from .words import ENGLISH, Words, latex_number, list_separator, number, say, say_n

__all__ = [
    "handout_title",
    "intro",
    "jacobian_sentence",
    "contents",
    "contents_sentence",
    "RESULT_TITLE",
    "ASSEMBLED",
    "SINGULAR_SETS",
    "JOINT_COLUMN",
    "NO_DH_TABLE",
    "NOTATION",
    "WHERE",
    "NOTE",
    "example_lines",
    "example_math",
    "dh_cell",
    "singular_texts",
    "handout_notation",
    "robot_text",
    "kind_text",
]


def _fmt(x: float, digits: int) -> str:
    text = f"{x:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def _digits(M: np.ndarray) -> int:
    return 3 if np.abs(M).max(initial=0.0) >= 1 else 4


def robot_text(h: Handout, key: str) -> str:
    """The robot's ``key`` text ("title", "description") in the handout's language, else English."""
    return h.robot.translations.get(h.words.code, {}).get(key) or getattr(h.robot, key)


def kind_text(w: Words, kind: str) -> str:
    """A singularity's kind ("wrist") in words ("wrist singularity"), in ``w``'s language."""
    return say(w, KIND_TEXT[kind])


def handout_title(h: Handout) -> str:
    return say(h.words, "The Jacobian of {robot}, step by step", robot=robot_text(h, "title") or h.robot.name)


def intro(h: Handout) -> list[str]:
    r, w = h.robot, h.words
    kinds = ", ".join(
        say(w, "{i} revolute", i=i + 1) if k == "revolute" else say(w, "{i} prismatic", i=i + 1)
        for i, k in enumerate(r.joint_types)
    )
    robot = say_n(
        w,
        "Robot {name}: {n} joint ({kinds}).",
        "Robot {name}: {n} joints ({kinds}).",
        r.dof,
        name=r.name,
        kinds=kinds,
    )
    rows = (
        say(
            w,
            "J has rows [v; ω] in the base axes: v is the velocity of the tool origin [m/s], ω the angular "
            "velocity [rad/s], per unit joint rate.",
        )
        if h.frame == "base"
        else say(
            w,
            "J has rows [v; ω] in the tool axes: v is the velocity of the tool origin [m/s], ω the angular "
            "velocity [rad/s], per unit joint rate.",
        )
    )
    compact = say(w, "Compact notation: cᵢ = cos θᵢ, sᵢ = sin θᵢ, cᵢⱼ = cos(θᵢ + θⱼ), sᵢⱼ = sin(θᵢ + θⱼ).")
    out = [" ".join((robot, rows, compact))]
    if h.symbolic_params:
        out.append(
            say(
                w,
                "Link lengths and offsets are kept as symbols (their values are in the notation at the end).",
            )
        )
    description = robot_text(h, "description")
    if description:
        out.append(description)
    if r.source:
        out.append(say(w, "Source: {source}", source=r.source))
    return out


def jacobian_sentence(h: Handout) -> str:
    """What the result section says of J: how the derivation that follows reaches it."""
    w, n = h.words, len(h.methods)
    if n > 1:
        if h.same_J:
            return say_n(
                w,
                "The {n} method derived below gives this same J (checked numerically at random "
                "configurations).",
                "The {n} methods derived below give this same J (checked numerically at random "
                "configurations).",
                n,
            )
        return say_n(
            w,
            "The {n} method derived below does NOT agree.",
            "The {n} methods derived below do NOT agree.",
            n,
        )
    return say(w, "Derived step by step below.")


def contents(h: Handout) -> list[tuple[int, str]]:
    """The handout's numbered sections after the result (§1): (number, title) of the derivation, then
    the worked example."""
    w = h.words
    out = [
        (2, say(w, "The Denavit–Hartenberg table")),
        (3, say(w, "Link transforms")),
        (4, say(w, "The frames in the base")),
    ]
    out += [(5 + k, w.gettext(TITLES[m])) for k, m in enumerate(h.methods)]
    out.append((5 + len(h.methods), say(w, "Worked example")))
    return out


def contents_sentence(h: Handout) -> str:
    """The line under the result: where the derivation is."""
    parts = ", ".join(f"§{n} {title}" for n, title in contents(h))
    return say(h.words, "The derivation follows: {sections}.", sections=parts)


RESULT_TITLE = "1. The result: J(q) and det J"
ASSEMBLED = "These steps give the J(q) of §1."
SINGULAR_SETS = "Singular configurations (a factor of the determinant vanishes):"
JOINT_COLUMN = "joint"
NO_DH_TABLE = "This robot has no DH table (a URDF chain): its link and joint frames come from the URDF file."
NOTATION = "Notation"
WHERE = "where {items}"
NOTE = "Note: {note}"


def example_lines(h: Handout) -> list[str]:
    ex, w = h.example, h.words
    q = list_separator(w).join(
        f"{number(w, degrees_text(sp.Float(v)))}°"
        if k == "revolute"
        else f"{number(w, _fmt(v, 3).rstrip('0').rstrip('.'))} m"
        for v, k in zip(ex.q, h.robot.joint_types, strict=True)
    )
    if ex.name:
        line = say(w, "At the configuration “{name}”, q = ({q}).", name=ex.name, q=q)
    else:
        line = say(w, "At the middle of the joint ranges, q = ({q}).", q=q)
    named = next((c for c in h.robot.configurations if c.name == ex.name), None)
    description = (named.translations.get(w.code, {}).get("description") if named else None) or ex.description
    out = [line + (f" {description}" if description else "")]
    rows = ", ".join(ROW_NAMES[r] for r in ex.rows)
    out.append(say(w, "J(q), task rows ({rows}):", rows=rows))
    return out


def _rate_text(w: Words, v: float, kind: str, digits: int = 3) -> str:
    if kind == "revolute":
        return f"{number(w, _fmt(np.degrees(v), 2))}°/s"
    return f"{number(w, _fmt(v, digits))} m/s"


# ---------------------------------------------------------------------------------- numbers
def _num_latex(w: Words, M: np.ndarray, digits: int) -> str:
    M = np.atleast_2d(M)
    return (
        "\\begin{bmatrix}"
        + "\\\\".join(" & ".join(latex_number(w, _fmt(x, digits)) for x in row) for row in M)
        + "\\end{bmatrix}"
    )


def _num_mathml(w: Words, M: np.ndarray, digits: int) -> str:
    M = np.atleast_2d(M)
    rows = "".join(
        "<mtr>"
        + "".join(f"<mtd><mn>{number(w, _fmt(x, digits)).replace('-', '−')}</mn></mtd>" for x in row)
        + "</mtr>"
        for row in M
    )
    return f"<mrow><mo>[</mo><mtable>{rows}</mtable><mo>]</mo></mrow>"


def _rates(w: Words, v: np.ndarray, kinds: tuple[str, ...]) -> str:
    return list_separator(w).join(_rate_text(w, x, k) for x, k in zip(v, kinds, strict=True))


def _units(units: list[str], latex: bool) -> str:
    """A column of units, set beside a column vector (one per row: a joint's rad/s or m/s)."""
    if latex:
        cells = (rf"\text{{{u[:-1]}}}^{{2}}" if u.endswith("²") else rf"\text{{{u}}}" for u in units)
        return r"\;\begin{matrix}" + r"\\".join(cells) + r"\end{matrix}"
    rows = "".join(f"<mtr><mtd><mtext>{u}</mtext></mtd></mtr>" for u in units)
    return f'<mspace width="0.4em"/><mtable columnalign="left">{rows}</mtable>'


def _joint_units(kinds: tuple[str, ...]) -> list[str]:
    return ["rad/s" if k == "revolute" else "m/s" for k in kinds]


def _row_units(rows: tuple[int, ...]) -> list[str]:
    return ["m/s" if r < 3 else "rad/s" for r in rows]


def example_math(h: Handout, latex: bool) -> list[tuple[str, str]]:
    """(caption, formula) pairs of the worked example."""
    ex, kinds, w = h.example, h.robot.joint_types, h.words

    def num(M: np.ndarray, digits: int) -> str:
        return _num_latex(w, M, digits) if latex else _num_mathml(w, M, digits)

    def col(v: npt.ArrayLike) -> np.ndarray:
        return np.asarray(v).reshape(-1, 1)

    lhs = (lambda t: t) if latex else lhs_mathml
    eq = " = " if latex else "<mo>=</mo>"
    dg = "\\frac{\\partial g}{\\partial x}"
    jdot, alone = "\\dot{J} \\dot{q}", "\\sum_i \\dot{J}_i \\dot{q}_i"
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
        out.append(("", f"{det_q}{eq}{_scalar(w, ex.det, latex)}"))
    else:
        out.append((say(w, "Manipulability √det(J Jᵀ):"), f"{w_q}{eq}{_scalar(w, ex.det, latex)}"))
    joint_units, row_units = _units(_joint_units(kinds), latex), _units(_row_units(ex.rows), latex)
    if ex.rates is not None and ex.velocity is not None:
        out.append(
            (
                say(w, "With the joint rates q̇ = ({rates}):", rates=_rates(w, ex.rates, kinds)),
                f"{qd}{eq}{num(col(ex.rates), 4)}{joint_units}",
            )
        )
        out.append(
            (say(w, "the tool velocity (task rows) is"), f"{Jqd}{eq}{num(col(ex.velocity), 3)}{row_units}")
        )
    if ex.jdot_qd is not None and ex.jdot_alone_qd is not None:
        acc_units = _units([u + "²" for u in _row_units(ex.rows)], latex)
        caption = say(w, "and at constant rates (q̈ = 0) the tool accelerates: ẍ = J q̈ + J̇ q̇ = J̇ q̇ =")
        out.append((caption, f"{lhs(jdot)}{eq}{num(col(ex.jdot_qd), 3)}{acc_units}"))
        caption = say(
            w,
            "Course 000's per-joint J̇ᵢ holds for joint i moving alone; the sum of its terms "
            "(equal to J̇ q̇ only when one joint moves):",
        )
        out.append((caption, f"{lhs(alone)}{eq}{num(col(ex.jdot_alone_qd), 3)}{acc_units}"))
    if ex.inverse is not None:
        out.append((say(w, "J is square and regular here; its inverse:"), f"{J_inv}{eq}{num(ex.inverse, 4)}"))
    elif ex.square:
        out.append((say(w, "J is singular here (det J = 0): it has no inverse."), ""))
    if ex.closed_form is not None:
        caption = say(w, "From the closed-form inverse kinematics q = g(x) (course 002, the third way):")
        out.append((caption, f"{J_inv}{eq}{lhs(dg)}{eq}{num(ex.closed_form, 4)}"))
    if ex.twist is not None:
        out.append(
            (say(w, "For the tool velocity (task rows)"), f"{v}{eq}{num(col(ex.twist), 3)}{row_units}")
        )
        if ex.solved is not None:
            out.append(
                (
                    say(w, "the joints must move at q̇ = ({rates}):", rates=_rates(w, ex.solved, kinds)),
                    f"{solved}{eq}{num(col(ex.solved), 4)}{joint_units}",
                )
            )
    return out


def _scalar(w: Words, x: float, latex: bool) -> str:
    text = f"{x:.6g}" if abs(x) >= 1e-4 or x == 0 else f"{x:.3e}"
    return latex_number(w, text) if latex else f"<mn>{number(w, text).replace('-', '−')}</mn>"


# ----------------------------------------------------------------------------------- DH table
def dh_cell(N: Notation, e: sp.Expr, angle: bool, latex: bool, w: Words = ENGLISH) -> str:
    show = N.latex if latex else N.mathml
    if not angle:
        return show(e)
    var, const = angle_parts(e)
    if const == 0:
        return show(var) if var != 0 else ("0" if latex else "<mn>0</mn>")
    deg = (latex_number if latex else number)(w, degrees_text(const))
    neg = deg.startswith("-")
    mag = deg.lstrip("-")
    c = f"{mag}^{{\\circ}}" if latex else f"<mn>{mag}°</mn>"
    if var == 0:
        return ("-" if latex else "<mo>−</mo>") * neg + c
    sign = (" - " if neg else " + ") if latex else ("<mo>−</mo>" if neg else "<mo>+</mo>")
    return f"{show(var)}{sign}{c}"


def singular_texts(N: Notation, det: Step, latex: bool, w: Words = ENGLISH) -> list[str]:
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
                f" \\quad \\text{{({latex_text(kind_text(w, s.kind), 120)})}}"
                if latex
                else f'<mspace width="1em"/><mtext>({xml_text(kind_text(w, s.kind))})</mtext>'
            )
        out.append(text)
    return out


# ---------------------------------------------------------------------------------------- HTML
def handout_notation(h: Handout) -> Notation:
    model = (h.transforms or h.result)[0].model
    return step_notation(model, names=h.names)
