"""Live readouts as HTML: the status banner and the labelled measures of J.

Pure functions of a :class:`~app.core.snapshot.Snapshot` (and the state): easy
to test, and the panel only assigns the returned strings (viser skips
unchanged ones).
"""

from __future__ import annotations

from kinematics import Robot
from kinematics.conventions import ROW_HTML

from ...core.snapshot import Loss, Snapshot
from ...core.state import LabState
from ...core.words import status_words
from .. import fmt
from ..palette import status_hex

__all__ = [
    "status_html",
    "measures_html",
    "source_html",
    "ROW_NAMES",
    "row_label",
    "task_name",
    "lost_text",
    "direction",
]

ROW_NAMES = ROW_HTML


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


def direction(u: object) -> str:
    """A unit direction in words: "+z" when it is a base axis, else "(0.71, 0, 0.71)"."""
    import numpy as np

    v = np.asarray(u, float)
    k = int(np.argmax(np.abs(v)))
    if abs(abs(v[k]) - 1.0) < 1e-3:
        return f"{'+' if v[k] > 0 else '−'}{'xyz'[k]} (base)"
    return "(" + ", ".join(fmt.number(0.0 if abs(x) < 5e-3 else x, 2) for x in v) + ")"


def _tool_line(loss: Loss, planar: bool) -> str:
    parts = []
    if loss.translation_share >= 0.1 or planar:
        share = "" if loss.translation_share > 0.999 else f" {fmt.number(100 * loss.translation_share, 2)} %"
        parts.append(f"translation{share} along {direction(loss.translation)}")
    if loss.rotation_share >= 0.1 and not planar:
        share = "" if loss.rotation_share > 0.999 else f" {fmt.number(100 * loss.rotation_share, 2)} %"
        parts.append(f"rotation{share} about {direction(loss.rotation)}")
    return f"<b>Lost</b>: {' + '.join(parts) or 'a mixed direction'}."


def lost_text(snap: Snapshot, planar: bool) -> str:
    """What is lost, in words, one sentence per part (empty when regular): the wrist's rotation and the
    arm's translation of the wrist centre for a spherical wrist, else every direction lost at the tool
    point, with the point and the weighing it refers to."""
    if not snap.losses:
        return ""
    exact = snap.report.status == "singular"
    arm = [direction(x.translation) for x in snap.losses if x.part == "arm"]
    wrist = [direction(x.rotation) for x in snap.losses if x.part == "wrist"]
    lines = []
    if wrist:
        head, verb = ("Wrist singular", "loses") if exact else ("Near a wrist singularity", "can hardly give")
        lines.append(f"<b>{head}</b>: the wrist {verb} a rotation about {' and '.join(wrist)}.")
    if arm:
        head, verb = ("Arm singular", "cannot") if exact else ("Near an arm singularity", "can hardly")
        lines.append(f"<b>{head}</b>: the wrist centre {verb} move along {' nor '.join(arm)}.")
    if arm or wrist:
        zero = " and ".join(
            f"det J<sub>{k}</sub> = 0" for k, part in (("11", arm), ("22", wrist)) if part and exact
        )
        lines.append(
            "Decoupled at the wrist centre: det J = det J<sub>11</sub> (arm) · det J<sub>22</sub> (wrist)"
            + (f"; {zero}." if zero else ".")
        )
        return "<br>".join(lines)
    lines = [_tool_line(loss, planar) for loss in snap.losses]
    mixed = any(r < 3 for r in snap.rows) and any(r >= 3 for r in snap.rows)
    weigh = (
        f", rad/s weighed as the tool moving L = {fmt.quantity(snap.length, 'm')} (the reach)"
        if mixed
        else ""
    )
    rows = "" if len(snap.rows) == 6 else f" (rows {row_label(snap.rows)})"
    lines.append(f"Measured at the tool point{rows}{weigh}.")
    if "wrist" in snap.report.kinds:
        lines.append("The wrist axes lie in one plane (not decoupled: no spherical wrist on an arm).")
    return "<br>".join(lines)


def status_html(snap: Snapshot, state: LabState) -> str:
    """The coloured banner ("regular", "near singular: wrist", "singular: wrist") with κ, and one line
    under it: the visited configuration's description, or why a motion stopped.

    The banner and the J(q) tab show it for the same redraw: the last one is kept (by identity).
    """
    last = _LAST_STATUS[0]  # one tuple, read and replaced whole: safe with tabs on several threads
    if last is not None and last[0] is snap and last[1] is state:
        return last[2]
    html = _status_html(snap, state)
    _LAST_STATUS[0] = (snap, state, html)
    return html


_LAST_STATUS: list[tuple[Snapshot, LabState, str] | None] = [None]


def _status_html(snap: Snapshot, state: LabState) -> str:
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
        + (f"; {a.regular_instead.upper()} is regular here" if a.regular_instead else "")
        if a is not None and a.singular
        else ""
    )
    # Every line wraps; a configuration's description (up to 376 characters) keeps at most two lines,
    # ending in "…" when cut, so the sliders stay in sight on a projector; a click on it shows all of it
    # (a checkbox and its label: no script), until the next change redraws the status. The lines keep
    # the height of such a description when fewer are shown, so the sliders below do not jump up under
    # the pointer as a drag leaves a named configuration (or down as a "lost" line comes and goes).
    lines = "".join(
        _description(x) if x is sub and not state.stopped else f'<div class="jl-sub">{x}</div>'
        for x in (representation, sub, lost)
        if x
    )
    return f'<div class="jl">{banner}<div class="jl-lines">{lines}</div></div>'


def _description(html: str) -> str:
    """A configuration's description: two lines, all of it on a click (and in its tooltip)."""
    return (
        '<input type="checkbox" id="jl-desc-all" class="jl-desc-all" hidden>'
        f'<label for="jl-desc-all" class="jl-sub jl-desc" title="{fmt.escape(_plain(html))}">{html}</label>'
    )


FIRST_HINT = (
    "<b>First:</b> drag a joint slider and watch J(q) change; then pick a singularity under Configuration."
)
"""What a new tab says to do first, in the 3-D view's lower corner, until its first change."""


def hint_html(state: LabState) -> str:
    """The first hint ("" once the tab has changed anything: gone for good)."""
    return "" if state.started else f'<div class="jl jl-hint">{FIRST_HINT}</div>'


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
    d = snap.decoupling
    if d is not None:
        arm = (
            fmt.number(d.det_arm)
            if d.det_arm is not None
            else f"σ<sub>min</sub> {fmt.number(d.sigma_arm[-1])}"
        )
        rows.append(("arm J<sub>11</sub> (wrist centre), det", arm))
        rows.append(("wrist J<sub>22</sub>, det", fmt.number(d.det_wrist)))
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
