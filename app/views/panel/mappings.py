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
    SetAcceleration,
    SetDesired,
    SetOption,
    SetRate,
    SetWrench,
    StopRates,
)
from ...core.i18n import Translator, translations
from ...core.ranges import (
    Range,
    accel_ranges,
    from_display,
    rate_ranges,
    to_display,
    twist_ranges,
    wrench_ranges,
)
from ...core.refusals import say
from ...core.robot_texts import motion_name
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...viser_adapter import handle_uuid
from .. import fmt
from ..shared import once
from .accel import accel_html
from .common import Dispatch, bind, bind_click, option_widget, show_option, sync_value
from .course import example_html, inverse_html
from .errata import erratum_html
from .style import slider_css
from .vectors import _display, _slider, bars_html, vector_table_html

__all__ = [
    "ForwardPanel",
    "InversePanel",
    "ForcePanel",
    "bars_html",
    "vector_table_html",
]  # the last two: .vectors


class ForwardPanel:
    """Joint rates → tool twist; Play moves the joints at those rates."""

    def __init__(
        self, gui: viser.GuiApi, dispatch: Dispatch, robot: Robot, order: float, tr: Translator | None = None
    ) -> None:
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.robot = robot
        self.ranges = rate_ranges(robot)
        self.root = gui.add_folder(None, order=order)
        css = []
        with self.root:
            self.twist = gui.add_html("")  # the result first: in sight while the sliders move
            self.accel = gui.add_html("")  # J̇ q̇: the tool's acceleration at constant rates
            self.sliders = []
            for i, (joint, r) in enumerate(zip(robot.joints, self.ranges, strict=True)):
                slider = _slider(gui, f"q̇{i + 1}", r, _("rate of {joint}").format(joint=joint.name))
                bind(slider, dispatch, functools.partial(_set_rate, i, r))
                css.append(slider_css(handle_uuid(slider), i))
                self.sliders.append(slider)
            self._shown: tuple | None = None
            self.play = gui.add_button(_("Play: move at these rates"), icon=viser.Icon.PLAYER_PLAY)
            self._playing = False
            bind_click(self.play, dispatch, lambda: Play(not self._playing))
            stop = gui.add_button(_("Stop (q̇ = 0)"), icon=viser.Icon.PLAYER_STOP)
            bind_click(stop, dispatch, StopRates)
            self.jdot = option_widget(gui, dispatch, "jdot_arrow", tr=tr)
            self.accel_ranges = accel_ranges(robot)
            self.accel_sliders = []
            with gui.add_folder(_("Joint accelerations q̈ (ẍ = J q̈ + J̇ q̇)"), expand_by_default=False):
                for i, (joint, r) in enumerate(zip(robot.joints, self.accel_ranges, strict=True)):
                    hint = _("acceleration of {joint}").format(joint=joint.name)
                    slider = _slider(gui, f"q̈{i + 1}", r, hint)
                    bind(slider, dispatch, functools.partial(_set_accel, i, r))
                    css.append(slider_css(handle_uuid(slider), i))
                    self.accel_sliders.append(slider)
            gui.add_html(f"<style>{''.join(css)}</style>")

    @property
    def stepped(self) -> list[Any]:
        """Its sliders whose step the page honours."""
        return [*self.sliders, *self.accel_sliders]

    def draw(self, state: LabState, snap: Snapshot) -> None:
        self.show(state)
        self.update(snap, state)

    def show(self, state: LabState) -> None:
        for i, (slider, r) in enumerate(zip(self.sliders, self.ranges, strict=True)):
            sync_value(slider, round(to_display(r, state.qd[i]), 6))
        for i, (slider, r) in enumerate(zip(self.accel_sliders, self.accel_ranges, strict=True)):
            sync_value(slider, round(to_display(r, state.qdd[i]), 6))
        show_option(self.jdot, "jdot_arrow", state.options.jdot_arrow, self.tr)
        if self._playing != state.playing:
            self._playing = state.playing
            _ = self.tr.gettext
            self.play.label = _("Pause") if state.playing else _("Play: move at these rates")
            self.play.icon = viser.Icon.PLAYER_PAUSE if state.playing else viser.Icon.PLAYER_PLAY

    def update(self, snap: Snapshot, state: LabState) -> None:
        still = not (state.qd.any() or state.qdd.any())
        idle = ("idle", state.stopped) if still else None  # nothing moves: nothing to redo
        if idle is not None and idle == self._shown:
            return
        self._shown = idle
        self.accel.content = accel_html(snap, state, self.tr)
        note = (
            f'<div class="jl-warn">{fmt.escape(say(state.stopped, self.tr))}</div>' if state.stopped else ""
        )
        arrows = self.tr.gettext("Black arrow at the tool: v; umber arrow: ω.")
        self.twist.content = (
            vector_table_html(tuple(range(6)), [("J q̇", snap.twist, "")], self.tr)
            + note
            + f'<div class="jl-note">{arrows}</div>'
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
        tr: Translator | None = None,
    ):
        self.tr = tr = tr or translations()
        _ = tr.gettext
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
                label = (
                    _("Course example")
                    if p.rates is not None
                    else _("Example: {name}").format(name=motion_name(p, tr))[:60]
                )
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
                slider = _slider(gui, ROW_TEXT[r], self.ranges[r], _("desired tool velocity, base axes"))
                bind(slider, dispatch, functools.partial(_set_desired, r, self.ranges[r]))
                self.sliders[r] = slider
            self.damping = option_widget(gui, dispatch, "damping", tr=tr)
            self._shown: tuple | None = None
            self.symbolic_button: viser.GuiButtonHandle | None = None
            self.symbolic = gui.add_html("")
            if len(rows) == robot.dof:  # a square task J: its inverse, symbolically, on demand
                self.symbolic_button = gui.add_button(_("Symbolic J⁻¹ = adj J / det J"), icon=viser.Icon.MATH)
                bind_click(
                    self.symbolic_button, dispatch, lambda: SetOption("symbolic_inverse", not self._asked)
                )
            self._asked = False

    @property
    def stepped(self) -> list[Any]:
        """Its sliders whose step the page honours."""
        return [*self.sliders.values(), self.damping]

    def draw(self, state: LabState, snap: Snapshot) -> None:
        self.show(state)
        self.update(snap, state)

    def show(self, state: LabState) -> None:
        for r, slider in self.sliders.items():
            sync_value(slider, round(to_display(self.ranges[r], state.v_desired[r]), 6))
        show_option(self.damping, "damping", state.options.damping, self.tr)
        asked = state.options.symbolic_inverse
        if asked != self._asked and self.symbolic_button is not None:
            _ = self.tr.gettext
            self.symbolic_button.label = (
                _("Hide the symbolic J⁻¹") if asked else _("Symbolic J⁻¹ = adj J / det J")
            )
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
        tr = self.tr
        _ = tr.gettext
        self.inverse.content = once(
            snap, inverse_html, snap.inverse, self.robot, snap.rows, state, snap.report.status, tr
        )
        p = self.example
        if p is not None:
            question = state.configuration == "course_question"
            self.course.content = example_html(snap, state, p.rates, self._example_start, question, tr)
        idle = ("idle", state.options.damping) if not state.v_desired[self._rows].any() else None
        if idle is not None and idle == self._shown:
            return
        self._shown = idle
        kinds = [j.kind for j in self.robot.joints]
        shown = fmt.cleaned([_display(k, v)[0] for k, v in zip(kinds, snap.rates, strict=True)])
        values = [(x, _display(k, 0.0)[1]) for x, k in zip(shown, kinds, strict=True)]
        full = [180.0 if k == "revolute" else 0.5 for k in kinds]
        lam = state.options.damping
        if lam > 0:
            caption = _("q̇ = J⁺ v (damped least squares, λ = {lam}); hatched: beyond {deg} ({m}).")
        else:
            caption = _("q̇ = J⁺ v (pseudo-inverse J⁺); hatched: beyond {deg} ({m}).")
        caption = caption.format(
            lam=fmt.number(lam, tr=tr), deg=fmt.quantity(180, "°/s", tr=tr), m=fmt.quantity(0.5, "m/s", tr=tr)
        )
        self.rates.content = bars_html(values, self.robot, full, caption, tr)
        desired = np.zeros(6)
        desired[list(snap.rows)] = state.v_desired[list(snap.rows)]
        wanted = float(np.linalg.norm(desired))
        lost = float(np.linalg.norm(snap.shortfall))
        table = vector_table_html(
            snap.rows,
            [
                (_("v wanted"), desired, ""),
                (_("J q̇ made"), snap.produced, ""),
                (_("v − J q̇ lost"), snap.shortfall, "lost"),
            ],
            tr,
        )
        if wanted > 0 and lost > 1e-6 * max(wanted, 1.0):
            percent = (
                fmt.number(100 * lost / wanted, tr=tr) + " %"
            )  # whole, in the words (a "%" would read as a format)
            if snap.report.status == "singular" and lam == 0:
                why = _(
                    "{percent} of v is not produced: the arm is singular: J⁺ drops the direction it has lost."
                )
            elif lam > 0:
                why = _("{percent} of v is not produced: damping trades accuracy for bounded joint rates.")
            else:
                why = _("{percent} of v is not produced: this twist is outside what the joints can produce.")
            table += f'<div class="jl-warn">{why.format(percent=percent)}</div>'
        self.result.content = table

    def remove(self) -> None:
        self.root.remove()


class ForcePanel:
    """Force and moment at the tool → joint torques τ = Jᵀ F."""

    def __init__(
        self, gui: viser.GuiApi, dispatch: Dispatch, robot: Robot, order: float, tr: Translator | None = None
    ):
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.robot = robot
        self.ranges = wrench_ranges(robot)
        self.root = gui.add_folder(None, order=order)
        rows = (0, 1, 5) if robot.planar else range(6)
        with self.root:
            self.torques = gui.add_html("")  # the result first: in sight while the sliders move
            self.sliders = {}
            self._bounds: dict[int, tuple[float, float]] = {}
            for r in rows:
                slider = _slider(
                    gui, WRENCH_TEXT[r], self.ranges[r], _("applied at the tool point, base axes")
                )
                bind(slider, dispatch, functools.partial(_set_wrench, r))
                self.sliders[r] = slider
                self._bounds[r] = (float(slider.min), float(slider.max))
            zero = gui.add_button(_("Remove the force (F = 0)"))
            bind_click(zero, dispatch, ClearWrench)
            self._idle = False

    @property
    def stepped(self) -> list[Any]:
        """Its sliders whose step the page honours."""
        return list(self.sliders.values())

    def draw(self, state: LabState, snap: Snapshot) -> None:
        self.show(state)
        self.update(snap, state)

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
        caption = self.tr.gettext(
            "Joint torques τ = Jᵀ F that hold the wrench (full bar: {full} N·m or N). At a singularity a "
            "force along the lost direction needs no torque at all."
        ).format(full=fmt.number(full, tr=self.tr))
        self.torques.content = bars_html(
            values, self.robot, [full] * self.robot.dof, caption + erratum_html("forces", self.tr), self.tr
        )

    def remove(self) -> None:
        self.root.remove()


def _set_rate(i: int, r: Range, value: Any) -> SetRate:
    return SetRate(i, from_display(r, float(value)))


def _set_accel(i: int, r: Range, value: Any) -> SetAcceleration:
    return SetAcceleration(i, from_display(r, float(value)))


def _set_desired(row: int, r: Range, value: Any) -> SetDesired:
    return SetDesired(row, from_display(r, float(value)))


def _set_wrench(row: int, value: Any) -> SetWrench:
    return SetWrench(row, float(value))
