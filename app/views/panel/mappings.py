"""The course's three mappings, one tab each: v = J q̇, q̇ = J⁺ v, τ = Jᵀ F.

* **v = J q̇**: joint-rate sliders, the tool twist they produce, and Play,
  which moves the joints at those rates in time (the tab's ticker).
* **q̇ = J⁺ v**: a desired tool twist (task rows only) and the joint rates
  J⁺ v (or damped) as bars that saturate (hatched) near a singularity, with
  the twist those rates actually produce, J q̇, and what is lost, v − J q̇:
  at a singularity J⁺ drops the lost direction, and damping trades accuracy
  for bounded rates, visibly.
* **τ = Jᵀ F**: a force and moment at the tool and the joint torques.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import viser

from kinematics import Robot
from kinematics.conventions import ROW_TEXT, WRENCH_TEXT

from ...core.actions import (
    ApplyPreset,
    ClearWrench,
    Play,
    SetDesired,
    SetOption,
    SetRate,
    SetWrench,
    StopRates,
)
from ...core.ranges import Range, from_display, rate_ranges, to_display, twist_ranges, wrench_ranges
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...viser_adapter import handle_uuid
from .. import fmt
from ..palette import joint_hex, joint_text_hex
from .common import Dispatch, bind, bind_click, sync_value
from .course import accel_html, example_html, inverse_html
from .readouts import ROW_NAMES
from .style import slider_css

__all__ = ["ForwardPanel", "InversePanel", "ForcePanel", "bars_html", "vector_table_html"]


def _display(kind: str, value: float) -> tuple[float, str]:
    return (math.degrees(value), "°/s") if kind == "revolute" else (float(value), "m/s")


def bars_html(values: list[tuple[float, str]], robot: Robot, full_scale: list[float], caption: str) -> str:
    """One centred bar per joint, coloured like the joint; a bar beyond ``full_scale`` is hatched.

    Args:
        values: (value, unit) per joint, in display units (float noise already cleaned).
        robot: The robot (joint count).
        full_scale: Value at which each bar reaches the edge.
        caption: Text under the bars (HTML).
    """
    rows = []
    for i, ((v, unit), full) in enumerate(zip(values, full_scale, strict=True)):
        v = float(v) if math.isfinite(v) else 0.0
        frac = min(abs(v) / full, 1.0) if full > 0 else 0.0
        left = 50.0 if v >= 0 else 50.0 - 50.0 * frac
        bar_class = "jl-bar over" if abs(v) > full else "jl-bar"
        bar_style = f"left:{left:.2f}%;width:{50.0 * frac:.2f}%;background-color:{joint_hex(i)}"
        title = fmt.escape(robot.joints[i].name)
        rows.append(
            f'<tr><td class="name" style="color:{joint_text_hex(i)}" title="{title}">q{i + 1}</td>'
            f'<td class="track"><div class="jl-bar-bg"><div class="jl-bar-mid"></div>'
            f'<div class="{bar_class}" style="{bar_style}"></div></div></td>'
            f'<td class="val">{fmt.quantity(v, unit)}</td></tr>'
        )
    table = f'<table class="jl-bars">{"".join(rows)}</table>'
    return f'<div class="jl">{table}<div class="jl-note">{caption}</div></div>'


def vector_table_html(rows: tuple[int, ...], columns: list[tuple[str, np.ndarray, str]]) -> str:
    """A table of twists: one line per (label, twist (6,), css class), one column per row of ``rows``.

    v rows are in m/s, ω rows in °/s (like the sliders).
    """
    head = "".join(f"<th>{ROW_NAMES[r]}</th>" for r in rows)
    body = []
    for label, twist, css in columns:
        shown = fmt.cleaned([twist[r] if r < 3 else math.degrees(twist[r]) for r in rows])
        cells = "".join(f"<td>{fmt.number(x)}</td>" for x in shown)
        body.append(f'<tr class="{css}"><th class="rowname">{label}</th>{cells}</tr>')
    units = "v in m/s, ω in °/s" if any(r >= 3 for r in rows) else "m/s"
    return (
        f'<div class="jl"><table class="jl-vec"><tr><th></th>{head}</tr>{"".join(body)}</table>'
        f'<div class="jl-note">{units}, base axes</div></div>'
    )


def _slider(gui: viser.GuiApi, label: str, r: Range, hint: str) -> viser.GuiSliderHandle:
    return gui.add_slider(
        f"{label} [{r.unit}]", min=r.lo, max=r.hi, step=r.step, initial_value=0.0, hint=hint
    )


class ForwardPanel:
    """Joint rates → tool twist; Play moves the joints at those rates."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, robot: Robot, order: float) -> None:
        self.robot = robot
        self.ranges = rate_ranges(robot)
        self.root = gui.add_folder(None, order=order)
        css = []
        with self.root:
            self.twist = gui.add_html("")  # the result first: in sight while the sliders move
            self.accel = gui.add_html("")  # J̇ q̇: the tool's acceleration at constant rates
            self.sliders = []
            for i, (joint, r) in enumerate(zip(robot.joints, self.ranges, strict=True)):
                slider = _slider(gui, f"q̇{i + 1}", r, f"rate of {joint.name}")
                bind(slider, dispatch, functools.partial(_set_rate, i, r))
                css.append(slider_css(handle_uuid(slider), i))
                self.sliders.append(slider)
            gui.add_html(f"<style>{''.join(css)}</style>")
            self._shown: tuple | None = None
            self.play = gui.add_button("Play: move at these rates", icon=viser.Icon.PLAYER_PLAY)
            self._playing = False
            bind_click(self.play, dispatch, lambda: Play(not self._playing))
            stop = gui.add_button("Stop (q̇ = 0)", icon=viser.Icon.PLAYER_STOP)
            bind_click(stop, dispatch, StopRates)
            self.jdot = gui.add_checkbox(
                "J̇ q̇ arrow at the tool",
                initial_value=True,
                hint="The tool's acceleration when the joints turn at constant rate (ẍ = J̇ q̇ when q̈ = 0)",
            )
            bind(self.jdot, dispatch, lambda v: SetOption("jdot_arrow", bool(v)))

    def show(self, state: LabState) -> None:
        for i, (slider, r) in enumerate(zip(self.sliders, self.ranges, strict=True)):
            sync_value(slider, round(to_display(r, state.qd[i]), 6))
        sync_value(self.jdot, bool(state.options.jdot_arrow))
        if self._playing != state.playing:
            self._playing = state.playing
            self.play.label = "Pause" if state.playing else "Play: move at these rates"
            self.play.icon = viser.Icon.PLAYER_PAUSE if state.playing else viser.Icon.PLAYER_PLAY

    def update(self, snap: Snapshot, state: LabState) -> None:
        idle = ("idle", state.stopped) if not state.qd.any() else None  # nothing moves: nothing to redo
        if idle is not None and idle == self._shown:
            return
        self._shown = idle
        self.accel.content = accel_html(snap.jdot_qd) if idle is None else ""
        note = f'<div class="jl-warn">{fmt.escape(state.stopped)}</div>' if state.stopped else ""
        self.twist.content = (
            vector_table_html(tuple(range(6)), [("J q̇", snap.twist, "")])
            + note
            + '<div class="jl-note">Black arrow at the tool: v; umber arrow: ω.</div>'
        )

    def remove(self) -> None:
        self.root.remove()


class InversePanel:
    """Desired tool twist → joint rates J⁺ v (or damped), with what they produce and what is lost."""

    def __init__(
        self,
        gui: viser.GuiApi,
        dispatch: Dispatch,
        robot: Robot,
        rows: tuple[int, ...],
        order: float,
        presets: Sequence[Any] = (),
    ):
        self.robot = robot
        self.rows = rows
        self._rows = list(rows)
        self.ranges = twist_ranges(robot)
        self.root = gui.add_folder(None, order=order)
        # The course's worked example: the first preset in base axes (a twist held from a configuration).
        self.example = next((p for p in presets if p.frame == "base"), None)
        self._example_start = next(
            (
                c.name
                for c in robot.configurations
                if self.example is not None and np.allclose(c.q, self.example.q)
            ),
            "",
        )
        self.example_button: viser.GuiButtonHandle | None = None
        with self.root:
            if self.example is not None:
                p = self.example
                # The course's worked example carries its joint rates; another robot's preset is an example.
                label = "Course example" if p.rates is not None else f"Example: {p.name}"[:60]
                self.example_button = gui.add_button(label, icon=viser.Icon.SCHOOL)
                bind_click(
                    self.example_button,
                    dispatch,
                    lambda: ApplyPreset(
                        p.name, tuple(map(float, p.q)), tuple(map(float, p.twist)), p.frame, p.speed
                    ),
                )
            self.rates = gui.add_html("")  # the results first: in sight while the sliders move
            self.result = gui.add_html("")
            self.inverse = gui.add_html("")  # J⁻¹ (or J⁺) at q, live
            self.course = gui.add_html("")
            self.sliders = {}
            for r in rows:
                slider = _slider(gui, ROW_TEXT[r], self.ranges[r], "desired tool velocity, base axes")
                bind(slider, dispatch, functools.partial(_set_desired, r, self.ranges[r]))
                self.sliders[r] = slider
            self.damping = gui.add_slider(
                "damping λ",
                min=0.0,
                max=0.5,
                step=0.005,
                initial_value=0.0,
                hint="0: pseudo-inverse J⁺; > 0: damped least squares (bounded rates, less accuracy)",
            )
            bind(self.damping, dispatch, lambda v: SetOption("damping", float(v)))
            self._shown: tuple | None = None
            self.symbolic_button: viser.GuiButtonHandle | None = None
            self.symbolic = gui.add_html("")
            if len(rows) == robot.dof:  # a square task J: its inverse, symbolically, on demand
                self.symbolic_button = gui.add_button("Symbolic J⁻¹ = adj J / det J", icon=viser.Icon.MATH)
                bind_click(
                    self.symbolic_button, dispatch, lambda: SetOption("symbolic_inverse", not self._asked)
                )
            self._asked = False

    def show(self, state: LabState) -> None:
        for r, slider in self.sliders.items():
            sync_value(slider, round(to_display(self.ranges[r], state.v_desired[r]), 6))
        sync_value(self.damping, float(state.options.damping))
        asked = state.options.symbolic_inverse
        if asked != self._asked and self.symbolic_button is not None:
            self.symbolic_button.label = "Hide the symbolic J⁻¹" if asked else "Symbolic J⁻¹ = adj J / det J"
            if not asked:
                self.symbolic.content = ""
        self._asked = asked

    def show_symbolic(self, mathml: str | None, note: str) -> None:
        """Show the symbolic J⁻¹ (``None``: only the note)."""
        if not self._asked:
            return
        body = f'<div class="jl-mathml" style="overflow-x:auto">{mathml}</div>' if mathml else ""
        self.symbolic.content = f'<div class="jl">{body}<div class="jl-note">{fmt.escape(note)}</div></div>'

    def update(self, snap: Snapshot, state: LabState) -> None:
        self.inverse.content = inverse_html(snap.inverse, self.robot, snap.rows, state, snap.report.status)
        p = self.example
        if p is not None:
            question = state.configuration == "course_question"
            self.course.content = example_html(snap, state, p.rates, self._example_start, question)
        idle = ("idle", state.options.damping) if not state.v_desired[self._rows].any() else None
        if idle is not None and idle == self._shown:
            return
        self._shown = idle
        kinds = [j.kind for j in self.robot.joints]
        shown = fmt.cleaned([_display(k, v)[0] for k, v in zip(kinds, snap.rates, strict=True)])
        values = [(x, _display(k, 0.0)[1]) for x, k in zip(shown, kinds, strict=True)]
        full = [180.0 if k == "revolute" else 0.5 for k in kinds]
        lam = state.options.damping
        method = f"damped least squares, λ = {fmt.number(lam)}" if lam > 0 else "pseudo-inverse J⁺"
        self.rates.content = bars_html(
            values, self.robot, full, f"q̇ = J⁺ v ({method}); hatched: beyond 180 °/s (0.5 m/s)."
        )
        desired = np.zeros(6)
        desired[list(snap.rows)] = state.v_desired[list(snap.rows)]
        wanted = float(np.linalg.norm(desired))
        lost = float(np.linalg.norm(snap.shortfall))
        table = vector_table_html(
            snap.rows,
            [
                ("v wanted", desired, ""),
                ("J q̇ made", snap.produced, ""),
                ("v − J q̇ lost", snap.shortfall, "lost"),
            ],
        )
        if wanted > 0 and lost > 1e-6 * max(wanted, 1.0):
            why = (
                "the arm is singular: J⁺ drops the direction it has lost"
                if snap.report.status == "singular" and lam == 0
                else "damping trades accuracy for bounded joint rates"
                if lam > 0
                else "this twist is outside what the joints can produce"
            )
            table += (
                f'<div class="jl-warn">{fmt.number(100 * lost / wanted)} % of v is not produced: {why}.</div>'
            )
        self.result.content = table

    def remove(self) -> None:
        self.root.remove()


class ForcePanel:
    """Force and moment at the tool → joint torques τ = Jᵀ F."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, robot: Robot, order: float):
        self.robot = robot
        self.ranges = wrench_ranges(robot)
        self.root = gui.add_folder(None, order=order)
        rows = (0, 1, 5) if robot.planar else range(6)
        with self.root:
            self.torques = gui.add_html("")  # the result first: in sight while the sliders move
            self.sliders = {}
            self._bounds: dict[int, tuple[float, float]] = {}
            for r in rows:
                slider = _slider(gui, WRENCH_TEXT[r], self.ranges[r], "applied at the tool point, base axes")
                bind(slider, dispatch, functools.partial(_set_wrench, r))
                self.sliders[r] = slider
                self._bounds[r] = (float(slider.min), float(slider.max))
            zero = gui.add_button("Remove the force (F = 0)")
            bind_click(zero, dispatch, ClearWrench)
            self._idle = False

    def show(self, state: LabState) -> None:
        for r, slider in self.sliders.items():
            lo, hi = self._bounds[r]  # the slider's range (reading slider.min and .max costs more)
            sync_value(slider, min(max(float(state.wrench[r]), lo), hi))

    def update(self, snap: Snapshot, state: LabState) -> None:
        idle = not state.wrench.any()
        if idle and self._idle:
            return
        self._idle = idle
        units = ["N·m" if j.kind == "revolute" else "N" for j in self.robot.joints]
        values = list(zip(fmt.cleaned(snap.torques), units, strict=True))
        full = max(abs(self.ranges[0].hi), 1.0)
        self.torques.content = bars_html(
            values,
            self.robot,
            [full] * self.robot.dof,
            f"Joint torques τ = Jᵀ F that hold the wrench (full bar: {fmt.number(full)} N·m or N). "
            "At a singularity a force along the lost direction needs no torque at all.",
        )

    def remove(self) -> None:
        self.root.remove()


def _set_rate(i: int, r: Range, value: Any) -> SetRate:
    return SetRate(i, from_display(r, float(value)))


def _set_desired(row: int, r: Range, value: Any) -> SetDesired:
    return SetDesired(row, from_display(r, float(value)))


def _set_wrench(row: int, value: Any) -> SetWrench:
    return SetWrench(row, float(value))
