"""Live readouts as HTML: the status banner and the labelled measures of J.

Pure functions of a :class:`~app.core.snapshot.Snapshot` (and the state): easy
to test, and the panel only assigns the returned strings (viser skips
unchanged ones).
"""

from __future__ import annotations

from kinematics import Robot

from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...core.words import status_words
from .. import fmt
from ..palette import status_hex

__all__ = ["status_html", "measures_html", "source_html", "ROW_NAMES", "row_label", "task_name", "lost_text"]

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
        return "tool-point velocity"
    if rows == (3, 4, 5):
        return "tool rotation"
    if rows == (0, 1, 5):
        return "planar rows"
    return "rows " + row_label(rows)


def lost_text(snap: Snapshot, planar: bool) -> str:
    """What the lost direction is, in words (empty when regular)."""
    lost = snap.lost
    if lost is None:
        return ""
    parts = []
    if lost.translation_share >= 0.1:
        parts.append(f"translation {fmt.number(100 * lost.translation_share, 2)} %")
    if lost.rotation_share >= 0.1 and not planar:
        parts.append(f"rotation {fmt.number(100 * lost.rotation_share, 2)} %")
    weigh = (
        f" (rad/s weighed as the tool moving L = {fmt.quantity(lost.length, 'm')}, the arm's reach)"
        if any(r < 3 for r in snap.rows) and any(r >= 3 for r in snap.rows)
        else ""
    )
    return f"Lost direction: {' + '.join(parts) or 'mixed'}{weigh}."


def status_html(snap: Snapshot, state: LabState) -> str:
    """The coloured banner ("regular", "near singular: wrist", "singular: wrist") with κ, and one line
    under it: the visited configuration's description, or why a motion stopped."""
    r = snap.report
    icon = "●" if r.status == "regular" else "▲" if r.status == "near singular" else "■"
    words = status_words(state.robot, r.status, tuple(r.kinds), state.configuration)
    banner = (
        f'<div class="jl-status" style="background:{status_hex(r.status)}" data-status="{r.status}">'
        f"<span>{icon}</span><span>{fmt.escape(words)}</span>"
        f'<small style="margin-left:auto">κ = {fmt.number(r.condition)}</small></div>'
    )
    robot = state.robot
    sub = ""
    if state.stopped:
        sub = fmt.escape(state.stopped)
    elif state.configuration:
        conf = next((c for c in robot.configurations if c.name == state.configuration), None)
        text = conf.description if conf is not None and conf.description else ""
        sub = f"<b>{fmt.escape(state.configuration.replace('_', ' '))}</b>" + (
            f": {fmt.escape(text)}" if text else ""
        )
    lost = lost_text(snap, robot.planar)
    a = snap.analytic
    representation = (
        f"<b>representation singular</b> ({a.convention.upper()}, "
        f"{'pitch ±90°' if a.convention == 'zyx' else 'θ = 0 or 180°'}): no J<sub>A</sub>; "
        f"J {r.status}, rank {snap.rank}"
        if a is not None and a.singular
        else ""
    )
    lines = "".join(
        f'<div class="jl-sub" title="{fmt.escape(_plain(x))}">{x}</div>'
        for x in (representation, sub, lost)
        if x
    )
    return f'<div class="jl">{banner}{lines}</div>'


def measures_html(snap: Snapshot, robot: Robot) -> str:
    """The table of measures, each labelled with what it is (task rows named)."""
    n_rows, n = len(snap.rows), robot.dof
    rows = [
        (f"κ, task ({task_name(snap.rows)})", fmt.number(snap.report.condition)),
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
        ("w = √det(J Jᵀ)", fmt.number(snap.manipulability)),
        ("σ", ", ".join(fmt.number(s) for s in fmt.cleaned(snap.sigma))),
        ("det J", fmt.number(snap.det) if snap.det is not None else f"— ({n_rows}×{n}, not square)"),
        ("rank", f"{snap.rank} of {min(n_rows, n)}"),
    ]
    body = "".join(
        f'<tr><th>{label}</th><td class="{"v wrap" if ", " in value else "v"}">{value}</td></tr>'
        for label, value in rows
    )
    note = (
        f'<div class="jl-note">Task rows {row_label(snap.rows)} of the base-frame J. '
        "κ = σ<sub>max</sub>/σ<sub>min</sub> (∞ at a singularity); w = Π σ<sub>i</sub>.</div>"
    )
    return f'<div class="jl"><table class="jl-table">{body}</table>{note}</div>'


def _plain(html_text: str) -> str:
    """The visible text of a small HTML fragment (for a hover title)."""
    import html
    import re

    return html.unescape(re.sub(r"<[^>]*>", "", html_text))


def source_html(robot: Robot, chain: object | None, meshes: tuple[int, list[str]]) -> str:
    """Where a URDF robot comes from: its file, the chain shown, and any mesh files not found."""
    if not robot.urdf_path:
        return ""
    import os

    parts = [
        f"<b>{fmt.escape(robot.title or robot.name)}</b> from {fmt.escape(os.path.basename(robot.urdf_path))}"
    ]
    if chain is not None:
        base, tip, dof = chain.base_link, chain.tip_link, chain.dof  # type: ignore[attr-defined]
        parts.append(f"chain {fmt.escape(base)} → {fmt.escape(tip)}, {dof} joints")
    found, missing = meshes
    if missing:
        shown = ", ".join(fmt.escape(m) for m in missing[:3]) + (" …" if len(missing) > 3 else "")
        parts.append(
            f'<span class="jl-warn">{len(missing)} of {found + len(missing)} mesh files not found: {shown}'
            "</span> (drawn as its DH-style picture)"
        )
    elif found:
        parts.append(f"{found} mesh files")
    return f'<div class="jl jl-note">{"; ".join(parts)}.</div>'
