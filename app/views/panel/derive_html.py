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
from kinematics.text import translated, words

from ...core.i18n import Translator, translations
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, sub
from .. import fmt
from ..methods import METHODS
from ..methods.common import matrix4_html
from ..palette import joint_text_hex

__all__ = ["dh_table_html", "step_html", "matrix4_html", "formulas_html"]


def _angle(x: float, digits: int = 4, tr: Translator | None = None) -> str:
    return fmt.quantity(math.degrees(x), "°", digits, tr=tr)


_DH_DIGITS = 6
"""Significant digits of the DH table's constants: the robot file's own numbers (the Puma's
d₃ = 0.15005 m, the value the formulas use), not 0.15."""


def dh_table_html(robot: Robot, q: np.ndarray, selected: int | None, tr: Translator | None = None) -> str:
    """The robot's DH table (degrees and metres) with the joint variable's current value highlighted.

    ``selected``: the row (0-based joint) a walk-through is on (outlined), or ``None``; ``tr``: the
    tab's language (its note's words, its numbers' decimal mark).
    """
    tr = tr or translations()
    if robot.dh is None:
        said = tr.gettext(
            "This robot comes from a URDF: its joints are placed by the <origin> of each joint, not by a "
            "DH table. Frame i is the URDF joint frame of joint i; its z axis is the joint axis."
        )
        return f'<div class="jl-note">{fmt.escape(said)}</div>'
    head, rows, tail = _dh_parts(robot, tr)
    out = [head]
    for j, (row, (before, after)) in enumerate(zip(robot.dh, rows, strict=True)):
        if row.joint == "revolute":
            value = _angle(q[j] + row.theta, tr=tr)
        else:
            value = fmt.quantity(q[j] + row.d, "m", 4, tr=tr)
        cls = ' class="sel"' if selected == j else ""
        out.append(f"<tr{cls}>{before}{value}{after}</tr>")
    return "".join(out) + tail


@functools.lru_cache(maxsize=64)
def _dh_parts(robot: Robot, tr: Translator) -> tuple[str, tuple[tuple[str, str], ...], str]:
    """What the DH table of ``robot`` keeps whatever q is: the head, each row's cells before and after
    the joint variable's value, the tail (built once per robot and language: the table is redrawn on
    every move)."""
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
            theta = f"{var} + {_angle(row.theta, _DH_DIGITS, tr)}" if abs(row.theta) > 1e-12 else var
            theta = f'<b style="color:{color}">{theta} = {mark}</b>'
            d = fmt.quantity(row.d, "m", _DH_DIGITS, tr=tr)
        else:
            d = f"{var} + {fmt.quantity(row.d, 'm', _DH_DIGITS, tr=tr)}" if abs(row.d) > 1e-12 else var
            d = f'<b style="color:{color}">{d} = {mark}</b>'
            theta = _angle(row.theta, _DH_DIGITS, tr)
        a, alpha = fmt.quantity(row.a, "m", _DH_DIGITS, tr=tr), _angle(row.alpha, _DH_DIGITS, tr)
        cells = (str(j + 1), theta, d, a, alpha) if standard else (str(j + 1), alpha, a, theta, d)
        before, after = "".join(f"<td>{c}</td>" for c in cells).split(mark)
        rows.append((before, after))
    _ = tr.gettext
    rule = (
        _(
            "Standard DH: {A} = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ); joint i turns about {z}. The joint variable "
            "is in its joint colour."
        ).format(A="Aᵢ", z="zᵢ₋₁")
        if standard
        else _(
            "Modified DH (Craig): {A} = Rx(αᵢ₋₁) Tx(aᵢ₋₁) Rz(θᵢ) Tz(dᵢ); joint i turns about {z}. The joint "
            "variable is in its joint colour."
        ).format(A="Aᵢ", z="zᵢ")
    )
    tail = f'</table><div class="jl-note">{fmt.escape(rule)}</div>'
    return head, tuple(rows), tail


def step_html(robot: Robot, d: Derivation, snap: Snapshot, tr: Translator | None = None) -> str:
    """One step of the walk-through: what it computes, in the course's notation, with its numbers at q
    (the method's record draws the body, :data:`app.views.methods.METHODS`), in ``tr``'s language."""
    tr = tr or translations()
    i = d.joint + 1
    steps = robot.dof + 1 if d.method == "dh" else robot.dof  # the DH walk ends with the tool frame
    if d.tool:
        title = tr.gettext("Step {i} of {n}: the tool frame, row {i} of the DH table").format(i=i, n=steps)
        color = "#3d434b"
    else:
        name = robot.joints[d.joint].name
        title = tr.gettext("Step {i} of {n}: joint {i} ({name})").format(i=i, n=steps, name=name)
        color = joint_text_hex(d.joint)
    head = f'<div class="jl-step-head" style="border-color:{color}">{fmt.escape(title)}</div>'
    return head + METHODS[d.method].html(robot, d, snap, tr)


def formulas_html(
    steps: tuple | None,
    note: str,
    method: str,
    joint: int,
    last: bool = False,
    tr: Translator | None = None,
    tool: bool = False,
) -> str:
    """The symbolic steps of ``method`` that belong to ``joint``, each caption over its MathML.

    ``steps``: (joint, key, caption HTML, MathML[, (catalog id, arguments)]) tuples from the symbolic
    worker (captions and MathML are escaped there; a caption with a catalog id is shown in ``tr``'s
    language), or ``None`` (then ``note`` says why). At the ``last`` step the
    assembled J and det J (factored, singular sets named) follow; at the DH walk's ``tool`` step, the
    tool transform ⁿT_tool and the tool pose ⁰T_tool.
    """
    tr = tr or translations()
    _ = tr.gettext
    title = fmt.escape(_("In symbols"))
    head = f'<div class="jl-t4-title" style="text-align:left">{title}</div>'
    if steps is None:
        return head + f'<div class="jl-note">{fmt.escape(note)}</div>'
    prefixes = METHODS[method].symbols if method in METHODS else ()
    chosen = [s for s in steps if s[0] == joint and s[1].startswith(prefixes)]
    if tool:
        chosen = [s for s in steps if s[0] is None and s[1] in ("Atool", "T0_tool")]
        if not chosen:
            said = _("The tool frame is frame {n} itself: its transform is the identity.").format(n=joint)
            return head + f'<div class="jl-note">{fmt.escape(said)}</div>'
    if last and method in METHODS and METHODS[method].steps.column is not None:  # a method that builds J
        chosen += [s for s in steps if s[0] is None and s[1] in ("J", "detJ")]
    if not chosen:
        none = fmt.escape(_("No symbolic step for this joint."))
        return head + f'<div class="jl-note">{none}</div>'
    body = "".join(
        f'<div class="jl-note">{_caption(step, tr)}</div><div class="jl-mathml">{step[3]}</div>'
        for step in chosen
    )
    return head + body


def _caption(step: tuple, tr: Translator) -> str:
    """A symbolic step's caption (HTML) in the tab's language: its catalog id translated and filled
    with its arguments (symbols and numbers), escaped; the worker's English caption when it has none."""
    if len(step) > 4 and step[4][0]:
        msgid, args = step[4]
        return fmt.escape(translated(words(msgid, **dict(args)), tr))
    return str(step[2])
