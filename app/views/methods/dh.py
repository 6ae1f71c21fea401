"""The DH frames, row by row: Aᵢ = ⁱ⁻¹Tᵢ and ⁰Tᵢ at q, frames i−1 (thin) and i (thick) drawn and named."""

from __future__ import annotations

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, sub
from .common import AXIS_RGB, Drawn, MethodView, matrix4_html


def html(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    i = d.joint + 1
    return (
        '<div class="jl-t4s">'
        + matrix4_html(d.A, f"A{sub(i)} = {sub(i - 1)}T{sub(i)} at q")
        + matrix4_html(d.T0, f"⁰T{sub(i)} = A₁ ⋯ A{sub(i)}")
        + "</div>"
        + f'<div class="jl-note">Drawn: frame {i - 1} (thin) and frame {i} (thick) with their axes named. '
        f"The last column of ⁰T{sub(i)} is the origin p{sub(i)}; its third column is z{sub(i)}.</div>"
    )


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float) -> Drawn:
    i = d.joint + 1
    thick: list = []
    thin: list = []
    labels: list = []
    for which, T in enumerate(d.frames):
        o, R = T[:3, 3], T[:3, :3]
        n = i - 1 + which
        target = thick if which else thin
        length = unit * (1.2 if which else 0.9)
        for a, name in enumerate("xyz"):
            target.append((o, R[:, a] * length, AXIS_RGB[a]))
            if a != 1:
                labels.append((f"{name}{sub(n)}", o + R[:, a] * length))
    return thick, thin, [], labels


VIEW = MethodView(METHODS["dh"], html, draw)
