"""Typeset pieces: J, its columns, det J and the singular sets in LaTeX and MathML (compact notation).

:func:`jacobian_mathml` is what the browser app shows (the viser client has
no LaTeX renderer; Chromium renders MathML). :func:`latex_parts` and
:func:`mathml_parts` give the pieces :mod:`kinematics.export` assembles.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from html import escape

import sympy as sp

from ..model import Robot
from .core import DEFAULT_TIMEOUT, Derivation, derive
from .printing import Notation
from .singular import Determinant, determinant
from .trig import Progress

__all__ = [
    "MATH_STYLE",
    "TypesetParts",
    "latex_parts",
    "mathml_parts",
    "jacobian_mathml",
    "jacobian_latex",
    "notation_for",
]

MATH_STYLE = (
    "font-family: 'STIX Two Math', 'Cambria Math', 'Latin Modern Math', 'DejaVu Math TeX Gyre', "
    "'TeX Gyre Pagella Math', math"
)
"""CSS for ``<math>``: a font with an OpenType MATH table, without which Chromium cannot stretch brackets."""

KIND_TEXT = {"wrist": "wrist singularity", "elbow": "elbow singularity", "shoulder": "shoulder singularity"}


def notation_for(d: Derivation | Determinant) -> Notation:
    """A fresh :class:`Notation` for the symbols of a derivation or determinant."""
    return Notation(d.q, d.display, d.joint_kinds, d.params)


@dataclass
class TypesetParts:
    """Typeset pieces, each one display formula (LaTeX source or a MathML element).

    Attributes:
        matrix: ``J = [...]``.
        columns: ``J_i = [...]`` for each column.
        det: ``det J = ...`` (or det(J Jᵀ)), or ``None`` if not computed.
        singular: One formula per singular set (``factor = 0``, solutions, kind).
        legend: The notation legend (uses only the abbreviations that appear above).
        notes: Plain-text notes (time limits, identically zero determinants, ...).
    """

    matrix: str
    columns: list[str]
    det: str | None
    singular: list[str]
    legend: str
    notes: list[str] = field(default_factory=list)


def _lhs(frame: str, latex: bool) -> str:
    if latex:
        return "J" if frame == "base" else "J_{\\mathrm{tool}}"
    return "<mi>J</mi>" if frame == "base" else "<msub><mi>J</mi><mtext>tool</mtext></msub>"


_ROWS_LATEX = ("v_{x}", "v_{y}", "v_{z}", "\\omega_{x}", "\\omega_{y}", "\\omega_{z}")
_ROWS_MATHML = tuple(f"<msub><mi>{a}</mi><mi>{b}</mi></msub>" for a in ("v", "ω") for b in "xyz")


def _det_label(det: Determinant, latex: bool) -> str:
    """``det J``, ``det J_v``, ``det J_ω``, ``det J_(vx, vy, ωz)``, ``det(J Jᵀ)`` or ``det(Jᵀ J)``."""
    rows = det.rows
    names = _ROWS_LATEX if latex else _ROWS_MATHML
    blocks = {(0, 1, 2): "v" if latex else "<mi>v</mi>", (3, 4, 5): "\\omega" if latex else "<mi>ω</mi>"}
    if len(rows) == 6:
        J = "J" if latex else "<mi>J</mi>"
    else:
        sub = blocks.get(rows) or (
            "(" + ", ".join(names[r] for r in rows) + ")"
            if latex
            else "<mrow><mo>(</mo>" + "<mo>,</mo>".join(names[r] for r in rows) + "<mo>)</mo></mrow>"
        )
        J = f"J_{{{sub}}}" if latex else f"<msub><mi>J</mi>{sub}</msub>"
    if not det.gram:
        return f"\\det {J}" if latex else f"<mi>det</mi><mo>&#x2061;</mo>{J}"
    JT = f"{J}^{{T}}" if latex else f"<msup>{J}<mi>T</mi></msup>"
    pair = (J, JT) if len(rows) < len(det.q) else (JT, J)
    if latex:
        return f"\\det({pair[0]} {pair[1]})"
    return f"<mi>det</mi><mo>&#x2061;</mo><mo>(</mo>{pair[0]}<mo>&#x2062;</mo>{pair[1]}<mo>)</mo>"


def _parts(d: Derivation, det: Determinant | None, latex: bool) -> TypesetParts:
    N = notation_for(d)
    show = N.latex if latex else N.mathml
    eq = " = " if latex else "<mo>=</mo>"
    lhs = _lhs(d.frame, latex)
    matrix = f"{lhs}{eq}{show(d.J)}"
    columns = []
    for j in range(d.J.cols):
        name = f"{lhs}_{{{j + 1}}}" if latex else f"<msub>{lhs}<mn>{j + 1}</mn></msub>"
        if latex and d.frame == "tool":
            name = f"J_{{\\mathrm{{tool}}, {j + 1}}}"
        columns.append(f"{name}{eq}{show(d.J[:, j])}")
    det_text, singular, notes = None, [], list(d.notes)
    if det is not None:
        notes += list(det.notes)
        expr = det.expr
        if expr is not None:
            det_text = f"{_det_label(det, latex)}{eq}{show(expr)}"
        for s in det.singular_sets:
            text = f"{show(s.factor)}{eq}{'0' if latex else '<mn>0</mn>'}"
            if s.solutions is not None and len(s.joints) == 1 and s.factor != s.joints[0]:
                sol = sp.FiniteSet(*s.solutions)
                text += (
                    f" \\;\\Rightarrow\\; {show(s.joints[0])} \\in {show(sol)}"
                    if latex
                    else f"<mo>&#x21D2;</mo>{show(s.joints[0])}<mo>&#x2208;</mo>{show(sol)}"
                )
            if s.kind:
                text += (
                    f" \\quad \\text{{({KIND_TEXT[s.kind]})}}"
                    if latex
                    else f'<mspace width="1em"/><mtext>({KIND_TEXT[s.kind]})</mtext>'
                )
            singular.append(text)
    legend = N.latex_legend() if latex else N.mathml_legend()
    return TypesetParts(matrix, columns, det_text, singular, legend, notes)


def _typeset(
    robot: Robot,
    frame: str,
    latex: bool,
    symbolic_params: bool,
    with_det: bool,
    timeout: float | None,
    progress: Progress | None,
) -> TypesetParts:
    d = derive(robot, frame, symbolic_params=symbolic_params, timeout=timeout, progress=progress)
    det = (
        determinant(robot, symbolic_params=symbolic_params, timeout=timeout, progress=progress)
        if with_det
        else None
    )
    return _parts(d, det, latex=latex)


def latex_parts(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic_params: bool = False,
    with_det: bool = True,
    timeout: float | None = DEFAULT_TIMEOUT,
    progress: Progress | None = None,
) -> TypesetParts:
    """LaTeX source of J, its columns, det J, the singular sets and the legend (one formula each)."""
    return _typeset(robot, frame, True, symbolic_params, with_det, timeout, progress)


def mathml_parts(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic_params: bool = False,
    with_det: bool = True,
    timeout: float | None = DEFAULT_TIMEOUT,
    progress: Progress | None = None,
) -> TypesetParts:
    """The same pieces as :func:`latex_parts`, as MathML elements (without ``<math>``)."""
    return _typeset(robot, frame, False, symbolic_params, with_det, timeout, progress)


def jacobian_latex(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic_params: bool = False,
    timeout: float | None = DEFAULT_TIMEOUT,
) -> str:
    """LaTeX ``J = \\begin{bmatrix}…\\end{bmatrix}`` in compact notation (no legend)."""
    return latex_parts(robot, frame, symbolic_params=symbolic_params, with_det=False, timeout=timeout).matrix


_LEFT_MTD = '<mtd style="text-align: left">'
WIDE_MATHML = 15_000
"""Above this many characters of MathML, ``layout="auto"`` shows J column by column."""


def jacobian_mathml(
    robot: Robot,
    frame: str = "base",
    timeout: float | None = DEFAULT_TIMEOUT,
    *,
    symbolic_params: bool = False,
    layout: str = "auto",
) -> str:
    """J(q) for the browser: ``<math display="block">J = […]</math>`` and a legend line.

    The legend is a ``<p class="jl-legend">`` holding an inline ``<math>``; notes (for example
    entries left unsimplified at the time limit) follow as ``<p class="jl-note">``.

    Args:
        robot: The robot.
        frame: ``"base"`` or ``"tool"``.
        timeout: Simplification budget [s] (the result is cached, so only the first call pays).
        symbolic_params: Keep DH lengths and offsets as symbols.
        layout: ``"matrix"`` (one J = […]), ``"columns"`` (J₁ = […], J₂ = […], … one per
            block, for arms whose whole matrix is too wide to read), or ``"auto"``: columns
            when the matrix exceeds :data:`WIDE_MATHML` characters (the 7-joint arms).
    """
    if layout not in ("auto", "matrix", "columns"):
        raise ValueError(f"layout must be 'auto', 'matrix' or 'columns', got {layout!r}")
    p = mathml_parts(robot, frame, symbolic_params=symbolic_params, with_det=False, timeout=timeout)
    if layout == "columns" or (layout == "auto" and len(p.matrix) > WIDE_MATHML):
        # Left-aligned entries, so that short ones (0, 1) stay in view beside very long ones.
        columns = [column.replace("<mtd>", _LEFT_MTD) for column in p.columns]
        out = "\n".join(
            f'<math display="block" style="{MATH_STYLE}"><mrow>{column}</mrow></math>' for column in columns
        )
    else:
        out = f'<math display="block" style="{MATH_STYLE}"><mrow>{p.matrix}</mrow></math>'
    if p.legend:
        out += f'\n<p class="jl-legend"><math style="{MATH_STYLE}">{p.legend}</math></p>'
    for note in p.notes:
        out += f'\n<p class="jl-note">{escape(note)}</p>'
    return out
