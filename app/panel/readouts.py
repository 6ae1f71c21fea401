"""Live readouts as HTML: the status banner and the labelled measures of J.

Pure functions of a :class:`~app.snapshot.Snapshot`: easy to test, and the
panel only assigns the returned strings (viser skips unchanged ones).
"""

from __future__ import annotations

from kinematics import Robot

from .. import fmt
from ..palette import status_hex
from ..snapshot import Snapshot

__all__ = ["status_html", "measures_html", "ROW_NAMES", "row_label", "task_name"]

ROW_NAMES = (
    "v<sub>x</sub>",
    "v<sub>y</sub>",
    "v<sub>z</sub>",
    "ω<sub>x</sub>",
    "ω<sub>y</sub>",
    "ω<sub>z</sub>",
)


def row_label(rows: tuple[int, ...]) -> str:
    """HTML list of the rows of J: "v<sub>x</sub>, v<sub>y</sub>, ω<sub>z</sub>"."""
    return ", ".join(ROW_NAMES[r] for r in rows)


def task_name(rows: tuple[int, ...]) -> str:
    """Words for a set of task rows."""
    if rows == (0, 1, 2, 3, 4, 5):
        return "all six rows"
    if rows == (0, 1, 2):
        return "tool-point velocity rows"
    if rows == (0, 1, 5):
        return "planar rows"
    return "rows " + row_label(rows)


def status_html(snap: Snapshot) -> str:
    """The coloured banner: "regular", "near singular: wrist", "singular: wrist", with κ."""
    r = snap.report
    color = status_hex(r.status)
    icon = "●" if r.status == "regular" else "▲" if r.status == "near singular" else "■"
    return (
        f'<div class="jl"><div class="jl-status" style="background:{color}" data-status="{r.status}">'
        f"<span>{icon}</span><span>{fmt.escape(r.text())}</span>"
        f'<small style="margin-left:auto">κ = {fmt.number(r.condition)}</small></div></div>'
    )


def measures_html(snap: Snapshot, robot: Robot) -> str:
    """The table of measures, each labelled with what it is (task rows named)."""
    n_rows, n = len(snap.rows), robot.dof
    rows = [
        ("Status", fmt.escape(snap.report.text())),
        (f"Condition number κ (task: {task_name(snap.rows)})", fmt.number(snap.report.condition)),
        (
            "κ translational (v rows)"
            if not robot.planar
            else "κ translational (v<sub>x</sub>, v<sub>y</sub>)",
            fmt.number(snap.cond_translational),
        ),
    ]
    if snap.cond_rotational is not None:
        rows.append(("κ rotational (ω rows)", fmt.number(snap.cond_rotational)))
    rows += [
        ("Manipulability w = √det(J Jᵀ)", fmt.number(snap.manipulability)),
        ("Singular values σ", ", ".join(fmt.number(s) for s in snap.sigma)),
        (
            "det J" if snap.det is not None else "det J",
            fmt.number(snap.det) if snap.det is not None else f"— (task J is {n_rows}×{n}, not square)",
        ),
        ("Rank", f"{snap.rank} of {min(n_rows, n)}" + (f" (task has {n_rows} rows)" if n_rows > n else "")),
    ]
    body = "".join(
        f'<tr><th>{label}</th><td class="{"v wrap" if ", " in value else "v"}">{value}</td></tr>'
        for label, value in rows
    )
    note = (
        f'<div class="jl-note">Task rows: {row_label(snap.rows)} of the base-frame J. '
        "κ = σ<sub>max</sub>/σ<sub>min</sub> (∞ at a singularity); w = Π σ<sub>i</sub>.</div>"
    )
    return f'<div class="jl"><table class="jl-table">{body}</table>{note}</div>'
