"""The singularity explorer's Motion tab (resolved rate, drive the tool, redundancy, the nearest
singularity); the Maps tab is :mod:`.maps`.

Views only: every control dispatches an action; :meth:`MotionPanel.draw` puts a state and its
snapshot on screen. Charts are uPlot (viser's ``add_uplot``) fed from the
state's trace, which holds only finite numbers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import viser
import viser.uplot as uplot

import robots
from kinematics import Robot
from kinematics.analysis import task_rows
from kinematics.conventions import ROW_TEXT

from ...core.actions import ApplyPreset, Play, ResetMotion, SelfMove, StepOnce
from ...core.commands import FindSingularity
from ...core.i18n import N_, Translator, translations
from ...core.motion_rules import redundancy_rows
from ...core.motion_state import Trace
from ...core.refusals import say
from ...core.robot_texts import motion_description, motion_name
from ...core.self_motion import is_null_motion
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...core.tool_path import is_tool_path
from .. import fmt
from ..palette import joint_hex
from .common import Dispatch, bind, option_widget, show_option, sync_value
from .course_motion import CourseMotion
from .errata import erratum_html

__all__ = ["MotionPanel", "OWN_TWIST", "PLAY_BUTTONS"]

OWN_TWIST = N_("your own v (set in q̇ = J⁺v)")
"""The preset menu's last entry, in English (the menu shows it in the tab's language)."""
PLAY_BUTTONS = (N_("Play"), N_("Pause"), N_("Step"), N_("Reset"))
"""The play buttons' English labels (the keys of their actions; shown in the tab's language)."""
_CHART_HEIGHT = 150
_Y_TICK_SPACE = 14
"""Least space between two y ticks [px] (uPlot's default, 30, left one or two ticks on a 150 px chart)."""


def _chart(
    gui: viser.GuiApi,
    title: str,
    labels: Sequence[str],
    colors: Sequence[str],
    y: str,
    x: str,
    log: bool = False,
):
    series: list[uplot.Series] = [{"label": "t"}]
    series += [{"label": lab, "stroke": c, "width": 2} for lab, c in zip(labels, colors, strict=True)]
    scales: dict[str, uplot.Scale] = {"x": {"time": False}, "y": {"distr": 3} if log else {}}
    empty = tuple(np.zeros(1) for _ in range(len(labels) + 1))
    return gui.add_uplot(
        empty,
        tuple(series),
        title=title,
        scales=scales,
        axes=({"label": x, "space": 40}, {"label": y, "space": _Y_TICK_SPACE}),
        height=_CHART_HEIGHT,
        aspect=2.0,
    )


class MotionPanel:
    """The Motion tab of one robot."""

    def __init__(
        self,
        gui: viser.GuiApi,
        dispatch: Dispatch,
        robot: Robot,
        presets: Sequence[robots.MotionPreset],
        order: float,
        tr: Translator | None = None,
    ) -> None:
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.own_twist = _(OWN_TWIST)  # the dropdown's entry in the tab's language
        self._buttons = {_(b): b for b in PLAY_BUTTONS}  # a button's words → its English key
        self.robot = robot
        self.presets = {p.name: p for p in presets}
        self._labels = {name: motion_name(p, tr) for name, p in self.presets.items()}  # name → shown
        self._names = {label: name for name, label in self._labels.items()}  # shown → name
        self.root = gui.add_folder(None, order=order)
        self._trace: Trace | None = None
        self._shown: tuple | None = None
        with self.root:
            # Resolved rate: the course's q_{k+1} = q_k + Δt J⁺ v, the tool twist held.
            with gui.add_folder(_("Resolved rate: q̇ = J⁺v held in time")):
                # The robot's first preset is shown first: Play on a fresh tab runs it (the arm goes to its
                # start), instead of refusing "your own v" = 0.
                self.preset = gui.add_dropdown(
                    _("Preset"),
                    (*self._labels.values(), self.own_twist),
                    initial_value=next(iter(self._labels.values()), self.own_twist),
                    hint=_("A start and a tool twist."),
                )
                bind(self.preset, dispatch, self._preset)
                self._own = not self.presets  # the user chose "your own v"
                self.pending: ApplyPreset | None = None  # the preset shown but not applied yet
                self.buttons = gui.add_button_group("", tuple(self._buttons))
                self.buttons.on_click(
                    lambda event: self._click(dispatch, self._buttons.get(str(event.target.value), ""))
                )
                self.readout = gui.add_html("")
                # The blow-up first: the joint rates, then κ, then σmin and w (all against the motion's t).
                names = [f"q̇{i + 1}" for i in range(robot.dof)]
                colors = [joint_hex(i) for i in range(robot.dof)]
                kinds = {j.kind for j in robot.joints}
                unit = "°/s" if kinds == {"revolute"} else "m/s" if "revolute" not in kinds else "°/s | m/s"
                # A mixed unit goes in the title: "q̇ [°/s | m/s]" did not fit the 150 px axis.
                mixed = "|" in unit
                time = _("t [s]")
                self.rates = _chart(
                    gui,
                    _("joint rates q̇ [{unit}]").format(unit=unit) if mixed else _("joint rates q̇"),
                    names,
                    colors,
                    "q̇" if mixed else f"q̇ [{unit}]",
                    time,
                )
                self.kappa = _chart(
                    gui,
                    # the scale in the title: a y-axis title is drawn along the 70 px plot, and cut beyond
                    _("condition number κ (log scale, no unit)"),
                    ("κ",),
                    ("#c2410c",),
                    "κ",
                    time,
                    log=True,
                )
                self.measures = _chart(
                    gui,
                    _("σmin and w of the task rows"),
                    ("σmin", "w"),
                    ("#c2255c", "#3b5bdb"),
                    "σmin, w",
                    time,
                )
                self.about = gui.add_html("")
                self.frame = option_widget(gui, dispatch, "twist_frame", tr=tr)
                self.speed = option_widget(gui, dispatch, "speed", tr=tr)
            # Drive the tool: IK every frame while the handle is dragged.
            with gui.add_folder(_("Drive the tool (IK)"), expand_by_default=False):
                self.gizmo = option_widget(gui, dispatch, "gizmo", tr=tr)
                self.method = option_widget(gui, dispatch, "ik_method", tr=tr)
                self.mode = option_widget(gui, dispatch, "ik_mode", tr=tr)
                self.ik = gui.add_html("")
            # Redundancy: self-motion and the manipulability climb, the tool held.
            rows = redundancy_rows(robot)
            self.redundant = rows is not None
            self.self_slider: viser.GuiSliderHandle | None = None
            self.self_chart = None
            self.notes: list[viser.GuiHtmlHandle] = []  # the course's error beside the climb
            if rows is not None:
                with gui.add_folder(_("Redundancy: move with the tool held"), expand_by_default=False):
                    gui.add_html(f'<div class="jl-note">{_redundancy_html(robot, rows, tr)}</div>')
                    self.self_slider = gui.add_slider(
                        _("Self-motion s"),
                        min=-3.0,
                        max=3.0,
                        step=0.01,
                        initial_value=0.0,
                        hint=_("along the null space"),
                    )
                    bind(self.self_slider, dispatch, lambda v: SelfMove(float(v)))
                    climb = gui.add_button(_("Climb manipulability"), icon=viser.Icon.TRENDING_UP)
                    climb.on_click(lambda _: dispatch(Play(True, "climb")))
                    self.notes.append(gui.add_html(f'<div class="jl">{erratum_html("gradient", tr)}</div>'))
                    self.self_chart = gui.add_uplot(
                        (np.zeros(1), np.zeros(1)),
                        ({"label": "s"}, {"label": "w", "stroke": "#3b5bdb", "width": 2}),
                        title=_("w along the self-motion"),
                        scales={"x": {"time": False}},
                        axes=({"label": "s"}, {"label": "w", "space": _Y_TICK_SPACE}),
                        height=_CHART_HEIGHT,
                        aspect=2.0,
                    )
            self.course = CourseMotion(gui, dispatch, tr)
            nearest = gui.add_button(_("Go to the nearest singularity"), icon=viser.Icon.TARGET)
            nearest.on_click(lambda _: dispatch(FindSingularity()))

    def _preset(self, value: Any) -> ApplyPreset | None:
        name = self._names.get(str(value), "")  # a label the menu offers, in the tab's language
        self._own = name not in self.presets
        return self._apply(name)

    def _apply(self, name: str) -> ApplyPreset | None:
        p = self.presets.get(name)
        if p is None:
            return None
        return ApplyPreset(p.name, tuple(map(float, p.q)), tuple(map(float, p.twist)), p.frame, p.speed)

    @property
    def stepped(self) -> list[Any]:
        """Its sliders whose step the page honours."""
        return [self.speed] + ([self.self_slider] if self.self_slider is not None else [])

    def _click(self, dispatch: Dispatch, label: str) -> None:  # label: the button's English key
        """Play or Step with a preset shown but not applied applies it first; then the button's action."""
        pending = self.pending
        if pending is not None and label in ("Play", "Step"):
            self.pending = None
            dispatch(pending)
        dispatch(_button(label))

    def shown_preset(self, state: LabState) -> str:
        """The preset the dropdown shows: the state's, else "your own v" once the user chose it or set a v,
        else the robot's first preset (what Play runs)."""
        m = state.motion
        if m.preset in self.presets:
            return m.preset
        if self._own or not self.presets or np.any(state.v_desired) or m.trace is not None:
            return self.own_twist
        return next(iter(self.presets))

    def draw(self, state: LabState, snap: Snapshot) -> None:
        o, m = state.options, state.motion
        shown = self.shown_preset(state)
        sync_value(self.preset, self._labels.get(shown, shown))
        self.pending = self._apply(shown) if shown != m.preset else None
        for handle, name in ((self.frame, "twist_frame"), (self.speed, "speed"), (self.gizmo, "gizmo")):
            show_option(handle, name, getattr(o, name), self.tr)
        show_option(self.method, "ik_method", o.ik_method, self.tr)
        show_option(self.mode, "ik_mode", o.ik_mode, self.tr)
        if self.self_slider is not None:
            sync_value(self.self_slider, float(round(m.s, 6)))
        key = (
            shown,
            state.playing,
            state.stopped,
            m.kind,
            tuple(np.round(state.v_desired, 9)),
            o.twist_frame,
        )
        if key != self._shown:
            self._shown = key
            self.about.content = self._about(shown)
            self.readout.content = _readout(state, snap, self.pending is not None, self.tr)
        self.ik.content = _ik_html(state, self.tr)
        self.course.draw(state, snap)
        # Charts at most every third frame while playing (each update resends the whole series).
        if (
            m.trace is not self._trace
            and m.trace is not None
            and (not state.playing or len(m.trace) % 3 == 1)
        ):
            self._trace = m.trace
            self._plot(m.trace)
        if self.self_chart is not None and len(m.self_trace) >= 2:
            s, w = _sorted_unique(m.self_trace)
            self.self_chart.data = (s, w)

    def _about(self, name: str) -> str:
        p = self.presets.get(name)
        text = motion_description(p, self.tr) if p else ""
        return f'<div class="jl-note">{fmt.escape(text)}</div>' if text else ""

    def _plot(self, trace: Trace) -> None:
        if len(trace) < 2:
            return
        t = np.asarray(trace.t, dtype=float)
        self.measures.data = (t, np.asarray(trace.sigma_min), np.asarray(trace.w))
        self.kappa.data = (t, np.maximum(np.asarray(trace.kappa), 1.0))
        kinds = [j.kind for j in self.robot.joints]
        cols = [
            np.degrees(trace.qd[:, i]) if k == "revolute" else np.asarray(trace.qd[:, i])
            for i, k in enumerate(kinds)
        ]
        self.rates.data = (t, *cols)

    def remove(self) -> None:
        self.root.remove()


def _button(label: str) -> Play | StepOnce | ResetMotion:
    if label == "Play":
        return Play(True, "resolved_rate")
    if label == "Pause":
        return Play(False)
    if label == "Step":
        return StepOnce("resolved_rate")
    return ResetMotion()


def _redundancy_html(robot: Robot, rows: tuple[int, ...], tr: Translator) -> str:
    """What the redundancy folder says: the joints, the rows held and what Climb raises."""
    held = ", ".join(ROW_TEXT[r] for r in rows)
    task = ", ".join(ROW_TEXT[r] for r in task_rows(robot))
    joints = tr.ngettext("{n} joint", "{n} joints", robot.dof).format(n=robot.dof)
    count = tr.ngettext("{n} task row held", "{n} task rows held", len(rows)).format(n=len(rows))
    if task != held:
        return tr.gettext(
            "{joints}, {rows} ({held}): the arm can move in the null space of J without moving the tool. "
            "<b>Climb</b> raises w = √det(J Jᵀ) of these rows ({held}), not the banner's κ of all task "
            "rows ({task})."
        ).format(joints=joints, rows=count, held=held, task=task)
    return tr.gettext(
        "{joints}, {rows} ({held}): the arm can move in the null space of J without moving the tool. "
        "<b>Climb</b> raises w = √det(J Jᵀ) of these rows ({held})."
    ).format(joints=joints, rows=count, held=held)


def _readout(state: LabState, snap: Snapshot, pending: bool = False, tr: Translator | None = None) -> str:
    tr = tr or translations()
    _ = tr.gettext
    if pending:
        text = _(
            "Press <b>Play</b>: the arm goes to the preset's start and its tool twist v is held (q̇ = J⁻¹ v), "
            "slowed down near the singularity so it can be followed."
        )
        return f'<div class="jl"><div class="jl-note">{text}</div></div>'
    rows = snap.rows
    v = [state.v_desired[r] if r < 3 else math.degrees(state.v_desired[r]) for r in rows]
    sep = "; " if tr.decimal_symbol == "," else ", "
    parts = sep.join(f"{ROW_TEXT[r]} {fmt.number(x, 5, tr)}" for r, x in zip(rows, v, strict=True))
    kind = state.motion.kind
    doing = (
        _("holding v")
        if kind == "resolved_rate"
        else _("climbing w of the held rows")
        if kind == "climb"
        else _("the null motion: the joints move, the tool stands still")
        if is_null_motion(state.motion)
        else _("following the path y(t)")
        if is_tool_path(state.motion)
        else _("descending to the nearest singularity")
        if kind == "path"
        else _("moving at q̇")
        if kind == "joints"
        else ""
    )
    held = (
        _("v held: {values} (m/s, °/s; tool axes).")
        if state.options.twist_frame == "tool"
        else _("v held: {values} (m/s, °/s; base axes).")
    ).format(values=parts)
    line = f'<div class="jl-note">{held}</div>'
    if state.playing:
        line += '<div class="jl-note">' + _("<b>Playing</b>: {what}.").format(what=doing) + "</div>"
    elif state.stopped:
        line += f'<div class="jl-warn">{fmt.escape(say(state.stopped, tr))}</div>'
    return f'<div class="jl">{line}</div>'


def _ik_html(state: LabState, tr: Translator | None = None) -> str:
    tr = tr or translations()
    _ = tr.gettext
    ik = state.motion.ik
    if not state.options.gizmo:
        return (
            '<div class="jl-note">'
            + _("Tick the box, then drag the handle at the tool: the arm follows.")
            + "</div>"
        )
    if ik is None:
        return '<div class="jl-note">' + _("Drag the handle at the tool.") + "</div>"
    method = _("damped least squares") if ik.method == "dls" else "Newton"
    text = (
        tr.ngettext(
            "{method}: {n} iteration, residual {residual}, converged.",
            "{method}: {n} iterations, residual {residual}, converged.",
            ik.iterations,
        )
        if ik.converged
        else tr.ngettext(
            "{method}: {n} iteration, residual {residual}, not converged.",
            "{method}: {n} iterations, residual {residual}, not converged.",
            ik.iterations,
        )
    ).format(method=method, n=ik.iterations, residual=fmt.number(ik.residual, tr=tr))
    if ik.departure > 1e-3:
        short = fmt.quantity(ik.departure * 1000, "mm", tr=tr)
        stops = (
            _("The tool stops {distance} short: damping keeps the rates bounded near the singularity.")
            if ik.method == "dls"
            else _("The tool stops {distance} short.")
        ).format(distance=short)
        text += f' <span class="jl-warn">{stops}</span>'
    return f'<div class="jl"><div class="jl-note">{text}</div></div>'


def _sorted_unique(samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = np.round(samples[:, 0], 4)
    order = np.argsort(s, kind="stable")
    s_sorted, w_sorted = s[order], samples[order, 1]
    keep = np.r_[s_sorted[1:] != s_sorted[:-1], True]  # the last sample at each s
    return s_sorted[keep], w_sorted[keep]
