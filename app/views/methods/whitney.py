"""Whitney's columns: Jᵢ = [zᵢ₋₁ × (pₙ − pᵢ₋₁); zᵢ₋₁], the axis, the lever and the column drawn."""

from __future__ import annotations

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.i18n import Translator
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, axis_names, sub, tool_name
from .. import fmt
from ..palette import joint_color
from .common import LEVER_RGB, Drawn, MethodView, check, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot, tr: Translator) -> str:
    _ = tr.gettext
    j, i = d.joint, d.joint + 1
    z, p = axis_names(robot, j)
    pn = tool_name(robot)
    rows = []
    for c in (d.numbers[k] for k in d.axes):
        if c.kind == "revolute":
            rows += [
                row(z, vec(c.z, tr=tr)),
                row(p, vec(c.p, "m", tr)),
                row(f"{pn} − {p}", vec(c.r, "m", tr)),
                row(f"{z} × ({pn} − {p})", vec(c.linear, "m/rad", tr), ' class="res"'),
                row(fmt.escape(_("ω part: {z}").format(z=z)), vec(c.angular, tr=tr)),
            ]
        else:
            rows += [
                row(z, vec(c.z, tr=tr)),
                row(fmt.escape(_("v part: {z}").format(z=z)), vec(c.linear, "m/m", tr), ' class="res"'),
            ]
            zero = vec(np.zeros(3), tr=tr)
            said = _("{zero}: a slide does not turn the tool").format(zero=zero)
            rows.append(row(fmt.escape(_("ω part")), fmt.escape(said)))
    formula = (
        f"J{sub(i)} = [{z} × ({pn} − {p}); {z}]"
        if robot.joints[j].kind == "revolute"
        else _("J{i} = [{z}; 0] (prismatic)").format(i=sub(i), z=z)
    )
    assembled = sum(d.numbers[k].column for k in d.axes)
    ok = bool(np.allclose(assembled, snap.J_base[:, j], atol=1e-9))
    head = f'<div class="jl-formula">{fmt.escape(formula)}</div>'
    return (
        head
        + f'<table class="jl-vec">{"".join(rows)}</table>'
        + check(ok, _("equals column {i} of J(q)").format(i=i))
    )


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float, tr: Translator) -> Drawn:
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
        labels.append((tr.gettext("{z} (slide)").format(z=z), tool + c.linear * lin))
    return thick, thin, [], labels


VIEW = MethodView(METHODS["whitney"], html, draw)
