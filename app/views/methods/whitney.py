"""Whitney's columns: Jᵢ = [zᵢ₋₁ × (pₙ − pᵢ₋₁); zᵢ₋₁], the axis, the lever and the column drawn."""

from __future__ import annotations

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, axis_names, sub, tool_name
from ..palette import joint_color
from .common import LEVER_RGB, Drawn, MethodView, check, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    j, i = d.joint, d.joint + 1
    z, p = axis_names(robot, j)
    pn = tool_name(robot)
    rows = []
    for c in (d.numbers[k] for k in d.axes):
        if c.kind == "revolute":
            rows += [
                row(z, vec(c.z)),
                row(p, vec(c.p, "m")),
                row(f"{pn} − {p}", vec(c.r, "m")),
                row(f"{z} × ({pn} − {p})", vec(c.linear, "m/rad"), ' class="res"'),
                row(f"ω part: {z}", vec(c.angular)),
            ]
        else:
            rows += [row(z, vec(c.z)), row(f"v part: {z}", vec(c.linear, "m/m"), ' class="res"')]
            rows.append(row("ω part", "(0, 0, 0): a slide does not turn the tool"))
    formula = (
        f"J{sub(i)} = [{z} × ({pn} − {p}); {z}]"
        if robot.joints[j].kind == "revolute"
        else f"J{sub(i)} = [{z}; 0] (prismatic)"
    )
    assembled = sum(d.numbers[k].column for k in d.axes)
    ok = bool(np.allclose(assembled, snap.J_base[:, j], atol=1e-9))
    return f'<div class="jl-formula">{formula}</div><table class="jl-vec">{"".join(rows)}</table>' + check(
        ok, f"equals column {i} of J(q)"
    )


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float) -> Drawn:
    z, p = axis_names(robot, d.joint)
    pn = tool_name(robot)
    c = d.numbers[d.axes[0]]
    rgb = joint_color(d.joint)
    tool = c.p + c.r
    thick = [(tool, c.linear * lin, rgb), (c.p, c.z * unit, rgb)]
    labels = [(z, c.p + c.z * unit)]
    thin = []
    if c.kind == "revolute":  # the lever pₙ − pᵢ₋₁ is a vector too: an arrow from the axis to the tool
        thin.append((c.p, c.r, LEVER_RGB))
        labels.append((f"{pn} − {p}", (c.p + tool) / 2))
        labels.append((f"{z} × ({pn} − {p})", tool + c.linear * lin))
    else:
        labels.append((f"{z} (slide)", tool + c.linear * lin))
    return thick, thin, [], labels


VIEW = MethodView(METHODS["whitney"], html, draw)
