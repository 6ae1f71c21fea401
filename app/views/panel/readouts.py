"""Live readouts as HTML: the status banner and the labelled measures of J.

Pure functions of a :class:`~app.core.snapshot.Snapshot` (and the state): easy
to test, and the panel only assigns the returned strings (viser skips
unchanged ones).
"""

from __future__ import annotations

import re

from kinematics import Robot
from kinematics.analysis import task_rows
from kinematics.conventions import ROW_HTML

from ...core.i18n import Translator, translations
from ...core.motion_rules import redundancy_rows
from ...core.refusals import say
from ...core.robot_texts import configuration_description
from ...core.snapshot import Loss, Snapshot
from ...core.state import LabState
from ...core.words import status_word, status_words
from .. import fmt
from ..palette import status_hex
from .live import shows_motion

__all__ = [
    "status_html",
    "status_lines",
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


def task_name(rows: tuple[int, ...], tr: Translator | None = None) -> str:
    """Words for a set of task rows."""
    _ = (tr or translations()).gettext
    if rows == (0, 1, 2, 3, 4, 5):
        return _("all six rows")
    if rows == (0, 1, 2):
        return _("tool-point velocity")
    if rows == (3, 4, 5):
        return _("tool rotation")
    if rows == (0, 1, 5):
        return _("planar rows")
    return _("rows {rows}").format(rows=row_label(rows))


def direction(u: object, tr: Translator | None = None) -> str:
    """A unit direction in words: "+z (base)" when it is a base axis, else "(0.71, 0, 0.71)"."""
    import numpy as np

    tr = tr or translations()
    v = np.asarray(u, float)
    k = int(np.argmax(np.abs(v)))
    if abs(abs(v[k]) - 1.0) < 1e-3:
        axis = f"{'+' if v[k] > 0 else '−'}{'xyz'[k]}"
        return tr.gettext("{axis} (base)").format(axis=axis)
    # a list of numbers with decimal commas is separated by semicolons
    sep = "; " if tr.decimal_symbol == "," else ", "
    return "(" + sep.join(fmt.number(0.0 if abs(x) < 5e-3 else x, 2, tr) for x in v) + ")"


def _share(share: float, tr: Translator) -> str:
    return "" if share > 0.999 else f" {fmt.number(100 * share, 2, tr)} %"


def _tool_line(loss: Loss, planar: bool, tr: Translator) -> str:
    _ = tr.gettext
    parts = []
    if loss.translation_share >= 0.1 or planar:
        parts.append(
            _("translation{share} along {direction}").format(
                share=_share(loss.translation_share, tr), direction=direction(loss.translation, tr)
            )
        )
    if loss.rotation_share >= 0.1 and not planar:
        parts.append(
            _("rotation{share} about {direction}").format(
                share=_share(loss.rotation_share, tr), direction=direction(loss.rotation, tr)
            )
        )
    return _("<b>Lost</b>: {what}.").format(what=" + ".join(parts) or _("a mixed direction"))


def lost_text(snap: Snapshot, planar: bool, tr: Translator | None = None) -> str:
    """What is lost, in words, one sentence per part (empty when regular): the wrist's rotation and the
    arm's translation of the wrist centre for a spherical wrist, else every direction lost at the tool
    point, with the point and the weighing it refers to."""
    if not snap.losses:
        return ""
    tr = tr or translations()
    _ = tr.gettext
    exact = snap.report.status == "singular"
    arm = [direction(x.translation, tr) for x in snap.losses if x.part == "arm"]
    wrist = [direction(x.rotation, tr) for x in snap.losses if x.part == "wrist"]
    lines = []
    if wrist:
        axes = _(" and ").join(wrist)
        if exact:
            lines.append(
                _("<b>Wrist singular</b>: the wrist loses a rotation about {axes}.").format(axes=axes)
            )
        else:
            lines.append(
                _(
                    "<b>Near a wrist singularity</b>: the wrist can hardly give a rotation about {axes}."
                ).format(axes=axes)
            )
    if arm:
        axes = _(" nor ").join(arm)
        if exact:
            lines.append(
                _("<b>Arm singular</b>: the wrist centre cannot move along {axes}.").format(axes=axes)
            )
        else:
            lines.append(
                _("<b>Near an arm singularity</b>: the wrist centre can hardly move along {axes}.").format(
                    axes=axes
                )
            )
    if arm or wrist:
        zero = _(" and ").join(
            f"det J<sub>{k}</sub> = 0" for k, part in (("11", arm), ("22", wrist)) if part and exact
        )
        decoupled = _(
            "Decoupled at the wrist centre: det J = det J<sub>11</sub> (arm) · det J<sub>22</sub> (wrist)"
        )
        lines.append(decoupled + (f"; {zero}." if zero else "."))
        return "<br>".join(lines)
    lines = [_tool_line(loss, planar, tr) for loss in snap.losses]
    mixed = any(r < 3 for r in snap.rows) and any(r >= 3 for r in snap.rows)
    length = fmt.quantity(snap.length, "m", tr=tr)
    if len(snap.rows) == 6:
        line = (
            _("Measured at the tool point, rad/s weighed as the tool moving L = {length} (the reach).")
            if mixed
            else _("Measured at the tool point.")
        )
    else:
        line = (
            _(
                "Measured at the tool point (rows {rows}), rad/s weighed as the tool moving L = {length} "
                "(the reach)."
            )
            if mixed
            else _("Measured at the tool point (rows {rows}).")
        )
    lines.append(line.format(rows=row_label(snap.rows), length=length))
    if "wrist" in snap.report.kinds:
        lines.append(_("The wrist axes lie in one plane (not decoupled: no spherical wrist on an arm)."))
    return "<br>".join(lines)


def status_html(snap: Snapshot, state: LabState, tr: Translator | None = None) -> str:
    """The coloured banner ("regular", "near singular: wrist", "singular: wrist") with κ, and one line
    under it: the visited configuration's description, or why a motion stopped.

    The banner and the J(q) tab show it for the same redraw: the last one is kept (by identity).
    """
    tr = tr or translations()
    last = _LAST_STATUS[0]  # one tuple, read and replaced whole: safe with tabs on several threads
    if last is not None and last[0] is snap and last[1] is state and last[2] is tr:
        return last[3]
    html = _status_html(snap, state, tr)
    _LAST_STATUS[0] = (snap, state, tr, html)
    return html


_LAST_STATUS: list[tuple[Snapshot, LabState, Translator, str] | None] = [None]


def _status_html(snap: Snapshot, state: LabState, tr: Translator) -> str:
    r = snap.report
    icon = "●" if r.status == "regular" else "▲" if r.status == "near singular" else "■"
    words = status_words(state.robot, r.status, tuple(r.kinds), state.configuration, tr)
    climb = _climb(state, tr)
    beside = f" · {climb[0]}" if climb else ""  # the measure the climb raises, beside the task rows' κ
    banner = (
        f'<div class="jl-status" style="background:{status_hex(r.status)}" data-status="{r.status}">'
        f"<span>{icon}</span><span>{fmt.escape(words)}</span>"
        f'<small style="margin-left:auto">κ = {fmt.number(r.condition, tr=tr)}{beside}</small></div>'
    )
    # While a motion plays and once it has stopped, its lines are in the readout over the 3-D view
    # (status_lines, beside the rates) and the block here keeps the height it had at the click on Play
    # (the page script holds it), so nothing in the panel moves under the pointer (issue 28, 4).
    lines = "" if shows_motion(state) else status_lines(snap, state, tr)
    held = " jl-held" if state.playing or state.stopped else ""
    return f'<div class="jl">{banner}<div class="jl-lines{held}">{lines}</div></div>'


def status_lines(snap: Snapshot, state: LabState, tr: Translator) -> str:
    """The lines under the banner: the representation's singularity, the climb, the configuration's
    description or why a motion stopped, the lost direction, the critical points at joint limits."""
    _ = tr.gettext
    r = snap.report
    climb = _climb(state, tr)
    robot = state.robot
    sub, at_limit = "", False
    if state.stopped:
        # A motion that met a joint limit ends at it: the critical-point line below says why it stopped.
        at_limit = bool(snap.limits) and _LIMIT_STOP.match(state.stopped) is not None
        sub = "" if at_limit else fmt.escape(say(state.stopped, tr))
    elif state.configuration:
        conf = next((c for c in robot.configurations if c.name == state.configuration), None)
        text = configuration_description(conf, tr) if conf is not None else ""
        sub = f"<b>{fmt.escape(state.configuration.replace('_', ' '))}</b>" + (
            f": {fmt.escape(text)}" if text else ""
        )
    lost = lost_text(snap, robot.planar, tr)
    a = snap.analytic
    representation = ""
    if a is not None and a.singular:
        representation = _(
            "<b>representation singular</b> ({convention}, {where}): no J<sub>A</sub>; "
            "J: {status}, rank {rank}"
        ).format(
            convention=a.convention.upper(),
            where=_("pitch ±90°") if a.convention == "zyx" else _("θ = 0 or 180°"),
            status=status_word(r.status, tr),
            rank=snap.rank,
        )
        if a.regular_instead:
            representation += _("; {convention} is regular here").format(convention=a.regular_instead.upper())
    # Every line wraps; a configuration's description (up to 376 characters) keeps at most two lines,
    # ending in "…" when cut, so the sliders stay in sight on a projector; a click on it shows all of it
    # (a checkbox and its label: no script), until the next change redraws the status. The lines keep
    # the height of such a description when fewer are shown, so the sliders below do not jump up under
    # the pointer as a drag leaves a named configuration (or down as a "lost" line comes and goes).
    limits = limit_text(snap, robot, tr, stopped=at_limit)
    return "".join(
        _description(x) if x is sub and not state.stopped else f'<div class="jl-sub">{x}</div>'
        for x in (
            representation,
            climb[1] if climb else "",
            sub,
            lost,
            limits,
        )
        if x
    )


def _climb(state: LabState, tr: Translator) -> tuple[str, str] | None:
    """While the manipulability climb plays (and once it stopped): the measure it raises, w of the rows it
    holds, for the banner ("w(vₓ, v_y) = 0.45"), and the line saying it climbs from its start to now and
    that the banner's κ, of all task rows, may rise meanwhile (issue 28, stumble 8: the 3R arm's κ went
    16.6 → 21.1 while the screen said "climbing"); None otherwise."""
    m = state.motion
    if m.kind != "climb" or m.trace is None or len(m.trace) < 1 or not (state.playing or state.stopped):
        return None
    rows = redundancy_rows(state.robot)
    if rows is None:
        return None
    held = ", ".join(ROW_HTML[r] for r in rows)
    measure = f"w({held})"
    start, now = (fmt.number(float(m.trace.w[i]), tr=tr) for i in (0, -1))
    line = tr.gettext("<b>Climbing</b> {measure} = √det(J Jᵀ) of the held rows: {start} → {now}.").format(
        measure=measure, start=start, now=now
    )
    if rows != task_rows(state.robot):
        task = ", ".join(ROW_HTML[r] for r in task_rows(state.robot))
        line += " " + tr.gettext(
            "The banner's κ is of all task rows ({rows}): it may rise meanwhile."
        ).format(rows=task)
    return f"{measure} = {now}", line


def _description(html: str) -> str:
    """A configuration's description: two lines, all of it on a click (and in its tooltip)."""
    return (
        '<input type="checkbox" id="jl-desc-all" class="jl-desc-all" hidden>'
        f'<label for="jl-desc-all" class="jl-sub jl-desc" title="{fmt.escape(_plain(html))}">{html}</label>'
    )


def measures_html(snap: Snapshot, robot: Robot, tr: Translator | None = None) -> str:
    """The table of measures, each labelled with what it is (task rows named)."""
    tr = tr or translations()
    _ = tr.gettext
    n_rows, n = len(snap.rows), robot.dof
    num = lambda x: fmt.number(x, tr=tr)  # noqa: E731
    rows = [
        (_("κ, task ({task})").format(task=task_name(snap.rows, tr)), num(snap.report.condition)),
        (
            _("κ translational (v rows)")
            if not robot.planar
            else _("κ translational (v<sub>x</sub>, v<sub>y</sub>)"),
            num(snap.cond_translational),
        ),
    ]
    if snap.cond_rotational is not None:
        rows.append((_("κ rotational (ω rows)"), num(snap.cond_rotational)))
    sep = "; " if tr.decimal_symbol == "," else ", "  # a list of decimal-comma numbers
    rows += [
        ("w = √det(J Jᵀ)", num(snap.manipulability)),
        ("σ", sep.join(num(s) for s in fmt.cleaned(snap.sigma))),
        (
            "det J",
            num(snap.det)
            if snap.det is not None
            else _("— ({rows}×{joints}, not square)").format(rows=n_rows, joints=n),
        ),
        (_("rank"), _("{rank} of {most}").format(rank=snap.rank, most=min(n_rows, n))),
    ]
    d = snap.decoupling
    if d is not None:
        arm = num(d.det_arm) if d.det_arm is not None else f"σ<sub>min</sub> {num(d.sigma_arm[-1])}"
        rows.append((_("arm J<sub>11</sub> (wrist centre), det"), arm))
        rows.append((_("wrist J<sub>22</sub>, det"), num(d.det_wrist)))
    body = "".join(
        f'<tr><th>{label}</th><td class="{"v wrap" if sep in value else "v"}">{value}</td></tr>'
        for label, value in rows
    )
    note = _(
        "Task rows {rows} of the base-frame J. κ = σ<sub>max</sub>/σ<sub>min</sub> (∞ at a singularity); "
        "w = Π σ<sub>i</sub>."
    ).format(rows=row_label(snap.rows))
    return f'<div class="jl"><table class="jl-table">{body}</table><div class="jl-note">{note}</div></div>'


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


_LIMIT_STOP = re.compile(r"stopped: joint \d+ .* would pass its (upper|lower) limit ")
"""The resolved-rate stop at a joint limit (kinematics' Stop message after motion_rules' "stopped: ")."""


def limit_text(snap: Snapshot, robot: Robot, tr: Translator, stopped: bool = False) -> str:
    """Why a configuration with a joint at a limit is critical (002: the joint-limit points), one sentence
    per such joint; empty when none is. The joint is named once, by its name ("q2 shoulder", "A2"), which
    carries its number. ``stopped``: a motion ended there (the short form says why it stopped, in the
    height the stop's own sentence took)."""
    _ = tr.gettext
    lines = []
    for c in snap.limits if stopped else ():
        template = (
            _("<b>Critical point</b>: {name} at its lower limit, q̇{number} ≥ 0.")
            if c.side == "lower"
            else _("<b>Critical point</b>: {name} at its upper limit, q̇{number} ≤ 0.")
        )  # fmt: skip
        lines.append(template.format(number=c.joint + 1, name=fmt.escape(robot.joint_names[c.joint])))
    for c in snap.limits if not stopped else ():
        template = (
            _(
                "<b>Critical point</b>: joint {name} is at its lower limit, so it can only "
                "increase (q̇{number} ≥ 0): the tool velocity along column {number} of J is possible in "
                "that sense only."
            )
            if c.side == "lower"
            else _(
                "<b>Critical point</b>: joint {name} is at its upper limit, so it can only "
                "decrease (q̇{number} ≤ 0): the tool velocity along column {number} of J is possible in "
                "the opposite sense only."
            )
        )
        lines.append(template.format(number=c.joint + 1, name=fmt.escape(robot.joint_names[c.joint])))
    return "<br>".join(lines)
