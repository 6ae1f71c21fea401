"""HTML of the acceleration map in the v = J q̇ tab: ẍ = J q̈ + J̇ q̇ term by term, and 000's per-joint
J̇ᵢ beside the full J̇ (equal when one joint moves, not when several do, with the difference).

Pure functions of a snapshot and the state (the panel only assigns the string).
"""

from __future__ import annotations

import math

import numpy as np

from kinematics import Robot

from ...core.i18n import Translator, translations
from ...core.snapshot import Snapshot
from ...core.state import LabState
from .. import fmt
from .course import grid_html
from .errata import erratum_html
from .readouts import ROW_NAMES

__all__ = ["accel_html"]

_HEAD = "".join(f"<th>{n}̇<sub>{a}</sub></th>" for n in ("v", "ω") for a in "xyz")


def _rows(rows: list[tuple[str, np.ndarray, str]], tr: Translator) -> str:
    """Accelerations (6,) as table rows: v̇ in m/s², ω̇ in °/s²."""
    out = []
    for label, a, css in rows:
        shown = fmt.cleaned([a[r] if r < 3 else math.degrees(a[r]) for r in range(6)])
        cells = "".join(f"<td>{fmt.number(x, tr=tr)}</td>" for x in shown)
        out.append(f'<tr class="{css}"><th class="rowname">{label}</th>{cells}</tr>')
    return f'<table class="jl-vec"><tr><th></th>{_HEAD}</tr>{"".join(out)}</table>'


def accel_html(snap: Snapshot, state: LabState, tr: Translator | None = None) -> str:
    """ẍ = J q̈ + J̇ q̇ (each term, and the sum when q̈ ≠ 0) and, while joints move, 000's per-joint
    terms J̇ᵢ q̇ᵢ against J̇ q̇ with their difference, then J̇ and 000's columns J̇ᵢ side by side."""
    if snap.jdot_qd is None or snap.j_qdd is None or snap.tool_accel is None:
        return ""
    moving, accelerating = bool(np.any(state.qd)), bool(np.any(state.qdd))
    if not (moving or accelerating):
        return ""
    tr = tr or translations()
    _ = tr.gettext
    scale = fmt.quantity(0.5, "m", tr=tr)
    if accelerating:
        table = _rows(
            [("J q̈", snap.j_qdd, "jqdd"), ("J̇ q̇", snap.jdot_qd, "accel"), ("ẍ", snap.tool_accel, "")], tr
        )
        note = _(
            "ẍ = J q̈ + J̇ q̇: J q̈ comes from the joint accelerations q̈, J̇ q̇ from the joint rates q̇ (the "
            "tool accelerates even when every joint turns steadily). v̇ in m/s², ω̇ in °/s², base axes; "
            "arrows at the tool: magenta J q̈, violet J̇ q̇ (drawn {scale} per m/s²)."
        ).format(scale=scale)
    else:
        table = _rows([("J̇ q̇", snap.jdot_qd, "accel")], tr)
        note = _(
            "ẍ = J q̈ + J̇ q̇; here q̈ = 0 (constant rates), so ẍ = J̇ q̇: the tool accelerates although every "
            "joint turns steadily. v̇ in m/s², ω̇ in °/s², base axes; violet arrow at the tool (drawn {scale} "
            "per m/s²)."
        ).format(scale=scale)
    parts = [table, f'<div class="jl-note">{note}</div>']
    if moving:
        parts.append(_per_joint_html(snap, state, tr))
    parts.append(erratum_html("jdot", tr))
    return f'<div class="jl jl-accel">{"".join(parts)}</div>'


def _per_joint_html(snap: Snapshot, state: LabState, tr: Translator) -> str:
    """000's J̇ᵢ q̇ᵢ, one row per moving joint, their sum, J̇ q̇ and the difference; J̇ beside 000's J̇ᵢ."""
    assert snap.jdot_terms is not None and snap.jdot_gap is not None and snap.jdot_qd is not None
    assert snap.jdot is not None and snap.jdot_alone is not None
    _ = tr.gettext
    robot: Robot = state.robot
    moving = [i for i in range(robot.dof) if state.qd[i] != 0]
    rows = [(f"J̇<sub>{i + 1}</sub> q̇<sub>{i + 1}</sub>", snap.jdot_terms[:, i], "term") for i in moving]
    if len(moving) > 1:
        rows.append(("Σ J̇<sub>i</sub> q̇<sub>i</sub>", snap.jdot_terms.sum(axis=1), "term"))
    rows += [("J̇ q̇", snap.jdot_qd, "accel"), ("J̇ q̇ − Σ", snap.jdot_gap, "gap")]
    head = _("Course 000 (§7) derives J̇ᵢ for joint i moving alone; its terms J̇ᵢ q̇ᵢ beside J̇ q̇:")
    if len(moving) == 1:
        say = _(
            "Only {joint} moves: 000's J̇ᵢ q̇ᵢ equals J̇ q̇, the difference is zero (column {column} of J̇ "
            "is 000's J̇ᵢ)."
        ).format(joint=fmt.escape(robot.joints[moving[0]].name), column=moving[0] + 1)
        css = "jl-note"
    else:
        gap = float(np.linalg.norm(snap.jdot_gap[:3]))
        say = tr.ngettext(
            "{count} joint moves: the sum of 000's J̇ᵢ q̇ᵢ misses {gap} of the tool's acceleration, because "
            "zᵢ₋₁ turns and pₙ − pᵢ₋₁ changes with the other joints.",
            "{count} joints move: the sum of 000's J̇ᵢ q̇ᵢ misses {gap} of the tool's acceleration, because "
            "zᵢ₋₁ turns and pₙ − pᵢ₋₁ changes with the other joints.",
            len(moving),
        ).format(count=len(moving), gap=fmt.quantity(gap, "m/s²", tr=tr))
        css = "jl-warn"
    cols = [f"q{i + 1}" for i in range(robot.dof)]
    heads = list(ROW_NAMES[:6])
    summary = _("J̇ beside 000's columns J̇ᵢ (SI units)")
    grids = (
        f"<details><summary>{summary}</summary>"
        f'<div class="jl-note">J̇</div>{grid_html(snap.jdot, heads, cols, 3, tr)}'
        f'<div class="jl-note">[J̇<sub>1</sub> … J̇<sub>{robot.dof}</sub>] (000)</div>'
        f"{grid_html(snap.jdot_alone, heads, cols, 3, tr)}</details>"
    )
    return f'<div class="jl-note">{head}</div>{_rows(rows, tr)}<div class="{css}">{say}</div>{grids}'
