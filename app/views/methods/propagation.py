"""Velocity propagation: ωᵢ and vᵢ link by link outward for the tab's joint rates, drawn at every frame."""

from __future__ import annotations

import math

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, axis_names, sub
from .. import fmt
from ..palette import TWIST_ANGULAR_RGB, TWIST_RGB
from .common import Drawn, MethodView, check, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    j, i = d.joint, d.joint + 1
    qd = d.inputs
    link = d.numbers[d.axes[-1]]
    prev = d.numbers[d.axes[0] - 1] if d.axes[0] > 0 else None
    revolute = robot.joints[j].kind == "revolute"
    rate = f"q̇{sub(i)}"
    z, _ = axis_names(robot, j)
    w, w0, v, v0, p, p0 = (
        f"{x}{sub(n)}" for x, n in (("ω", i), ("ω", i - 1), ("v", i), ("v", i - 1), ("p", i), ("p", i - 1))
    )
    turn = f"{w} = {w0} + {rate} {z}" if revolute else f"{w} = {w0}"
    if robot.convention == "standard":  # joint i turns frame i about z_{i-1}, through p_{i-1}
        move = f"{v} = {v0} + {w} × ({p} − {p0})" + ("" if revolute else f" + {rate} {z}")
    else:  # frame i sits on joint i's axis: the joint turns what comes after it
        move = f"{v} = {v0} + {w0} × ({p} − {p0})" + ("" if revolute else f" + {rate} {z}")
    zero = np.zeros(3)
    rows = [
        row(f"ω{sub(i - 1)}", vec(prev.omega if prev else zero, "rad/s")),
        row(f"v{sub(i - 1)}", vec(prev.v if prev else zero, "m/s")),
        row(rate, fmt.quantity(math.degrees(qd[j]), "°/s") if revolute else fmt.quantity(qd[j], "m/s")),
        row(f"ω{sub(i)}", vec(link.omega, "rad/s"), ' class="res"'),
        row(f"v{sub(i)}", vec(link.v, "m/s"), ' class="res"'),
        row(f"in frame {i}: ⁱωᵢ", vec(link.omega_own, "rad/s")),
    ]
    out = f'<div class="jl-formula">{turn};<br>{move}</div><table class="jl-vec">{"".join(rows)}</table>'
    out += '<div class="jl-note">Base axes (the last row in the link\'s own axes, as Craig writes it). '
    out += "Drawn: ω (umber) and v (black) of every link frame up to this one.</div>"
    if j == robot.dof - 1:
        tool = d.numbers[-1]
        twist = np.concatenate([tool.v, tool.omega])
        ok = np.allclose(twist, snap.J_base @ qd, atol=1e-9 * max(1.0, float(np.abs(twist).max())))
        out += check(bool(ok), "at the tool, (v, ω) equals J q̇")
    if d.assumed:
        out += (
            '<div class="jl-note">The joint rates in “v = J q̇” are all zero: shown for q̇ᵢ = 1 '
            "(rad/s or m/s) for every joint. Set rates there to use yours.</div>"
        )
    return out


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float) -> Drawn:
    last = d.axes[-1]
    thick: list = []
    thin: list = []
    for k, link in enumerate(d.numbers[: last + 1]):
        target = thick if k == last else thin
        target.append((link.origin, link.v * lin, TWIST_RGB))
        target.append((link.origin, link.omega * unit, TWIST_ANGULAR_RGB))
    link = d.numbers[last]
    i = d.joint + 1
    labels = [(f"v{sub(i)}", link.origin + link.v * lin), (f"ω{sub(i)}", link.origin + link.omega * unit)]
    return thick, thin, [], labels


VIEW = MethodView(METHODS["propagation"], html, draw)
