"""The motion readout at the top of the panel: while a motion plays (and after it stops), the joint
rates, κ and σmin as numbers beside the arm, readable from the back row (the charts below are the
history; these are the values now).

A pure function of the state: :func:`live_html` returns "" when no motion has traced anything.
"""

from __future__ import annotations

import math

import numpy as np

from kinematics.analysis import task_rows
from kinematics.conventions import ROW_HTML

from ...core.i18n import Translator, translations
from ...core.motion_rules import redundancy_rows
from ...core.self_motion import is_null_motion
from ...core.state import LabState
from ...core.tool_path import is_tool_path
from .. import fmt
from ..palette import joint_text_hex

__all__ = ["live_html", "shows_motion"]


def _doing(kind: str, tr: Translator) -> str:
    _ = tr.gettext
    if kind == "resolved_rate":
        return _("holding v")
    if kind == "climb":
        return _("climbing w")
    if kind == "tool_path":
        return _("following the path y(t)")
    if kind == "null":
        return _("the null motion (Ker J)")
    if kind == "path":
        return _("to the nearest singularity")
    return _("moving at q̇") if kind == "joints" else ""


def shows_motion(state: LabState) -> bool:
    """Whether the readout is on screen: a motion plays or has stopped, and has traced two steps."""
    trace = state.motion.trace
    return (state.playing or bool(state.stopped)) and trace is not None and len(trace) >= 2


def live_html(state: LabState, tr: Translator | None = None, lines: str = "") -> str:
    """Rates [°/s | m/s], κ, σmin, the motion's time and its pace, then ``lines`` (the status's lines,
    :func:`app.views.panel.readouts.status_lines`: the lost direction, why it stopped); "" when nothing
    is traced."""
    tr = tr or translations()
    _ = tr.gettext
    m = state.motion
    trace = m.trace
    if trace is None or len(trace) < 2:
        return ""
    qd = np.asarray(trace.qd[-1], dtype=float)
    cells = []
    for i, joint in enumerate(state.robot.joints):
        revolute = joint.kind == "revolute"
        value = math.degrees(qd[i]) if revolute else float(qd[i])
        unit = "°/s" if revolute else "m/s"
        cells.append(
            f'<div class="jl-live-rate" style="color:{joint_text_hex(i)}"><span>q̇{_sub(i + 1)}</span>'
            f"<b>{fmt.fixed(value, 1 if revolute else 3, tr)}</b><small>{unit}</small></div>"
        )
    kappa = float(trace.kappa[-1])
    doing = _doing("null" if is_null_motion(m) else "tool_path" if is_tool_path(m) else m.kind, tr)
    state_word = _("playing") if state.playing else _("paused") if not state.stopped else _("stopped")
    slowed = _("slowed ×{factor} near the singularity").format(factor=fmt.number(m.pace, 2, tr))
    pace = (
        f' · <span class="jl-live-slow">{slowed}</span>'
        if state.playing and m.kind == "resolved_rate" and m.pace < 0.95
        else ""
    )
    # The climb measures the rows it holds (the 3R planar arm: vx, vy), not the banner's task rows: say so.
    held = redundancy_rows(state.robot) if m.kind == "climb" else None
    rows = (
        f"<small>({', '.join(ROW_HTML[r] for r in held)})</small>"
        if held is not None and held != task_rows(state.robot)
        else ""
    )
    head = (
        f'<div class="jl-live-head"><span>κ{rows} <b>{fmt.number(kappa, tr=tr)}</b></span>'
        f"<span>σ<sub>min</sub> <b>{fmt.number(float(trace.sigma_min[-1]), tr=tr)}</b></span>"
        f"<span>t <b>{fmt.fixed(state.time, 2, tr)}</b> s</span></div>"
    )
    what = _("{state}: {doing}").format(state=state_word, doing=doing) if doing else state_word
    if is_tool_path(m) and not state.playing and state.stopped:  # played out: say so, not "following"
        what = _("the path y(t) was followed to its end")
    foot = f'<div class="jl-live-foot">{what}{pace}</div>'
    more = f'<div class="jl-live-lines">{lines}</div>' if lines and shows_motion(state) else ""
    rates = f'<div class="jl-live-rates">{"".join(cells)}</div>'
    return f'<div class="jl jl-live">{head}{rates}{foot}{more}</div>'


def _sub(n: int) -> str:
    return str(n).translate(str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉"))
