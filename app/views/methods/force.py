"""Force propagation: the tool wrench carried inward to τᵢ (τ = Jᵀ F), the force, lever and axis drawn."""

from __future__ import annotations

import math

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, axis_names, sub, tool_name
from .. import fmt
from ..palette import FORCE_RGB, joint_color
from .common import LEVER_RGB, Drawn, MethodView, check, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    j, i = d.joint, d.joint + 1
    z, p = axis_names(robot, j)
    pn = tool_name(robot)
    wrench, loads = d.inputs, d.numbers
    load = next(x for x in loads if x.axis == d.axes[0])
    revolute = robot.joints[j].kind == "revolute"
    formula = (
        f"τ{sub(i)} = {z} · (n + ({pn} − {p}) × f)"
        if revolute
        else f"τ{sub(i)} = {z} · f (a slide feels the force along it)"
    )
    tau = snap.J_base.T @ wrench
    rows = [row("f (at the tool)", vec(wrench[:3], "N")), row("n (at the tool)", vec(wrench[3:], "N·m"))]
    if revolute:
        rows.append(row(f"moment about {p}", vec(load.moment, "N·m")))
    total = sum(x.multiplier * x.load for x in loads if x.joint == j)
    rows.append(row(f"τ{sub(i)}", fmt.quantity(total, "N·m" if revolute else "N"), ' class="res"'))
    out = f'<div class="jl-formula">{formula}</div><table class="jl-vec">{"".join(rows)}</table>'
    ok = math.isclose(total, float(tau[j]), abs_tol=1e-9)
    out += check(ok, f"equals (Jᵀ F){sub(i)}: column {i} of J dotted with F — the transpose view")
    out += (
        '<div class="jl-note">The wrench is carried inward from the tool: go down from the last joint.</div>'
    )
    if d.assumed:
        out += (
            '<div class="jl-note">The force in “τ = JᵀF” is zero: shown for 1 N along the base x axis. '
            "Set a force there to use yours.</div>"
        )
    return out


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float) -> Drawn:
    load = next(x for x in d.numbers if x.axis == d.axes[0])
    tool = snap.tool_point
    f = d.inputs[:3]
    scale = unit / max(float(np.linalg.norm(f)), 1e-9) if np.any(f) else 0.0
    thick = [(tool, f * scale, FORCE_RGB)]
    rgb = joint_color(d.joint)
    z, _ = axis_names(robot, d.joint)
    thin = [(load.p, load.z * unit * np.sign(load.load or 1.0), rgb)]
    if load.kind == "revolute":
        thin.append((load.p, tool - load.p, LEVER_RGB))
    # Beside the axis, a quarter of the way along the lever: clear of the joint's own label.
    where = load.p + 0.25 * (tool - load.p) + 0.5 * unit * load.z
    labels = [("F", tool + f * scale), (f"τ{sub(d.joint + 1)} about {z}", where)]
    return thick, thin, [], labels


VIEW = MethodView(METHODS["force"], html, draw)
