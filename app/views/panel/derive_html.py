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
from ...core.snapshot.derive import Derivation, axis_names, sub, tool_name
from .. import fmt
from ..palette import joint_text_hex

__all__ = ["dh_table_html", "step_html", "matrix4_html", "formulas_html", "STEP_KEYS"]


def _vec(values: np.ndarray, unit: str = "") -> str:
    return (
        "("
        + ", ".join(fmt.fixed(x, 3) for x in fmt.cleaned(values, 1e-12))
        + ")"
        + (f" {unit}" if unit else "")
    )


def matrix4_html(T: np.ndarray, title: str) -> str:
    """A 4×4 transform as a small bracketed table under ``title``."""
    rows = "".join(
        "<tr>" + "".join(f"<td>{fmt.fixed(x, 3)}</td>" for x in fmt.cleaned(row, 1e-12)) + "</tr>"
        for row in T
    )
    table = f'<table class="jl-matrix jl-br">{rows}</table>'
    return f'<div class="jl-t4"><div class="jl-t4-title">{title}</div>{table}</div>'


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


def _row(name: str, value: str, cls: str = "") -> str:
    return f'<tr{cls}><th class="rowname">{name}</th><td>{value}</td></tr>'


def _check(ok: bool, what: str) -> str:
    return f'<div class="jl-note">{"✓" if ok else "✗"} {what}</div>'


def step_html(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    """One step of the walk-through: what it computes, in the course's notation, with its numbers at q."""
    j = d.joint
    i = j + 1
    z, p = axis_names(robot, j)
    pn = tool_name(robot)
    words = fmt.escape(fmt.joint_words(robot.joints[j].name, robot.name))
    color = joint_text_hex(j)
    title = f"Step {i} of {robot.dof}: joint {i}, q{sub(i)}" + (f" ({words})" if words else "")
    head = f'<div class="jl-step-head" style="border-color:{color}">{title}</div>'
    col = snap.J_base[:, j]
    body: list[str] = []
    if d.method == "dh":
        body.append(
            '<div class="jl-t4s">'
            + matrix4_html(d.A, f"A{sub(i)} = {sub(i - 1)}T{sub(i)} at q")
            + matrix4_html(d.T0, f"⁰T{sub(i)} = A₁ ⋯ A{sub(i)}")
            + "</div>"
        )
        body.append(
            f'<div class="jl-note">Drawn: frame {i - 1} (thin) and frame {i} (thick) with their axes named. '
            f"The last column of ⁰T{sub(i)} is the origin p{sub(i)}; its third column is z{sub(i)}.</div>"
        )
    elif d.method == "whitney":
        rows = []
        for c in (d.whitney[k] for k in d.axes):
            if c.kind == "revolute":
                rows += [
                    _row(z, _vec(c.z)),
                    _row(p, _vec(c.p, "m")),
                    _row(f"{pn} − {p}", _vec(c.r, "m")),
                    _row(f"{z} × ({pn} − {p})", _vec(c.linear, "m/rad"), ' class="res"'),
                    _row(f"ω part: {z}", _vec(c.angular)),
                ]
            else:
                rows += [_row(z, _vec(c.z)), _row(f"v part: {z}", _vec(c.linear, "m/m"), ' class="res"')]
                rows.append(_row("ω part", "(0, 0, 0): a slide does not turn the tool"))
        formula = (
            f"J{sub(i)} = [{z} × ({pn} − {p}); {z}]"
            if robot.joints[j].kind == "revolute"
            else f"J{sub(i)} = [{z}; 0] (prismatic)"
        )
        body.append(f'<div class="jl-formula">{formula}</div><table class="jl-vec">{"".join(rows)}</table>')
        assembled = sum(d.whitney[k].column for k in d.axes)
        body.append(_check(bool(np.allclose(assembled, col, atol=1e-9)), f"equals column {i} of J(q)"))
    elif d.method == "differentiation" and d.derivative is not None:
        dv = d.derivative
        unit = "m/rad" if robot.joints[j].kind == "revolute" else "m/m"
        body.append(f'<div class="jl-formula">J{sub(i)} = [∂p/∂q{sub(i)}; ω from (∂R/∂q{sub(i)}) Rᵀ]</div>')
        body.append(
            '<table class="jl-vec">'
            + _row(f"∂p/∂q{sub(i)}", _vec(dv.dp, unit), ' class="res"')
            + _row(f"(∂R/∂q{sub(i)}) Rᵀ → ω", _vec(dv.omega))
            + "</table>"
        )
        body.append(
            '<div class="jl-note">Drawn: the path the tool traces when only '
            f"q{sub(i)} moves (±30°), and its tangent ∂p/∂q{sub(i)}: column {i} of J.</div>"
        )
        ok = np.allclose(dv.column, col, atol=1e-6 * max(1.0, float(np.abs(col).max())))
        body.append(_check(bool(ok), f"central differences equal column {i} of J(q)"))
    elif d.method == "propagation":
        body.append(_propagation(robot, d, snap))
    elif d.method == "force":
        body.append(_force(robot, d, snap))
    return head + "".join(body)


def _rates_note(robot: Robot, d: Derivation) -> str:
    if not d.assumed:
        return ""
    return (
        '<div class="jl-note">The joint rates in “v = J q̇” are all zero: shown for q̇ᵢ = 1 '
        "(rad/s or m/s) for every joint. Set rates there to use yours.</div>"
    )


def _propagation(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    j, i = d.joint, d.joint + 1
    link = d.links[d.axes[-1]]
    prev = d.links[d.axes[0] - 1] if d.axes[0] > 0 else None
    revolute = robot.joints[j].kind == "revolute"
    rate = f"q̇{sub(i)}"
    z, _ = axis_names(robot, j)
    w, w0, v, v0, p, p0 = (
        f"{x}{sub(n)}" for x, n in (("ω", i), ("ω", i - 1), ("v", i), ("v", i - 1), ("p", i), ("p", i - 1))
    )
    if robot.convention == "standard":  # joint i turns frame i about z_{i-1}, through p_{i-1}
        turn = f"{w} = {w0} + {rate} {z}" if revolute else f"{w} = {w0}"
        move = f"{v} = {v0} + {w} × ({p} − {p0})" + ("" if revolute else f" + {rate} {z}")
    else:  # frame i sits on joint i's axis: the joint turns what comes after it
        turn = f"{w} = {w0} + {rate} {z}" if revolute else f"{w} = {w0}"
        move = f"{v} = {v0} + {w0} × ({p} − {p0})" + ("" if revolute else f" + {rate} {z}")
    formula = f"{turn};<br>{move}"
    zero = np.zeros(3)
    rows = [
        _row(f"ω{sub(i - 1)}", _vec(prev.omega if prev else zero, "rad/s")),
        _row(f"v{sub(i - 1)}", _vec(prev.v if prev else zero, "m/s")),
        _row(rate, fmt.quantity(math.degrees(d.qd[j]), "°/s") if revolute else fmt.quantity(d.qd[j], "m/s")),
        _row(f"ω{sub(i)}", _vec(link.omega, "rad/s"), ' class="res"'),
        _row(f"v{sub(i)}", _vec(link.v, "m/s"), ' class="res"'),
        _row(f"in frame {i}: ⁱωᵢ", _vec(link.omega_own, "rad/s")),
    ]
    out = f'<div class="jl-formula">{formula}</div><table class="jl-vec">{"".join(rows)}</table>'
    out += '<div class="jl-note">Base axes (the last row in the link\'s own axes, as Craig writes it). '
    out += "Drawn: ω (umber) and v (black) of every link frame up to this one.</div>"
    if j == robot.dof - 1:
        tool = d.links[-1]
        twist = np.concatenate([tool.v, tool.omega])
        ok = np.allclose(twist, snap.J_base @ d.qd, atol=1e-9 * max(1.0, float(np.abs(twist).max())))
        out += _check(bool(ok), "at the tool, (v, ω) equals J q̇")
    return out + _rates_note(robot, d)


def _force(robot: Robot, d: Derivation, snap: Snapshot) -> str:
    j, i = d.joint, d.joint + 1
    z, p = axis_names(robot, j)
    pn = tool_name(robot)
    load = next(x for x in d.loads if x.axis == d.axes[0])
    revolute = robot.joints[j].kind == "revolute"
    formula = (
        f"τ{sub(i)} = {z} · (n + ({pn} − {p}) × f)"
        if revolute
        else f"τ{sub(i)} = {z} · f (a slide feels the force along it)"
    )
    tau = snap.J_base.T @ d.wrench
    rows = [
        _row("f (at the tool)", _vec(d.wrench[:3], "N")),
        _row("n (at the tool)", _vec(d.wrench[3:], "N·m")),
    ]
    if revolute:
        rows.append(_row(f"moment about {p}", _vec(load.moment, "N·m")))
    unit = "N·m" if revolute else "N"
    rows.append(
        _row(
            f"τ{sub(i)}",
            fmt.quantity(sum(x.multiplier * x.load for x in d.loads if x.joint == j), unit),
            ' class="res"',
        )
    )
    out = f'<div class="jl-formula">{formula}</div><table class="jl-vec">{"".join(rows)}</table>'
    ok = math.isclose(
        sum(x.multiplier * x.load for x in d.loads if x.joint == j), float(tau[j]), abs_tol=1e-9
    )
    out += _check(ok, f"equals (Jᵀ F){sub(i)}: column {i} of J dotted with F — the transpose view")
    out += (
        '<div class="jl-note">The wrench is carried inward from the tool: go down from the last joint.</div>'
    )
    if d.assumed:
        out += (
            '<div class="jl-note">The force in “τ = JᵀF” is zero: shown for 1 N along the base x axis. '
            "Set a force there to use yours.</div>"
        )
    return out


STEP_KEYS = {
    "dh": ("A", "T0_"),
    "whitney": ("whitney.",),
    "differentiation": ("diff.",),
    "propagation": ("prop.",),
    "force": ("force.",),
}
"""Which symbolic steps (by key prefix) each walk-through shows for its joint."""


def formulas_html(steps: tuple | None, note: str, method: str, joint: int, last: bool = False) -> str:
    """The symbolic steps of ``method`` that belong to ``joint``, each caption over its MathML.

    ``steps``: (joint, key, caption HTML, MathML) tuples from the symbolic worker (captions and
    MathML are escaped there), or ``None`` (then ``note`` says why). At the ``last`` step the
    assembled J and det J (factored, singular sets named) follow.
    """
    head = '<div class="jl-t4-title" style="text-align:left">In symbols</div>'
    if steps is None:
        return head + f'<div class="jl-note">{fmt.escape(note)}</div>'
    prefixes = STEP_KEYS.get(method, ())
    chosen = [s for s in steps if s[0] == joint and s[1].startswith(prefixes)]
    if last and method != "dh":
        chosen += [s for s in steps if s[0] is None and s[1] in ("J", "detJ")]
    if not chosen:
        return head + '<div class="jl-note">No symbolic step for this joint.</div>'
    body = "".join(
        f'<div class="jl-note">{caption}</div><div class="jl-mathml">{ml}</div>'
        for _, _, caption, ml in chosen
    )
    return head + body
