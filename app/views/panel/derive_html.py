"""The Derive tab's readouts as HTML: the DH table and one step of a derivation, with its numbers.

Pure functions of the robot, the state and the snapshot's :class:`~app.core.snapshot.derive.Derivation`.
The course's notation: for the standard DH convention joint i turns about zᵢ₋₁ through the
origin pᵢ₋₁ of frame i−1 and the tool point is pₙ; in the modified convention joint i turns
about zᵢ through pᵢ; a URDF robot's joint i turns about its own joint frame's axis zᵢ.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from kinematics import Robot

from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, sub
from .. import fmt
from ..methods import METHODS
from ..methods.common import matrix4_html
from ..palette import joint_text_hex

__all__ = ["dh_table_html", "step_html", "matrix4_html", "formulas_html"]


def _angle(x: float, digits: int = 4) -> str:
    return fmt.quantity(math.degrees(x), "°", digits)


_DH_DIGITS = 6
"""Significant digits of the DH table's constants: the robot file's own numbers (the Puma's
d₃ = 0.15005 m, the value the formulas use), not 0.15."""


def dh_table_html(robot: Robot, q: np.ndarray, selected: int | None) -> str:
    """The robot's DH table (degrees and metres) with the joint variable's current value highlighted.

    ``selected``: the row (0-based joint) a walk-through is on (outlined), or ``None``.
    """
    if robot.dh is None:
        return (
            '<div class="jl-note">This robot comes from a URDF: its joints are placed by the '
            "&lt;origin&gt; of each joint, not by a DH table. Frame i is the URDF joint frame "
            "of joint i; its z axis is the joint axis.</div>"
        )
    head, rows, tail = _dh_parts(robot)
    out = [head]
    for j, (row, (before, after)) in enumerate(zip(robot.dh, rows, strict=True)):
        if row.joint == "revolute":
            value = _angle(q[j] + row.theta)
        else:
            value = fmt.quantity(q[j] + row.d, "m", 4)
        cls = ' class="sel"' if selected == j else ""
        out.append(f"<tr{cls}>{before}{value}{after}</tr>")
    return "".join(out) + tail


@functools.lru_cache(maxsize=64)
def _dh_parts(robot: Robot) -> tuple[str, tuple[tuple[str, str], ...], str]:
    """What the DH table of ``robot`` keeps whatever q is: the head, each row's cells before and after
    the joint variable's value, the tail (built once per robot: the table is redrawn on every move)."""
    standard = robot.convention == "standard"
    names = ("i", "θᵢ", "dᵢ", "aᵢ", "αᵢ") if standard else ("i", "αᵢ₋₁", "aᵢ₋₁", "θᵢ", "dᵢ")
    head = f'<table class="jl-dh"><tr>{"".join(f"<th>{h}</th>" for h in names)}</tr>'
    mark = "\x00"  # where the variable's value goes
    rows = []
    assert robot.dh is not None
    for j, row in enumerate(robot.dh):
        color = joint_text_hex(j)
        var = f"q{sub(j + 1)}"
        if row.joint == "revolute":
            theta = f"{var} + {_angle(row.theta, _DH_DIGITS)}" if abs(row.theta) > 1e-12 else var
            theta = f'<b style="color:{color}">{theta} = {mark}</b>'
            d = fmt.quantity(row.d, "m", _DH_DIGITS)
        else:
            d = f"{var} + {fmt.quantity(row.d, 'm', _DH_DIGITS)}" if abs(row.d) > 1e-12 else var
            d = f'<b style="color:{color}">{d} = {mark}</b>'
            theta = _angle(row.theta, _DH_DIGITS)
        a, alpha = fmt.quantity(row.a, "m", _DH_DIGITS), _angle(row.alpha, _DH_DIGITS)
        cells = (str(j + 1), theta, d, a, alpha) if standard else (str(j + 1), alpha, a, theta, d)
        before, after = "".join(f"<td>{c}</td>" for c in cells).split(mark)
        rows.append((before, after))
    rule = (
        "Standard DH: Aᵢ = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ); joint i turns about zᵢ₋₁."
        if standard
        else "Modified DH (Craig): Aᵢ = Rx(αᵢ₋₁) Tx(aᵢ₋₁) Rz(θᵢ) Tz(dᵢ); joint i turns about zᵢ."
    )
    tail = f'</table><div class="jl-note">{rule} The joint variable is in its joint colour.</div>'
    return head, tuple(rows), tail


def step_html(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    """One step of the walk-through: what it computes, in the course's notation, with its numbers at q
    (the method's record draws the body, :data:`app.views.methods.METHODS`)."""
    i = d.joint + 1
    name = fmt.escape(robot.joints[d.joint].name)
    title = f"Step {i} of {robot.dof}: joint {i} ({name})"
    head = f'<div class="jl-step-head" style="border-color:{joint_text_hex(d.joint)}">{title}</div>'
    return head + METHODS[d.method].html(robot, d, snap)


def formulas_html(steps: tuple | None, note: str, method: str, joint: int, last: bool = False) -> str:
    """The symbolic steps of ``method`` that belong to ``joint``, each caption over its MathML.

    ``steps``: (joint, key, caption HTML, MathML) tuples from the symbolic worker (captions and
    MathML are escaped there), or ``None`` (then ``note`` says why). At the ``last`` step the
    assembled J and det J (factored, singular sets named) follow.
    """
    head = '<div class="jl-t4-title" style="text-align:left">In symbols</div>'
    if steps is None:
        return head + f'<div class="jl-note">{fmt.escape(note)}</div>'
    prefixes = METHODS[method].symbols if method in METHODS else ()
    chosen = [s for s in steps if s[0] == joint and s[1].startswith(prefixes)]
    if last and method in METHODS and METHODS[method].steps.column is not None:  # a method that builds J
        chosen += [s for s in steps if s[0] is None and s[1] in ("J", "detJ")]
    if not chosen:
        return head + '<div class="jl-note">No symbolic step for this joint.</div>'
    body = "".join(
        f'<div class="jl-note">{caption}</div><div class="jl-mathml">{ml}</div>'
        for _, _, caption, ml in chosen
    )
    return head + body
