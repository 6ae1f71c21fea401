"""Typeset pieces: J, its columns, det J and the singular sets in LaTeX and MathML (compact notation).

:func:`jacobian_mathml` is what the browser app shows (the viser client has
no LaTeX renderer; Chromium renders MathML). :func:`latex_parts` and
:func:`mathml_parts` give the pieces :mod:`kinematics.symbolic.typeset.export` assembles.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ...conventions import ROW_LATEX, ROW_MATHML
from ...model import Robot
from ..core import DEFAULT_TIMEOUT, Derivation, derive
from ..singular import Determinant, determinant
from ..trig import Deadline, Progress
from .escape import NOTE_CHARS, xml_text
from .layout import MATHML_WIDTH, latex_matrix, mathml_lines, mathml_matrix, text_width, too_long
from .printing import Notation

__all__ = [
    "MATH_STYLE",
    "TypesetParts",
    "latex_parts",
    "mathml_parts",
    "jacobian_mathml",
    "jacobian_latex",
    "notation_for",
    "det_label",
]

MATH_STYLE = (
    "font-family: 'STIX Two Math', 'Cambria Math', 'Latin Modern Math', 'DejaVu Math TeX Gyre', "
    "'TeX Gyre Pagella Math', math"
)
"""CSS for ``<math>``: a font with an OpenType MATH table, without which Chromium cannot stretch brackets."""

KIND_TEXT = {"wrist": "wrist singularity", "elbow": "elbow singularity", "shoulder": "shoulder singularity"}


def notation_for(d: Derivation | Determinant, robot: Robot | None = None) -> Notation:
    """A fresh :class:`Notation` for the symbols of a derivation or determinant (with the robot's
    joint names in the legend when ``robot`` is given)."""
    return Notation(d.q, d.display, d.joint_kinds, d.params, robot.joint_names if robot is not None else ())


@dataclass
class TypesetParts:
    """Typeset pieces, each one display formula (LaTeX source or a MathML element).

    Attributes:
        matrix: ``J = [...]``.
        columns: ``J_i = [...]`` for each column.
        det: ``det J = ...`` (or det(J Jᵀ)), or ``None`` if not computed.
        singular: One formula per singular set (``factor = 0``, solutions, kind).
        legend: The notation legend (uses only the abbreviations that appear above).
        notes: Plain-text notes (snapped values, time limits, ...): escape them for the output.
        legend_items: The legend's items as separate MathML fragments (for wrapping text).
    """

    matrix: str
    columns: list[str]
    det: str | None
    singular: list[str]
    legend: str
    notes: list[str] = field(default_factory=list)
    legend_items: list[str] = field(default_factory=list)


def _lhs(frame: str, latex: bool) -> str:
    if latex:
        return "J" if frame == "base" else "J_{\\mathrm{tool}}"
    return "<mi>J</mi>" if frame == "base" else "<msub><mi>J</mi><mtext>tool</mtext></msub>"


def det_label(rows: tuple[int, ...], gram: bool, dof: int, latex: bool) -> str:
    """``det J``, ``det J_v``, ``det J_ω``, ``det J_(vx, vy, ωz)``, ``det(J Jᵀ)`` or ``det(Jᵀ J)``
    in LaTeX or MathML, for the determinant of the rows ``rows`` of a J with ``dof`` columns."""
    names = ROW_LATEX if latex else ROW_MATHML
    blocks: dict[tuple[int, ...], str] = {
        (0, 1, 2): "v" if latex else "<mi>v</mi>",
        (3, 4, 5): "\\omega" if latex else "<mi>ω</mi>",
    }
    if len(rows) == 6:
        J = "J" if latex else "<mi>J</mi>"
    else:
        sub = blocks.get(rows) or (
            "(" + ", ".join(names[r] for r in rows) + ")"
            if latex
            else "<mrow><mo>(</mo>" + "<mo>,</mo>".join(names[r] for r in rows) + "<mo>)</mo></mrow>"
        )
        J = f"J_{{{sub}}}" if latex else f"<msub><mi>J</mi>{sub}</msub>"
    if not gram:
        return f"\\det {J}" if latex else f"<mi>det</mi><mo>&#x2061;</mo>{J}"
    JT = f"{J}^{{T}}" if latex else f"<msup>{J}<mi>T</mi></msup>"
    pair = (J, JT) if len(rows) < dof else (JT, J)
    if latex:
        return f"\\det({pair[0]} {pair[1]})"
    return f"<mi>det</mi><mo>&#x2061;</mo><mo>(</mo>{pair[0]}<mo>&#x2062;</mo>{pair[1]}<mo>)</mo>"


def _matrix(
    N: Notation, M: sp.Matrix, latex: bool, deadline: Deadline | None, wrap: bool
) -> tuple[str, list[tuple[int, int]]]:
    if latex:
        return latex_matrix(N, M, deadline)
    return mathml_matrix(N, M, deadline, MATHML_WIDTH if wrap else None)


def _parts(
    d: Derivation, det: Determinant | None, latex: bool, robot: Robot, deadline: Deadline | None, wrap: bool
) -> TypesetParts:
    N = notation_for(d, robot)
    show = N.latex if latex else N.mathml
    eq = " = " if latex else "<mo>=</mo>"
    lhs = _lhs(d.frame, latex)
    body, skipped = _matrix(N, d.J, latex, deadline, wrap)
    matrix = f"{lhs}{eq}{body}"
    columns = []
    for j in range(d.J.cols):
        name = f"{lhs}_{{{j + 1}}}" if latex else f"<msub>{lhs}<mn>{j + 1}</mn></msub>"
        if latex and d.frame == "tool":
            name = f"J_{{\\mathrm{{tool}}, {j + 1}}}"
        columns.append(f"{name}{eq}{_matrix(N, d.J[:, j], latex, deadline, wrap)[0]}")
    det_text, singular, notes = None, [], list(d.notes)
    if skipped:
        notes.append(
            f"{len(skipped)} entries of J are shown as * (too long to typeset, or past the time limit); "
            "the Python and JSON exports hold them in full"
        )
    if det is not None:
        notes += list(det.notes)
        expr = det.expr
        if expr is not None and deadline is not None and deadline.expired():
            notes.append("det J is not typeset: time limit reached")
        elif expr is not None:
            det_text = f"{det_label(det.rows, det.gram, len(det.q), latex)}{eq}{show(expr)}"
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
    return TypesetParts(matrix, columns, det_text, singular, legend, notes, N.mathml_legend_items())


def _typeset(
    robot: Robot,
    frame: str,
    latex: bool,
    symbolic_params: bool,
    with_det: bool,
    timeout: float | None,
    progress: Progress | None,
    deadline: Deadline | None = None,
    wrap: bool = False,
) -> TypesetParts:
    deadline = deadline if deadline is not None else Deadline(timeout)
    d = derive(robot, frame, symbolic_params=symbolic_params, progress=progress, deadline=deadline)
    det = (
        determinant(robot, symbolic_params=symbolic_params, progress=progress, deadline=deadline)
        if with_det
        else None
    )
    return _parts(d, det, latex, robot, deadline, wrap)


def latex_parts(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic_params: bool = False,
    with_det: bool = True,
    timeout: float | None = DEFAULT_TIMEOUT,
    progress: Progress | None = None,
    deadline: Deadline | None = None,
) -> TypesetParts:
    """LaTeX source of J, its columns, det J, the singular sets and the legend (one formula each).

    ``deadline`` (shared with other steps) replaces ``timeout``: derivation, determinant and
    typesetting all stop at it (see the notes).
    """
    return _typeset(robot, frame, True, symbolic_params, with_det, timeout, progress, deadline)


def mathml_parts(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic_params: bool = False,
    with_det: bool = True,
    timeout: float | None = DEFAULT_TIMEOUT,
    progress: Progress | None = None,
    deadline: Deadline | None = None,
    wrap: bool = False,
) -> TypesetParts:
    """The same pieces as :func:`latex_parts`, as MathML elements (without ``<math>``).

    ``wrap``: break entries wider than :data:`.layout.MATHML_WIDTH` characters over lines.
    """
    return _typeset(robot, frame, False, symbolic_params, with_det, timeout, progress, deadline, wrap)


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
PANEL_WIDTH = 38
"""Width of the app's panel text in characters (380 px of the 400 px panel): a wider J is shown column
by column (the planar 3R's lettered J, 48 characters, was 455 px as one matrix)."""


def _matrix_width(robot: Robot, frame: str, symbolic_params: bool, timeout: float | None) -> float:
    """Estimated width [characters] of J with wrapped entries: the widest line of each column, summed."""
    d = derive(robot, frame, symbolic_params=symbolic_params, timeout=timeout)  # cached by mathml_parts
    N = notation_for(d, robot)
    widths = [
        max((max(map(text_width, mathml_lines(N, e))) for e in d.J[:, j] if not too_long(e)), default=1.0)
        for j in range(d.J.cols)
    ]
    return sum(widths) + 2.0 * len(widths) + 4.0


def jacobian_mathml(
    robot: Robot,
    frame: str = "base",
    timeout: float | None = DEFAULT_TIMEOUT,
    *,
    symbolic_params: bool = False,
    layout: str = "auto",
) -> str:
    """J(q) for the browser: ``<math display="block">J = […]</math>``, a legend and notes.

    Never wider than about 600 px: entries wider than :data:`.layout.MATHML_WIDTH` characters
    are broken over lines (after a term, or inside a product's parentheses), and a J whose
    columns together are wider than :data:`PANEL_WIDTH` characters is shown column by column
    (J₁ = […], J₂ = […], …). The legend is a ``<p class="jl-legend">`` of inline ``<math>``
    items (so the paragraph wraps between them; long joint names are listed there, escaped,
    never in the matrix); notes (snapped values, time limits) follow as ``<p class="jl-note">``.

    Args:
        robot: The robot.
        frame: ``"base"`` or ``"tool"``.
        timeout: Time budget [s] (the result is cached, so only the first call pays).
        symbolic_params: Keep DH lengths and offsets as symbols.
        layout: ``"matrix"`` (one J = […]), ``"columns"`` (one block per column), or ``"auto"``:
            columns when the matrix is wider than :data:`PANEL_WIDTH` characters.
    """
    if layout not in ("auto", "matrix", "columns"):
        raise ValueError(f"layout must be 'auto', 'matrix' or 'columns', got {layout!r}")
    p = mathml_parts(
        robot, frame, symbolic_params=symbolic_params, with_det=False, timeout=timeout, wrap=True
    )
    if layout == "auto":
        layout = (
            "columns" if _matrix_width(robot, frame, symbolic_params, timeout) > PANEL_WIDTH else "matrix"
        )
    if layout == "columns":
        # Left-aligned entries, so that short ones (0, 1) stay in view beside very long ones.
        columns = [column.replace("<mtd>", _LEFT_MTD) for column in p.columns]
        out = "\n".join(
            f'<math display="block" style="{MATH_STYLE}"><mrow>{column}</mrow></math>' for column in columns
        )
    else:
        out = f'<math display="block" style="{MATH_STYLE}"><mrow>{p.matrix}</mrow></math>'
    if p.legend_items:
        items = ", ".join(f'<math style="{MATH_STYLE}">{item}</math>' for item in p.legend_items)
        out += f'\n<p class="jl-legend">where {items}</p>'
    for note in p.notes:
        out += f'\n<p class="jl-note">{xml_text(note, NOTE_CHARS)}</p>'
    return out
