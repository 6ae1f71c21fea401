"""The joint rates of a recorded demo: the label's second line and ``joint_rates.csv``.

viser records the 3-D scene only; the rates that blow up near a singularity are drawn as text above the
arm each frame (:func:`rates_readout`) and kept as numbers, every frame's q and q̇ with units
(:func:`rates_csv`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..core.i18n import Translator
from ..core.state import LabState
from ..views.fmt import number

__all__ = ["joint_rates", "rates_readout", "rates_csv"]


def joint_rates(state: LabState) -> np.ndarray | None:
    """The motion's joint rates q̇ (n,) [rad/s | m/s] at this frame: the last sample of its trace while
    it plays, or the rates that stopped it; ``None`` when no motion drives the joints."""
    trace = state.motion.trace
    if trace is None or len(trace) == 0 or float(trace.t[-1]) < state.time:
        return None
    if not (state.playing or state.stopped):
        return None
    return np.asarray(trace.qd[-1], dtype=float)


def rates_readout(state: LabState, tr: Translator | None = None) -> str:
    """The label under the readout: "q̇  q1 12 °/s · q2 −40 °/s · …" ("" when nothing moves the joints),
    its numbers as ``tr``'s language writes them."""
    qd = joint_rates(state)
    if qd is None:
        return ""
    parts = [
        f"{j.name.split()[0]} {_rate(j.kind, float(x), tr)}"
        for j, x in zip(state.robot.joints, qd, strict=True)
    ]
    return "q̇   " + " · ".join(parts)


def _rate(kind: str, x: float, tr: Translator | None = None) -> str:
    return f"{number(x, 3, tr)} m/s" if kind == "prismatic" else f"{number(np.degrees(x), 3, tr)} °/s"


def rates_csv(states: Sequence[LabState], fps: float) -> str:
    """Every frame's time, joint values and the motion's joint rates, one row per frame (units in the
    header: degrees and °/s for revolute joints, metres and m/s for prismatic; empty q̇ cells where no
    motion drives the joints); ``states``: one per frame, 1/``fps`` seconds apart."""
    robot = states[0].robot
    heads = ["frame", "t [s]"]
    for j in robot.joints:
        heads.append(f"{j.name} [{'m' if j.kind == 'prismatic' else 'deg'}]")
    for j in robot.joints:
        heads.append(f"{j.name} rate [{'m/s' if j.kind == 'prismatic' else 'deg/s'}]")
    rows = [",".join(_csv_cell(h) for h in heads)]
    for k, state in enumerate(states):
        q = [_si(j.kind, float(x)) for j, x in zip(robot.joints, state.q, strict=True)]
        qd = joint_rates(state)
        rates = (
            [_si(j.kind, float(x)) for j, x in zip(robot.joints, qd, strict=True)]
            if qd is not None
            else [""] * robot.dof
        )
        rows.append(",".join([str(k), f"{k / fps:.6g}", *q, *rates]))
    return "\n".join(rows) + "\n"


def _si(kind: str, x: float) -> str:
    return f"{x:.9g}" if kind == "prismatic" else f"{np.degrees(x):.9g}"


def _csv_cell(text: str) -> str:
    return '"' + text.replace('"', '""') + '"' if any(c in text for c in ',"\n') else text
