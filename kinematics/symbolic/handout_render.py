"""Writers of a :class:`.handout.Handout`: one self-contained HTML page (MathML, no script, no
network) or one complete LaTeX document. Every name from the robot file is escaped here
(:func:`.escape.xml_text`, :func:`.escape.latex_text`)."""

from __future__ import annotations

import re

import numpy as np
import sympy as sp

from .escape import NOTE_CHARS, latex_text, xml_text
from .handout import INTRO, ROW_NAMES, TITLES, Example, Handout, angle_parts, degrees_text
from .printing import Notation
from .render import KIND_TEXT, MATH_STYLE
from .step import DH_COLUMNS, Step, lhs_mathml, step_notation
from .step_layout import OMITTED

__all__ = ["render_html", "render_tex", "HTML_MATH_PX", "TEX_MATH_CHARS"]

HTML_MATH_PX = 780
"""Width [px] the HTML handout gives a formula (the page's text column is 60rem)."""
TEX_MATH_CHARS = 72
"""Width [characters] the LaTeX handout gives a formula (A4 with 2 cm margins)."""

CSS = f"""
body {{ margin: 0; background: #fff; color: #1d1d1d; font: 17px/1.55 Georgia, 'DejaVu Serif', serif; }}
main {{ max-width: 60rem; margin: 0 auto; padding: 1.5rem 2rem 4rem; box-sizing: border-box; }}
h1 {{ font-size: 1.7rem; line-height: 1.25; margin-bottom: 0.3rem; }}
h2 {{ font-size: 1.3rem; border-bottom: 1px solid #bbb; margin-top: 2.4rem; }}
h3 {{ font-size: 1.05rem; margin: 1.6rem 0 0.4rem; }}
p {{ margin: 0.5rem 0; overflow-wrap: anywhere; }}
.sub {{ color: #555; }}
.cap {{ margin: 1.1rem 0 0.1rem; }}
.note {{ color: #555; font-size: 0.92rem; }}
math {{ {MATH_STYLE}; }}
math[display="block"] {{ margin: 0.35rem 0 0.35rem 1.5rem; }}
table.dh {{ border-collapse: collapse; margin: 0.6rem 0 0.6rem 1.5rem; }}
table.dh th, table.dh td {{ padding: 0.2rem 0.9rem; border-bottom: 1px solid #ddd; text-align: center; }}
table.dh td.name {{ text-align: left; max-width: 16rem; overflow-wrap: anywhere; }}
"""


def _fmt(x: float, digits: int) -> str:
    text = f"{x:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def _digits(M: np.ndarray) -> int:
    return 3 if np.abs(M).max(initial=0.0) >= 1 else 4


def _title(h: Handout) -> str:
    r = h.robot
    return f"The Jacobian of {r.title or r.name}, step by step"


def _intro(h: Handout) -> list[str]:
    r = h.robot
    axes = "base" if h.frame == "base" else "tool"
    out = [
        f"Robot {r.name}: {r.dof} joints ("
        + ", ".join(f"{i + 1} {'revolute' if k == 'revolute' else 'prismatic'}" for i, k in enumerate(r.joint_types))
        + f"). J has rows [v; ω] in the {axes} axes: v is the velocity of the tool origin [m/s], ω the "
        "angular velocity [rad/s], per unit joint rate. Compact notation: cᵢ = cos θᵢ, sᵢ = sin θᵢ, "
        "cᵢⱼ = cos(θᵢ + θⱼ), sᵢⱼ = sin(θᵢ + θⱼ).",
    ]
    if h.symbolic_params:
        out.append("Link lengths and offsets are kept as symbols (their values are in the notation at the end).")
    if r.description:
        out.append(r.description)
    if r.source:
        out.append(f"Source: {r.source}")
    return out


def _jacobian_sentence(h: Handout) -> str:
    if len(h.methods) > 1:
        agree = "give this same J (checked numerically at random configurations)" if h.same_J else "do NOT agree"
        return f"The {len(h.methods)} methods above {agree}."
    return "Assembled from the steps above."


def _example_lines(ex: Example, robot_kinds: tuple[str, ...]) -> list[str]:
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
    return "\\begin{bmatrix}" + "\\\\".join(" & ".join(_fmt(x, digits) for x in row) for row in M) + "\\end{bmatrix}"


def _num_mathml(M: np.ndarray, digits: int) -> str:
    M = np.atleast_2d(M)
    rows = "".join(
        "<mtr>" + "".join(f"<mtd><mn>{_fmt(x, digits).replace('-', '−')}</mn></mtd>" for x in row) + "</mtr>"
        for row in M
    )
    return f"<mrow><mo>[</mo><mtable>{rows}</mtable><mo>]</mo></mrow>"


def _rates(v: np.ndarray, kinds: tuple[str, ...]) -> str:
    return ", ".join(_rate_text(x, k) for x, k in zip(v, kinds, strict=True))


def _example_math(ex: Example, kinds: tuple[str, ...], latex: bool) -> list[tuple[str, str]]:
    """(caption, formula) pairs of the worked example."""
    num = (lambda M, d: _num_latex(M, d)) if latex else (lambda M, d: _num_mathml(M, d))
    col = lambda v: np.asarray(v).reshape(-1, 1)  # noqa: E731
    lhs = (lambda t: t) if latex else lhs_mathml
    eq = " = " if latex else "<mo>=</mo>"
    J_q, det_q, w_q, qd, Jqd, J_inv, v, solved = (
        lhs(t)
        for t in ("J(q)", "\\det J(q)", "w(q)", "\\dot{q}", "J \\dot{q}", "J^{-1}(q)", "v", "\\dot{q} = J^{-1} v")
    )
    out = [("", f"{J_q}{eq}{num(ex.J, _digits(ex.J))}")]
    if ex.square:
        out.append(("", f"{det_q}{eq}{_scalar(ex.det, latex)}"))
    else:
        out.append(("Manipulability √det(J Jᵀ):", f"{w_q}{eq}{_scalar(ex.det, latex)}"))
    if ex.rates is not None and ex.velocity is not None:
        out.append((f"With the joint rates q̇ = ({_rates(ex.rates, kinds)}), in rad/s and m/s:", f"{qd}{eq}{num(col(ex.rates), 4)}"))
        out.append(("the tool velocity (task rows) is", f"{Jqd}{eq}{num(col(ex.velocity), 3)}"))
    if ex.inverse is not None:
        out.append(("J is square and regular here; its inverse:", f"{J_inv}{eq}{num(ex.inverse, 4)}"))
    elif ex.square:
        out.append(("J is singular here (det J = 0): it has no inverse.", ""))
    if ex.twist is not None:
        out.append(("For the tool velocity (task rows)", f"{v}{eq}{num(col(ex.twist), 3)}"))
        if ex.solved is not None:
            out.append((f"the joints must move at q̇ = ({_rates(ex.solved, kinds)}):", f"{solved}{eq}{num(col(ex.solved), 4)}"))
    return out


def _scalar(x: float, latex: bool) -> str:
    text = f"{x:.6g}" if abs(x) >= 1e-4 or x == 0 else f"{x:.3e}"
    return text if latex else f"<mn>{text.replace('-', '−')}</mn>"


# ----------------------------------------------------------------------------------- DH table
def _dh_cell(N: Notation, e: sp.Expr, angle: bool, latex: bool) -> str:
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


def _singular(N: Notation, det: Step, latex: bool) -> list[str]:
    show = N.latex if latex else N.mathml
    out = []
    for s in det.singular:
        text = f"{show(s.factor)} = 0" if latex else f"{show(s.factor)}<mo>=</mo><mn>0</mn>"
        if s.solutions is not None and len(s.joints) == 1 and s.factor != s.joints[0]:
            sol = show(sp.FiniteSet(*s.solutions))
            text += f" \\;\\Rightarrow\\; {show(s.joints[0])} \\in {sol}" if latex else f"<mo>⇒</mo>{show(s.joints[0])}<mo>∈</mo>{sol}"
        if s.kind:
            text += f" \\quad \\text{{({KIND_TEXT[s.kind]})}}" if latex else f'<mspace width="1em"/><mtext>({KIND_TEXT[s.kind]})</mtext>'
        out.append(text)
    return out


# ---------------------------------------------------------------------------------------- HTML
def _mblock(inner: str) -> str:
    return f'<math display="block"><mrow>{inner}</mrow></math>'


def render_html(h: Handout) -> str:
    """The handout as one HTML page with MathML."""
    N = _notation(h)
    out = [f"<h1>{xml_text(_title(h))}</h1>"]
    out += [f'<p class="sub">{xml_text(t, NOTE_CHARS)}</p>' for t in _intro(h)]
    out.append("<h2>1. The Denavit–Hartenberg table</h2>")
    if h.table:
        heads = "".join(f"<th><math>{lhs_mathml(c)}</math></th>" for c in DH_COLUMNS[h.table[0].convention])
        rows = []
        for r in h.table:
            cells = "".join(
                f"<td><math>{_dh_cell(N, e, a, False)}</math></td>" for e, a in zip(r.cells(), r.is_angle(), strict=True)
            )
            rows.append(f'<tr><td>{r.index}</td>{cells}<td class="name">{xml_text(r.name)}</td></tr>')
        conv = "standard (Aᵢ = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ))" if h.table[0].convention == "standard" else "modified, Craig's (Aᵢ = Rx(αᵢ₋₁) Tx(aᵢ₋₁) Rz(θᵢ) Tz(dᵢ))"
        out.append(f"<p>Convention: {conv}. Lengths in metres, angles in degrees.</p>")
        out.append(f'<table class="dh"><tr><th>i</th>{heads}<th>joint</th></tr>{"".join(rows)}</table>')
    else:
        out.append("<p>This robot has no DH table (a URDF chain): its link and joint frames come from the URDF file.</p>")
    sections = [
        ("2. Link transforms", [s for s in h.transforms if not s.key.startswith("T0_")]),
        ("3. The frames in the base: ⁰Tᵢ = A₁ A₂ ⋯ Aᵢ", [s for s in h.transforms if s.key.startswith("T0_")]),
    ]
    for head, steps in sections:
        out.append(f"<h2>{xml_text(head)}</h2>")
        out += _html_steps(steps, N)
    number = 4
    for m in h.methods:
        out.append(f"<h2>{number}. {xml_text(TITLES[m])}</h2><p>{xml_text(INTRO[m])}</p>")
        out += _html_steps(h.method_steps[m], N)
        number += 1
    out.append(f"<h2>{number}. The Jacobian and its singularities</h2>")
    for s in h.result:
        out += _html_steps([s], N)
        if s.key == "J":
            out.append(f"<p>{xml_text(_jacobian_sentence(h))}</p>")
        if s.key == "detJ" and s.singular:
            out.append("<p>Singular configurations (a factor of the determinant vanishes):</p>")
            out += [_mblock(t) for t in _singular(N, s, False)]
    out.append(f"<h2>{number + 1}. Worked example</h2>")
    for line in _example_lines(h.example, h.robot.joint_types):
        out.append(f"<p>{xml_text(line, NOTE_CHARS)}</p>")
    for cap, formula in _example_math(h.example, h.robot.joint_types, False):
        if cap:
            out.append(f'<p class="cap">{xml_text(cap)}</p>')
        if formula:
            out.append(_mblock(formula))
    out.append("<h2>Notation</h2>")
    items = N.mathml_legend_items()
    if items:
        out.append("<p>where " + ", ".join(f"<math>{i}</math>" for i in items) + "</p>")
    notes = h.notes + ([OMITTED] if any("<mo>∗</mo>" in x for x in out) else [])
    out += [f'<p class="note">Note: {xml_text(n, NOTE_CHARS)}</p>' for n in notes]
    title = xml_text(_title(h))
    head = (
        f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f'<meta name="viewport" content="width=device-width, initial-scale=1">\n<title>{title}</title>\n'
        f"<style>{CSS}</style>\n</head>\n<body>\n<main>\n"
    )
    return head + "\n".join(out) + "\n</main>\n</body>\n</html>\n"


def _notation(h: Handout) -> Notation:
    model = (h.transforms or h.result)[0].model
    return step_notation(model, names=h.names)


def _html_steps(steps: list[Step], N: Notation) -> list[str]:
    out = []
    for s in steps:
        out.append(f'<p class="cap">{s.title_html()}</p>')
        out.append(s.mathml(HTML_MATH_PX, N))
    return out


# ---------------------------------------------------------------------------------------- LaTeX
_TEX_CHARS = {
    **{c: f"\\textsubscript{{{d}}}" for c, d in zip("₀₁₂₃₄₅₆₇₈₉ᵢⱼₙ₋", "0123456789ijn-", strict=True)},
    **{c: f"\\textsuperscript{{{d}}}" for c, d in zip("⁰¹²³⁴⁵⁶⁷⁸⁹ᵀ", "0123456789T", strict=True)},
    "∂": "\\ensuremath{\\partial}",
    "θ": "\\ensuremath{\\theta}",
    "α": "\\ensuremath{\\alpha}",
    "ω": "\\ensuremath{\\omega}",
    "τ": "\\ensuremath{\\tau}",
    "×": "\\ensuremath{\\times}",
    "·": "\\ensuremath{\\cdot}",
    "∈": "\\ensuremath{\\in}",
    "⋯": "\\ensuremath{\\cdots}",
    "√": "\\ensuremath{\\surd}",
    "−": "-",
    "–": "--",
    "“": "``",
    "”": "''",
    "°": "\\ensuremath{^\\circ}",
}


def tex_text(text: str, max_chars: int = NOTE_CHARS) -> str:
    """Plain text (with the course's Unicode notation) as LaTeX text: escaped, then the symbols as commands."""
    result: list[str] = []
    for c in latex_text(text, max_chars):
        if c == "\u0307":  # combining dot above: q̇ θ̇ ḋ
            prev = result.pop() if result else ""
            base = {"\\ensuremath{\\theta}": "\\theta"}.get(prev, prev)
            result.append(f"\\ensuremath{{\\dot{{{base}}}}}")
            continue
        result.append(_TEX_CHARS.get(c, c))
    out = "".join(result).replace("ẑ", "\\ensuremath{\\hat{z}}").replace("ḋ", "\\ensuremath{\\dot{d}}")
    for cmd in ("textsubscript", "textsuperscript"):  # x\textsubscript{i}\textsubscript{j} → x\textsubscript{ij}
        out = re.sub(rf"(\\{cmd}\{{[^{{}}]*)\}}\\{cmd}\{{", r"\1", out)
        out = re.sub(rf"(\\{cmd}\{{[^{{}}]*)\}}\\{cmd}\{{", r"\1", out)
    return out


def render_tex(h: Handout) -> str:
    """The handout as a complete LaTeX document; every formula is a ``\\[ … \\]`` display."""
    N = _notation(h)
    out = [
        "\\documentclass[11pt,a4paper]{article}",
        "\\usepackage[utf8]{inputenc}",
        "\\usepackage[T1]{fontenc}",
        "\\usepackage{lmodern}",
        "\\usepackage{amsmath,amssymb}",
        "\\usepackage[margin=2cm]{geometry}",
        "\\setcounter{MaxMatrixCols}{20}",
        "\\allowdisplaybreaks",
        f"\\title{{{tex_text(_title(h), 300)}}}",
        "\\date{}",
        "\\begin{document}",
        "\\maketitle",
        "% Generated by Jacobian Lab (jacobian-lab handout).",
    ]
    out += [tex_text(t) + "\n" for t in _intro(h)]
    out.append("\\section*{1. The Denavit--Hartenberg table}")
    if h.table:
        heads = " & ".join(DH_COLUMNS[h.table[0].convention])
        rows = [
            f"{r.index} & "
            + " & ".join(_dh_cell(N, e, a, True) for e, a in zip(r.cells(), r.is_angle(), strict=True))
            + f" & \\text{{{latex_text(r.name, 120)}}}"
            for r in h.table
        ]
        conv = "standard" if h.table[0].convention == "standard" else "modified (Craig's)"
        out.append(f"Convention: {conv}. Lengths in metres, angles in degrees.")
        out += ["\\[", f"\\begin{{array}}{{c|cccc|l}} i & {heads} & \\text{{joint}} \\\\ \\hline " + " \\\\ ".join(rows) + " \\end{array}", "\\]"]
    else:
        out.append("This robot has no DH table (a URDF chain): its link and joint frames come from the URDF file.\n")
    out.append("\\section*{2. Link transforms}")
    out += _tex_steps([s for s in h.transforms if not s.key.startswith("T0_")], N)
    out.append("\\section*{3. The frames in the base}")
    out += _tex_steps([s for s in h.transforms if s.key.startswith("T0_")], N)
    number = 4
    for m in h.methods:
        out += [f"\\section*{{{number}. {tex_text(TITLES[m])}}}", tex_text(INTRO[m]) + "\n"]
        out += _tex_steps(h.method_steps[m], N)
        number += 1
    out.append(f"\\section*{{{number}. The Jacobian and its singularities}}")
    for s in h.result:
        out += _tex_steps([s], N)
        if s.key == "J":
            out.append(tex_text(_jacobian_sentence(h)) + "\n")
        if s.key == "detJ" and s.singular:
            out.append("Singular configurations (a factor of the determinant vanishes):")
            for t in _singular(N, s, True):
                out += ["\\[", t, "\\]"]
    out.append(f"\\section*{{{number + 1}. Worked example}}")
    out += [tex_text(line) + "\n" for line in _example_lines(h.example, h.robot.joint_types)]
    for cap, formula in _example_math(h.example, h.robot.joint_types, True):
        if cap:
            out.append(tex_text(cap))
        if formula:
            out += ["\\[", formula, "\\]"]
    out.append("\\section*{Notation}")
    out += ["\\[", N.latex_legend(), "\\]"]
    notes = h.notes + ([OMITTED] if any("\\ast" in x for x in out) else [])
    out += [f"Note: {tex_text(n)}\n" for n in notes]
    out.append("\\end{document}")
    return "\n".join(out) + "\n"


def _tex_steps(steps: list[Step], N: Notation) -> list[str]:
    out = []
    for s in steps:
        out.append(tex_text(s.title))
        for block in s.latex_blocks(TEX_MATH_CHARS, N):
            out += ["\\[", block, "\\]"]
    return out
