"""HTML of the course's extra quantities: J⁻¹ (or J⁺), the course's worked example, J_A and M(φ).

Pure functions of a snapshot and the state (the panels only assign the
strings). Numbers go through :mod:`app.views.fmt`: a blown-up J⁻¹ reads 1.23×10⁴,
never ``inf``; where J⁻¹ does not exist the panel says so in words.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np

from kinematics import Robot

from ...core.i18n import N_, Translator, translations
from ...core.snapshot import Snapshot
from ...core.snapshot.course import REPRESENTATIONS, AnalyticView, InverseView
from ...core.state import LabState
from .. import fmt
from ..palette import joint_hex, joint_text_hex
from .errata import erratum_html
from .readouts import ROW_NAMES

__all__ = ["inverse_html", "example_html", "analytic_html", "grid_html", "J_INV", "J_PLUS"]

J_INV = "J<sup>−1</sup>"
J_PLUS = "J<sup>+</sup>"
_ANGLE_NAMES = {"zyx": (N_("yaw α"), N_("pitch β"), N_("roll γ")), "zyz": ("φ", "θ", "ψ")}


def _sep(tr: Translator) -> str:
    """What separates numbers in a list: "; " where a comma is the decimal mark."""
    return "; " if tr.decimal_symbol == "," else ", "


def grid_html(
    M: np.ndarray,
    row_heads: Sequence[str],
    col_heads: Sequence[str],
    digits: int = 4,
    tr: Translator | None = None,
) -> str:
    """A small numeric matrix as a ``jl-matrix`` table (``digits`` significant digits, ×10ⁿ when large,
    written as ``tr``'s language writes numbers)."""
    values = fmt.cleaned(np.asarray(M, float).ravel().tolist(), rel=1e-12)
    cols = len(col_heads)
    head = "".join(f'<th class="col" style="border-color:#bbb">{h}</th>' for h in col_heads)
    body = "".join(
        f'<tr><th class="row">{h}</th>'
        + "".join(f"<td>{fmt.number(x, digits, tr)}</td>" for x in values[i * cols : (i + 1) * cols])
        + "</tr>"
        for i, h in enumerate(row_heads)
    )
    return f'<table class="jl-matrix"><tr><th></th>{head}</tr>{body}</table>'


@functools.lru_cache(maxsize=64)
def _joint_heads(robot: Robot) -> tuple[str, ...]:
    return tuple(
        f'<span style="color:{joint_text_hex(i)};border-bottom:3px solid {joint_hex(i)}" '
        f'title="{fmt.escape(j.name)}">q̇{i + 1}</span>'
        for i, j in enumerate(robot.joints)
    )


def inverse_html(
    view: InverseView | None,
    robot: Robot,
    rows: tuple[int, ...],
    state: LabState,
    status: str,
    tr: Translator | None = None,
) -> str:
    """J⁻¹ at q with det J beside it (a square task J), or J⁺ labelled as such; words where none exists."""
    if view is None:
        return ""
    tr = tr or translations()
    _ = tr.gettext
    tool = state.options.twist_frame == "tool"
    cols = [ROW_NAMES[r] for r in rows]
    if view.kind == "none":
        text = _(
            "{inverse} does not exist (det J = 0): the arm is singular and no joint rates produce the "
            "lost direction."
        ).format(inverse=J_INV)
        return f'<div class="jl"><div class="jl-warn">{text}</div>{_closed_html(view, robot, cols, tr)}</div>'
    name = J_INV if view.kind == "inverse" else J_PLUS
    assert view.matrix is not None
    table = grid_html(view.matrix, _joint_heads(robot), cols, tr=tr)
    if view.kind == "inverse":
        det = fmt.number(view.det or 0.0, 4, tr)
        if tool:
            head = _("<b>{name}</b> at q (tool axes) &nbsp; det J = <b>{det}</b>")
        else:
            head = _("<b>{name}</b> at q (base axes) &nbsp; det J = <b>{det}</b>")
        head = head.format(name=name, det=det)
        note = _("q̇ = {inverse} v; {inverse} = adj J / det J grows as 1/det J.").format(inverse=J_INV)
        if status != "regular":
            note += ' <span class="jl-warn">{}</span>'.format(_("det J is near 0: J⁻¹ is blowing up."))
    else:
        if tool:
            head = _("<b>{name}</b> at q (tool axes): J is {k}×{n}, not square, so it has no {inverse}")
        else:
            head = _("<b>{name}</b> at q (base axes): J is {k}×{n}, not square, so it has no {inverse}")
        head = head.format(name=name, k=len(rows), n=robot.dof, inverse=J_INV)
        note = _(
            "{plus} = Jᵀ(J Jᵀ)⁻¹ (Moore–Penrose pseudo-inverse): q̇ = {plus} v is the least-norm rate."
        ).format(plus=J_PLUS)
    if state.options.damping > 0:
        lam = fmt.number(state.options.damping, tr=tr)
        note += " " + _("The rates above use damped least squares (λ = {lam}), not {name}.").format(
            lam=lam, name=name
        )
    closed = _closed_html(view, robot, cols, tr)
    return f'<div class="jl"><div>{head}</div>{table}<div class="jl-note">{note}</div>{closed}</div>'


def _closed_html(view: InverseView, robot: Robot, cols: list[str], tr: Translator) -> str:
    """002's third way: J⁻¹ = ∂q/∂x from the closed-form inverse kinematics q = g(x), beside J⁻¹."""
    if not view.closed:
        return ""
    _ = tr.gettext
    if view.closed_form is None:
        if view.kind == "none":
            text = _(
                "The closed-form inverse kinematics gives no {inverse} here either: its derivative divides "
                "by sin q{joint} = 0."
            ).format(inverse=J_INV, joint=robot.dof)
        else:
            text = _("{inverse} from the closed-form inverse kinematics is shown in base axes only.").format(
                inverse=J_INV
            )
        return f'<div class="jl-note">{text}</div>'
    head = _(
        "<b>{inverse}</b> from the closed-form inverse kinematics (course 002, the third way): "
        "q = g(x), so {inverse} = ∂g/∂x (base axes)"
    ).format(inverse=J_INV)
    table = grid_html(view.closed_form, _joint_heads(robot), cols, tr=tr)
    if view.closed_gap is not None:
        note = _("The same matrix as the inverse of J above: the largest difference is {gap}.").format(
            gap=fmt.number(view.closed_gap, 2, tr)
        )
    else:
        note = ""
    return f'<div class="jl-closed"><div>{head}</div>{table}<div class="jl-note">{note}</div></div>'


def _vector(values: np.ndarray, units: list[str], tr: Translator, digits: int = 4) -> str:
    parts = [fmt.quantity(x, u, digits, tr) for x, u in zip(fmt.cleaned(values), units, strict=True)]
    return "(" + _sep(tr).join(parts) + ")"


def example_html(
    snap: Snapshot,
    state: LabState,
    rates: np.ndarray | None,
    start_name: str,
    question: bool,
    tr: Translator | None = None,
) -> str:
    """The course's worked example at this q: its q̇ mapped by J (v = J q̇), and at the course's question
    configuration the question answered (J, det J and v; J⁻¹ is shown above)."""
    if rates is None or len(rates) != state.robot.dof:
        return ""
    tr = tr or translations()
    _ = tr.gettext
    robot, rows = state.robot, list(snap.rows)
    kinds = [j.kind for j in robot.joints]
    shown = np.array([math.degrees(x) if k == "revolute" else x for x, k in zip(rates, kinds, strict=True)])
    rate_units = ["°/s" if k == "revolute" else "m/s" for k in kinds]
    v = (snap.J_base @ rates)[rows]
    v_shown = np.array([x if r < 3 else math.degrees(x) for x, r in zip(v, rows, strict=True)])
    v_units = ["m/s" if r < 3 else "°/s" for r in rows]
    q_shown = [math.degrees(x) if k == "revolute" else x for x, k in zip(snap.q, kinds, strict=True)]
    q_text = _vector(np.array(q_shown), ["°" if k == "revolute" else "m" for k in kinds], tr)
    parts = []
    if question:
        parts.append(_("<b>The course's question, q = {q}, answered:</b>").format(q=q_text))
        J_task = snap.J_base[rows]
        heads = [f"q{i + 1}" for i in range(robot.dof)]
        parts.append(grid_html(J_task, [ROW_NAMES[r] for r in rows], heads, tr=tr))
        if snap.det is not None:
            det = fmt.number(snap.det, 4, tr)
            parts.append(_("det J = <b>{det}</b>; {inverse} is above.").format(det=det, inverse=J_INV))
    elif start_name == state.configuration:
        parts.append(
            _("<b>The course's worked example</b> at the course's example configuration, q = {q}:").format(
                q=q_text
            )
        )
    else:
        parts.append(_("<b>The course's worked example</b> at this q, q = {q}:").format(q=q_text))
    parts.append(
        _("its q̇ = {rates} gives v = J q̇ = <b>{v}</b>.").format(
            rates=_vector(shown, rate_units, tr), v=_vector(v_shown, v_units, tr, 5)
        )
    )
    return '<div class="jl jl-example">' + "<br>".join(parts) + "</div>"


def analytic_html(
    view: AnalyticView | None, robot: Robot, rank: int, rows: tuple[int, ...], tr: Translator | None = None
) -> str:
    """φ, M(φ) (ω = M(φ) φ̇) and J_A = diag(I, M(φ)⁻¹) J, or why J_A does not exist at this orientation."""
    if view is None:
        return ""
    tr = tr or translations()
    _ = tr.gettext
    names = [_(n) for n in _ANGLE_NAMES[view.convention]]
    phi = _sep(tr).join(
        f"{n} = {fmt.quantity(math.degrees(x), '°', 4, tr)}" for n, x in zip(names, view.phi, strict=True)
    )
    label = _(REPRESENTATIONS[view.convention])
    parts = [f"<div><b>{fmt.escape(label)}</b>: φ = ({phi})</div>"]
    m_heads = ["ω<sub>x</sub>", "ω<sub>y</sub>", "ω<sub>z</sub>"]
    rate_heads = [f"{n.split()[-1]}̇" for n in names]
    m_note = _("M(φ), with ω = M(φ) φ̇ (kinematics.analytic_jacobian calls it B(φ)); det M = {det}")
    parts.append(
        f'<div class="jl-note">{m_note.format(det=fmt.number(view.det_M, 4, tr))}</div>'
        + grid_html(view.M, m_heads, rate_heads, 3, tr)
    )
    parts.append(erratum_html("M", tr))
    if view.singular:
        which = _("pitch β = ±90°") if view.convention == "zyx" else _("θ = 0 or 180°")
        text = _(
            "Representation singular ({which}): M(φ) has no inverse, so J<sub>A</sub> does not exist "
            "here — while the geometric J is fine (rank {rank} of {most}). A singularity of the angles "
            "chosen, not of the arm."
        ).format(which=which, rank=rank, most=min(len(rows), robot.dof))
        parts.append(f'<div class="jl-warn">{text}</div>')
        if view.regular_instead:
            other = fmt.escape(_(REPRESENTATIONS[view.regular_instead]))
            text = _(
                "{representation} is regular at this orientation: the button below shows J<sub>A</sub> "
                "with it."
            ).format(representation=other)
            parts.append(f'<div class="jl-note">{text}</div>')
    else:
        assert view.J_A is not None
        row_heads = [*ROW_NAMES[:3], *rate_heads]
        cols = [f"q{i + 1}" for i in range(robot.dof)]
        text = _("J<sub>A</sub> = diag(I, M(φ)<sup>−1</sup>) J, rows [v; φ̇] (base axes):")
        parts.append(f'<div class="jl-note">{text}</div>' + grid_html(view.J_A, row_heads, cols, 3, tr))
    return f'<div class="jl jl-analytic">{"".join(parts)}</div>'
