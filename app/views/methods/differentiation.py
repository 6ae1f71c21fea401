"""Differentiation: ∂p/∂qᵢ and ω from (∂R/∂qᵢ) Rᵀ, the tool's path as qᵢ alone moves and its tangent."""

from __future__ import annotations

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, sub
from ..palette import joint_color
from .common import Drawn, MethodView, check, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    j, i = d.joint, d.joint + 1
    dv = d.numbers.derivative
    unit = "m/rad" if robot.joints[j].kind == "revolute" else "m/m"
    col = snap.J_base[:, j]
    ok = np.allclose(dv.column, col, atol=1e-6 * max(1.0, float(np.abs(col).max())))
    return (
        f'<div class="jl-formula">J{sub(i)} = [∂p/∂q{sub(i)}; ω from (∂R/∂q{sub(i)}) Rᵀ]</div>'
        + '<table class="jl-vec">'
        + row(f"∂p/∂q{sub(i)}", vec(dv.dp, unit), ' class="res"')
        + row(f"(∂R/∂q{sub(i)}) Rᵀ → ω", vec(dv.omega))
        + "</table>"
        + '<div class="jl-note">Drawn: the path the tool traces when only '
        f"q{sub(i)} moves (±30°), and its tangent ∂p/∂q{sub(i)}: column {i} of J.</div>"
        + check(bool(ok), f"central differences equal column {i} of J(q)")
    )


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float) -> Drawn:
    rgb = joint_color(d.joint)
    tool = snap.tool_point
    path, dp = d.numbers.path, d.numbers.derivative.dp
    lines = [(a, b, rgb) for a, b in zip(path[:-1], path[1:], strict=True)]
    label = f"∂p/∂q{sub(d.joint + 1)}"
    return [(tool, dp * lin, rgb)], [], lines, [(label, tool + dp * lin)]


VIEW = MethodView(METHODS["differentiation"], html, draw)
