"""The DH frames, row by row: Aᵢ = ⁱ⁻¹Tᵢ and ⁰Tᵢ at q, frames i−1 (thin) and i (thick) drawn and named;
the last row is the tool frame's (ⁿTₙ₊₁, the tool transform, and ⁰Tₙ₊₁: 001's ³T₄ and ⁰T₄ of the 3R)."""

from __future__ import annotations

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.i18n import Translator
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, sub, tool_name
from .common import AXIS_RGB, Drawn, MethodView, matrix4_html, note

_SUP = str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹")


def sup(i: int) -> str:
    """``i`` as superscript digits: the frame a transform is seen from (ⁱ⁻¹Tᵢ, ¹T₂)."""
    return str(i).translate(_SUP)


def html(robot: Robot, d: Derivation, snap: Snapshot, tr: Translator) -> str:
    _ = tr.gettext
    i = d.joint + 1
    if d.tool:
        return _tool_html(robot, d, tr)
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


def _tool_html(robot: Robot, d: Derivation, tr: Translator) -> str:
    """The last step: the tool frame as DH row n + 1 (001's frame 4 of the 3R): ⁿTₙ₊₁ and ⁰Tₙ₊₁."""
    _ = tr.gettext
    n = robot.dof
    T = f"{sup(n)}T{sub(n + 1)}"
    T0 = f"⁰T{sub(n + 1)}"
    product = " ".join(f"A{sub(k + 1)}" for k in range(n))
    said = _(
        "The tool frame is frame {last} of the course's table: its row is constant (no joint moves it), "
        "so {T} is the robot's tool transform, the identity when the tool is frame {n} itself. Drawn: "
        "frame {n} (thin) and the tool frame {last} (thick). The last column of {T0} is the tool point {p}."
    ).format(last=n + 1, n=n, T=T, T0=T0, p=tool_name(robot))
    return (
        '<div class="jl-t4s">'
        + matrix4_html(d.A, _("{T} = the tool transform (constant)").format(T=T), tr)
        + matrix4_html(d.T0, f"{T0} = {product} · {T}", tr)
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
