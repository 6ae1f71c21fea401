"""The DH frames, row by row: Aᵢ = ⁱ⁻¹Tᵢ and ⁰Tᵢ at q, frames i−1 (thin) and i (thick) drawn and named."""

from __future__ import annotations

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.i18n import Translator
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, sub
from .common import AXIS_RGB, Drawn, MethodView, matrix4_html, note

_SUP = str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹")


def sup(i: int) -> str:
    """``i`` as superscript digits: the frame a transform is seen from (ⁱ⁻¹Tᵢ, ¹T₂)."""
    return str(i).translate(_SUP)


def html(robot: Robot, d: Derivation, snap: Snapshot, tr: Translator) -> str:
    _ = tr.gettext
    i = d.joint + 1
    said = _(
        "Drawn: frame {before} (thin) and frame {i} (thick) with their axes named. The last column of "
        "{T} is the origin {p}; its third column is {z}."
    ).format(before=i - 1, i=i, T=f"⁰T{sub(i)}", p=f"p{sub(i)}", z=f"z{sub(i)}")
    return (
        '<div class="jl-t4s">'
        + matrix4_html(d.A, _("{A} = {T} at q").format(A=f"A{sub(i)}", T=f"{sup(i - 1)}T{sub(i)}"), tr)
        + matrix4_html(d.T0, f"⁰T{sub(i)} = A₁ ⋯ A{sub(i)}", tr)
        + "</div>"
        + note(said)
    )


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float, tr: Translator) -> Drawn:
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
