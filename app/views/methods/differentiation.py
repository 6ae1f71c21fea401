"""Differentiation: ∂p/∂qᵢ and ω from (∂R/∂qᵢ) Rᵀ, the tool's path as qᵢ alone moves and its tangent."""

from __future__ import annotations

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.i18n import Translator
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, sub
from .. import fmt
from ..palette import joint_color
from .common import Drawn, MethodView, check, note, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot, tr: Translator) -> str:
    _ = tr.gettext
    j, i = d.joint, d.joint + 1
    dv = d.numbers.derivative
    unit = "m/rad" if robot.joints[j].kind == "revolute" else "m/m"
    col = snap.J_base[:, j]
    ok = np.allclose(dv.column, col, atol=1e-6 * max(1.0, float(np.abs(col).max())))
    q, dp = f"q{sub(i)}", f"∂p/∂q{sub(i)}"
    formula = _("{J} = [{dp}; ω from {S}]").format(J=f"J{sub(i)}", dp=dp, S=f"(∂R/∂q{sub(i)}) Rᵀ")
    said = _(
        "Drawn: the path the tool traces when only {q} moves (±30°), and its tangent {dp}: column {i} of J."
    )
    return (
        f'<div class="jl-formula">{fmt.escape(formula)}</div>'
        + '<table class="jl-vec">'
        + row(dp, vec(dv.dp, unit, tr), ' class="res"')
        + row(f"(∂R/∂q{sub(i)}) Rᵀ → ω", vec(dv.omega, tr=tr))
        + "</table>"
        + note(said.format(q=q, dp=dp, i=i))
        + check(bool(ok), _("central differences equal column {i} of J(q)").format(i=i))
    )


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float, tr: Translator) -> Drawn:
    rgb = joint_color(d.joint)
    tool = snap.tool_point
    path, dp = d.numbers.path, d.numbers.derivative.dp
    lines = [(a, b, rgb) for a, b in zip(path[:-1], path[1:], strict=True)]
    label = f"∂p/∂q{sub(d.joint + 1)}"
    return [(tool, dp * lin, rgb)], [], lines, [(label, tool + dp * lin)]


VIEW = MethodView(METHODS["differentiation"], html, draw)
