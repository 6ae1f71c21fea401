"""Force propagation: the tool wrench carried inward to τᵢ (τ = Jᵀ F), the force, lever and axis drawn."""

from __future__ import annotations

import math

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.i18n import Translator
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, axis_names, sub, tool_name
from .. import fmt
from ..palette import FORCE_RGB, joint_color
from .common import LEVER_RGB, Drawn, MethodView, check, note, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot, tr: Translator) -> str:
    _ = tr.gettext
    j, i = d.joint, d.joint + 1
    z, p = axis_names(robot, j)
    pn = tool_name(robot)
    wrench, loads = d.inputs, d.numbers
    load = next(x for x in loads if x.axis == d.axes[0])
    revolute = robot.joints[j].kind == "revolute"
    tau_i = f"τ{sub(i)}"
    formula = (
        f"{tau_i} = {z} · (n + ({pn} − {p}) × f)"
        if revolute
        else _("{tau} = {z} · f (a slide feels the force along it)").format(tau=tau_i, z=z)
    )
    tau = snap.J_base.T @ wrench
    rows = [
        row(fmt.escape(_("f (at the tool)")), vec(wrench[:3], "N", tr)),
        row(fmt.escape(_("n (at the tool)")), vec(wrench[3:], "N·m", tr)),
    ]
    if revolute:
        rows.append(row(fmt.escape(_("moment about {p}").format(p=p)), vec(load.moment, "N·m", tr)))
    total = sum(x.multiplier * x.load for x in loads if x.joint == j)
    rows.append(row(tau_i, fmt.quantity(total, "N·m" if revolute else "N", tr=tr), ' class="res"'))
    out = f'<div class="jl-formula">{fmt.escape(formula)}</div><table class="jl-vec">{"".join(rows)}</table>'
    ok = math.isclose(total, float(tau[j]), abs_tol=1e-9)
    said = _("equals {JF}: column {i} of J dotted with F — the transpose view")
    out += check(ok, said.format(JF=f"(Jᵀ F){sub(i)}", i=i))
    out += note(_("The wrench is carried inward from the tool: go down from the last joint."))
    if d.assumed:
        out += note(
            _(
                "The force in “τ = JᵀF” is zero: shown for {one} along the base x axis. Set a force there to "
                "use yours."
            ).format(one="1 N")
        )
    return out


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float, tr: Translator) -> Drawn:
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
    labels = [
        ("F", tool + f * scale),
        (tr.gettext("{tau} about {z}").format(tau=f"τ{sub(d.joint + 1)}", z=z), where),
    ]
    return thick, thin, [], labels


VIEW = MethodView(METHODS["force"], html, draw)
