"""Velocity propagation: ωᵢ and vᵢ link by link outward for the tab's joint rates, drawn at every frame."""

from __future__ import annotations

import math

import numpy as np

from kinematics import Robot
from kinematics.steps import METHODS

from ...core.i18n import Translator
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation, axis_names, sub
from .. import fmt
from ..palette import TWIST_ANGULAR_RGB, TWIST_RGB
from .common import Drawn, MethodView, check, note, row, vec


def html(robot: Robot, d: Derivation, snap: Snapshot, tr: Translator) -> str:
    _ = tr.gettext
    j, i = d.joint, d.joint + 1
    qd = d.inputs
    link = d.numbers[d.axes[-1]]
    prev = d.numbers[d.axes[0] - 1] if d.axes[0] > 0 else None
    revolute = robot.joints[j].kind == "revolute"
    rate = f"q̇{sub(i)}"
    z = axis_names(robot, j)[0]
    w, w0, v, v0, p, p0 = (
        f"{x}{sub(n)}" for x, n in (("ω", i), ("ω", i - 1), ("v", i), ("v", i - 1), ("p", i), ("p", i - 1))
    )
    turn = f"{w} = {w0} + {rate} {z}" if revolute else f"{w} = {w0}"
    if robot.convention == "standard":  # joint i turns frame i about z_{i-1}, through p_{i-1}
        move = f"{v} = {v0} + {w} × ({p} − {p0})" + ("" if revolute else f" + {rate} {z}")
    else:  # frame i sits on joint i's axis: the joint turns what comes after it
        move = f"{v} = {v0} + {w0} × ({p} − {p0})" + ("" if revolute else f" + {rate} {z}")
    zero = np.zeros(3)
    speed = fmt.quantity(math.degrees(qd[j]), "°/s", tr=tr) if revolute else fmt.quantity(qd[j], "m/s", tr=tr)
    rows = [
        row(f"ω{sub(i - 1)}", vec(prev.omega if prev else zero, "rad/s", tr)),
        row(f"v{sub(i - 1)}", vec(prev.v if prev else zero, "m/s", tr)),
        row(rate, speed),
        row(f"ω{sub(i)}", vec(link.omega, "rad/s", tr), ' class="res"'),
        row(f"v{sub(i)}", vec(link.v, "m/s", tr), ' class="res"'),
        row(fmt.escape(_("in frame {i}: {w}").format(i=i, w="ⁱωᵢ")), vec(link.omega_own, "rad/s", tr)),
    ]
    formula = f"{fmt.escape(turn)};<br>{fmt.escape(move)}"
    out = f'<div class="jl-formula">{formula}</div><table class="jl-vec">{"".join(rows)}</table>'
    out += note(
        _(
            "Base axes (the last row in the link's own axes, as Craig writes it). Drawn: ω (umber) and v "
            "(black) of every link frame up to this one."
        )
    )
    if j == robot.dof - 1:
        tool = d.numbers[-1]
        twist = np.concatenate([tool.v, tool.omega])
        ok = np.allclose(twist, snap.J_base @ qd, atol=1e-9 * max(1.0, float(np.abs(twist).max())))
        out += check(bool(ok), _("at the tool, {twist} equals {Jq}").format(twist="(v, ω)", Jq="J q̇"))
    if d.assumed:
        out += note(
            _(
                "The joint rates in “{formula}” are all zero: shown for {rates} (rad/s or m/s) for every "
                "joint. Set rates there to use yours."
            ).format(formula="v = J q̇", rates="q̇ᵢ = 1")
        )
    return out


FLOOR = 0.15
"""The shortest drawn vₖ or ωₖ, as a fraction of the arm's size: a 5 m/s v₂ beside a 21 m/s v₃ on the
TRR (0.085 at one scale) was a stub."""


def draw(robot: Robot, d: Derivation, snap: Snapshot, unit: float, lin: float, tr: Translator) -> Drawn:
    """Every link's vₖ and ωₖ up to frame i, each seen: the longest of each kind drawn 0.35 × the arm's
    size, the others to that scale but none shorter than :data:`FLOOR` × (a 0.5 m/s slide beside
    26 m/s on the TRR's 24 m arm stays visible). The scale is stated on the arrows: the label at
    every vₖ's tip, and at ωᵢ's, gives its size ("v₃ = 26.5 m/s", in the tab's numbers)."""
    last = d.axes[-1]
    links = d.numbers[: last + 1]
    size = unit / 0.2  # the arm's size × the glyph scale
    thick: list = []
    thin: list = []
    labels: list = []
    v_draw = _readable([link.v for link in links], size)
    w_draw = _readable([link.omega for link in links], size)
    for k, (link, v, w) in enumerate(zip(links, v_draw, w_draw, strict=True)):
        target = thick if k == last else thin
        if v is not None:
            target.append((link.origin, v, TWIST_RGB))
            labels.append((_named(f"v{sub(k + 1)}", link.v, "m/s", tr), link.origin + v))
        if w is not None:
            target.append((link.origin, w, TWIST_ANGULAR_RGB))
    if w_draw[last] is not None:
        link = d.numbers[last]
        labels.append((_named(f"ω{sub(last + 1)}", link.omega, "rad/s", tr), link.origin + w_draw[last]))
    return thick, thin, [], labels[-6:]


def _named(name: str, vector: np.ndarray, unit: str, tr: Translator) -> str:
    """ "v₃ = 26.5 m/s": a drawn vector's name and size, in ``tr``'s numbers."""
    return f"{name} = {fmt.quantity(float(np.linalg.norm(vector)), unit, tr=tr)}"


def _readable(vectors: list, size: float) -> list[np.ndarray | None]:
    """Drawn vectors of one kind: the longest 0.35 × ``size``, none shorter than :data:`FLOOR` ×
    ``size`` (direction kept), a zero vector not drawn (``None``)."""
    norms = [float(np.linalg.norm(v)) for v in vectors]
    top = max(norms, default=0.0)
    if not math.isfinite(top) or top <= 1e-12:
        return [None] * len(vectors)
    out: list[np.ndarray | None] = []
    for v, n in zip(vectors, norms, strict=True):
        if n <= 1e-9 * top:
            out.append(None)
            continue
        out.append(np.asarray(v, float) / n * max(0.35 * size * n / top, FLOOR * size))
    return out


VIEW = MethodView(METHODS["propagation"], html, draw)
