"""The singularity explorer's tabs: Motion (resolved rate, drive the tool, redundancy, the nearest
singularity) and Maps (a joint-space map of w, the workspace cloud).

Views only: every control dispatches an action; :meth:`MotionPanel.draw` and :meth:`MapsPanel.draw`
put a state and its snapshot on screen. Charts are uPlot (viser's ``add_uplot``) fed from the
state's trace, which holds only finite numbers.
"""

from __future__ import annotations

import functools
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

from ...core.actions import ApplyPreset, Play, ResetMotion, SelfMove, SetOption, StepOnce
from ...core.commands import FindSingularity
from ...core.motion_rules import redundancy_rows
from ...core.motion_state import Trace
from ...core.ranges import joint_ranges
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...viser_adapter import handle_uuid
from .. import fmt
from ..palette import joint_hex
from .common import Dispatch, bind, sync_value

__all__ = ["MotionPanel", "MapsPanel", "OWN_TWIST", "PLAY_BUTTONS"]

OWN_TWIST = "your own v (set in q̇ = J⁺v)"
PLAY_BUTTONS = ("Play", "Pause", "Step", "Reset")
_METHODS = {"DLS (damped)": "dls", "Newton (J⁻¹, J⁺)": "newton"}
_MODES = {"tool position": "position", "tool pose": "pose"}
_CHART_HEIGHT = 150


def _chart(
    gui: viser.GuiApi, title: str, labels: Sequence[str], colors: Sequence[str], y: str, log: bool = False
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
        axes=({"label": "t [s]"}, {"label": y}),
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
    ) -> None:
        self.robot = robot
        self.presets = {p.name: p for p in presets}
        self.root = gui.add_folder(None, order=order)
        self._trace: Trace | None = None
        self._shown: tuple | None = None
        with self.root:
            # Resolved rate: the course's q_{k+1} = q_k + Δt J⁺ v, the tool twist held.
            with gui.add_folder("Resolved rate: q̇ = J⁺v held in time"):
                self.preset = gui.add_dropdown(
                    "Preset",
                    (OWN_TWIST, *self.presets),
                    initial_value=OWN_TWIST,
                    hint="A start and a tool twist.",
                )
                bind(self.preset, dispatch, self._preset)
                self.buttons = gui.add_button_group("", PLAY_BUTTONS)
                self.buttons.on_click(lambda event: dispatch(_button(str(event.target.value))))
                self.readout = gui.add_html("")
                self.measures = _chart(gui, "σmin and w", ("σmin", "w"), ("#c2255c", "#3b5bdb"), "σmin, w")
                self.kappa = _chart(gui, "condition number κ", ("κ",), ("#e8590c",), "κ (log)", log=True)
                names = [f"q̇{i + 1}" for i in range(robot.dof)]
                colors = [joint_hex(i) for i in range(robot.dof)]
                self.rates = _chart(gui, "joint rates", names, colors, "°/s, m/s")
                self.about = gui.add_html("")
                self.frame = gui.add_dropdown(
                    "v in axes", ("base", "tool"), hint="tool: v is held in the moving tool's own axes"
                )
                bind(self.frame, dispatch, lambda v: SetOption("twist_frame", str(v)))
                self.speed = gui.add_slider(
                    "Speed",
                    min=0.05,
                    max=2.0,
                    step=0.05,
                    initial_value=1.0,
                    hint="1: real time; 0.1: ten times slower",
                )
                bind(self.speed, dispatch, lambda v: SetOption("speed", float(v)))
            # Drive the tool: IK every frame while the handle is dragged.
            with gui.add_folder("Drive the tool (IK)", expand_by_default=False):
                self.gizmo = gui.add_checkbox("Drag handle at the tool", initial_value=False)
                bind(self.gizmo, dispatch, lambda v: SetOption("gizmo", bool(v)))
                self.method = gui.add_dropdown(
                    "Method", tuple(_METHODS), hint="q_{k+1} = q_k + J⁺ (y_d − k(q_k))"
                )
                bind(self.method, dispatch, lambda v: SetOption("ik_method", _METHODS[str(v)]))
                self.mode = gui.add_dropdown("Follow", tuple(_MODES))
                bind(self.mode, dispatch, lambda v: SetOption("ik_mode", _MODES[str(v)]))
                self.ik = gui.add_html("")
            # Redundancy: self-motion and the manipulability climb, the tool held.
            rows = redundancy_rows(robot)
            self.redundant = rows is not None
            self.self_slider: viser.GuiSliderHandle | None = None
            self.self_chart = None
            if rows is not None:
                with gui.add_folder("Redundancy: move with the tool held", expand_by_default=False):
                    held = ", ".join(ROW_TEXT[r] for r in rows)
                    task = ", ".join(ROW_TEXT[r] for r in task_rows(robot))
                    gui.add_html(
                        f'<div class="jl-note">{robot.dof} joints, {len(rows)} task rows held ({held}): '
                        f"the arm can move in the null space of J without moving the tool. "
                        f"<b>Climb</b> raises w = √det(J Jᵀ) of these rows ({held})"
                        + (f", not the banner's κ of all task rows ({task})." if task != held else ".")
                        + "</div>"
                    )
                    self.self_slider = gui.add_slider(
                        "Self-motion s",
                        min=-3.0,
                        max=3.0,
                        step=0.01,
                        initial_value=0.0,
                        hint="along the null space",
                    )
                    bind(self.self_slider, dispatch, lambda v: SelfMove(float(v)))
                    climb = gui.add_button("Climb manipulability", icon=viser.Icon.TRENDING_UP)
                    climb.on_click(lambda _: dispatch(Play(True, "climb")))
                    self.self_chart = gui.add_uplot(
                        (np.zeros(1), np.zeros(1)),
                        ({"label": "s"}, {"label": "w", "stroke": "#3b5bdb", "width": 2}),
                        title="w along the self-motion",
                        scales={"x": {"time": False}},
                        axes=({"label": "s"}, {"label": "w"}),
                        height=_CHART_HEIGHT,
                        aspect=2.0,
                    )
            nearest = gui.add_button("Go to the nearest singularity", icon=viser.Icon.TARGET)
            nearest.on_click(lambda _: dispatch(FindSingularity()))

    def _preset(self, value: Any) -> ApplyPreset | None:
        p = self.presets.get(str(value))
        if p is None:
            return None
        return ApplyPreset(p.name, tuple(map(float, p.q)), tuple(map(float, p.twist)), p.frame, p.speed)

    def draw(self, state: LabState, snap: Snapshot) -> None:
        o, m = state.options, state.motion
        sync_value(self.preset, m.preset if m.preset in self.presets else OWN_TWIST)
        sync_value(self.frame, o.twist_frame)
        sync_value(self.speed, float(o.speed))
        sync_value(self.gizmo, o.gizmo)
        sync_value(self.method, next(k for k, v in _METHODS.items() if v == o.ik_method))
        sync_value(self.mode, next(k for k, v in _MODES.items() if v == o.ik_mode))
        if self.self_slider is not None:
            sync_value(self.self_slider, float(round(m.s, 6)))
        key = (
            m.preset,
            state.playing,
            state.stopped,
            m.kind,
            tuple(np.round(state.v_desired, 9)),
            o.twist_frame,
        )
        if key != self._shown:
            self._shown = key
            self.about.content = self._about(m.preset)
            self.readout.content = _readout(state, snap)
        self.ik.content = _ik_html(state)
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
        return f'<div class="jl-note">{fmt.escape(p.description)}</div>' if p and p.description else ""

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


def _readout(state: LabState, snap: Snapshot) -> str:
    rows = snap.rows
    v = [state.v_desired[r] if r < 3 else math.degrees(state.v_desired[r]) for r in rows]
    parts = ", ".join(f"{ROW_TEXT[r]} {fmt.number(x)}" for r, x in zip(rows, v, strict=True))
    axes = "tool" if state.options.twist_frame == "tool" else "base"
    doing = {
        "resolved_rate": "holding v",
        "climb": "climbing w of the held rows",
        "path": "descending to the nearest singularity",
        "joints": "moving at q̇",
    }.get(state.motion.kind, "")
    line = f'<div class="jl-note">v held: {parts} (m/s, °/s; {axes} axes).</div>'
    if state.playing:
        line += f'<div class="jl-note"><b>Playing</b>: {doing}.</div>'
    elif state.stopped:
        line += f'<div class="jl-warn">{fmt.escape(state.stopped)}</div>'
    return f'<div class="jl">{line}</div>'


def _ik_html(state: LabState) -> str:
    ik = state.motion.ik
    if not state.options.gizmo:
        return '<div class="jl-note">Tick the box, then drag the handle at the tool: the arm follows.</div>'
    if ik is None:
        return '<div class="jl-note">Drag the handle at the tool.</div>'
    method = "damped least squares" if ik.method == "dls" else "Newton"
    text = (
        f"{method}: {ik.iterations} iterations, residual {fmt.number(ik.residual)}, "
        f"{'converged' if ik.converged else 'not converged'}."
    )
    if ik.departure > 1e-3:
        text += (
            f' <span class="jl-warn">The tool stops {fmt.quantity(ik.departure * 1000, "mm")} short'
            + (": damping keeps the rates bounded near the singularity." if ik.method == "dls" else ".")
            + "</span>"
        )
    return f'<div class="jl"><div class="jl-note">{text}</div></div>'


def _sorted_unique(samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    s = np.round(samples[:, 0], 4)
    order = np.argsort(s, kind="stable")
    s_sorted, w_sorted = s[order], samples[order, 1]
    keep = np.r_[s_sorted[1:] != s_sorted[:-1], True]  # the last sample at each s
    return s_sorted[keep], w_sorted[keep]


class MapsPanel:
    """The Maps tab: w over two joints (click to go there) and the workspace cloud."""

    def __init__(
        self, gui: viser.GuiApi, dispatch: Dispatch, robot: Robot, slider_ids: Sequence[str], order: float
    ):
        self.robot = robot
        self.slider_ids = list(slider_ids)
        self.root = gui.add_folder(None, order=order)
        names = [f"q{i + 1}" for i in range(robot.dof)]
        with self.root:
            self.cloud = gui.add_checkbox(
                "Workspace cloud",
                initial_value=False,
                hint="20,000 tool points of random configurations, coloured by w (yellow: high, purple: low)",
            )
            bind(self.cloud, dispatch, lambda v: SetOption("workspace", bool(v)))
            self.show_map = gui.add_checkbox(
                "Joint-space map of w", initial_value=False, disabled=robot.dof < 2
            )
            bind(self.show_map, dispatch, lambda v: SetOption("joint_map", bool(v)))
            self.i = gui.add_dropdown("x axis", names, initial_value=names[1 if robot.dof >= 3 else 0])
            bind(self.i, dispatch, functools.partial(_map_joint, "map_i", names))
            self.j = gui.add_dropdown(
                "y axis", names, initial_value=names[2 if robot.dof >= 3 else min(1, robot.dof - 1)]
            )
            bind(self.j, dispatch, functools.partial(_map_joint, "map_j", names))
            self.map = gui.add_html("")
        self._shown: str | None = None

    def draw(self, state: LabState, snap: Snapshot) -> None:
        o = state.options
        names = [f"q{i + 1}" for i in range(self.robot.dof)]
        sync_value(self.cloud, o.workspace)
        sync_value(self.show_map, o.joint_map)
        sync_value(self.i, names[o.map_i])
        sync_value(self.j, names[o.map_j])
        jm = snap.joint_map
        if jm is None:
            note = "Tick the box to compute w over two joints (the others held where they are)."
            if o.joint_map and o.map_i == o.map_j:
                note = "Choose two different joints."
            html = f'<div class="jl-note">{note}</div>'
        else:
            html = self._map_html(state, jm)
        if html != self._shown:
            self._shown = html
            self.map.content = html

    def _map_html(self, state: LabState, jm: Any) -> str:
        ranges = joint_ranges(self.robot)
        ri, rj = ranges[jm.i], ranges[jm.j]
        xi = math.degrees(state.q[jm.i]) if ri.degrees else float(state.q[jm.i])
        xj = math.degrees(state.q[jm.j]) if rj.degrees else float(state.q[jm.j])
        left = min(max(100.0 * (xi - jm.lo[0]) / (jm.hi[0] - jm.lo[0]), 0.0), 100.0)
        top = min(max(100.0 * (1.0 - (xj - jm.lo[1]) / (jm.hi[1] - jm.lo[1])), 0.0), 100.0)
        ids = f'data-i="{self.slider_ids[jm.i]}" data-j="{self.slider_ids[jm.j]}"'
        box = " ".join(
            f'data-{k}="{v:.6g}"' for k, v in zip(("ilo", "jlo", "ihi", "jhi"), (*jm.lo, *jm.hi), strict=True)
        )
        return (
            f'<div class="jl"><div class="jl-map" {ids} {box}>'
            f'<img alt="w over q{jm.i + 1} and q{jm.j + 1}" src="data:image/png;base64,{jm.png}">'
            f'<div class="jl-map-dot" style="left:{left:.2f}%;top:{top:.2f}%"></div></div>'
            f'<div class="jl-note">x: q{jm.i + 1} {jm.lo[0]:g} … {jm.hi[0]:g} {ri.unit}; y: q{jm.j + 1} '
            f"{jm.lo[1]:g} … {jm.hi[1]:g} {rj.unit}. Colour: w from 0 (purple) to {fmt.number(jm.w_max)} "
            f"(yellow); white ring: the arm now. Click the map to go there.</div></div>"
        )

    def remove(self) -> None:
        self.root.remove()


def _map_joint(option: str, names: list[str], value: Any) -> SetOption | None:
    return SetOption(option, names.index(str(value))) if str(value) in names else None


def slider_ids(sliders: Sequence[viser.GuiSliderHandle]) -> list[str]:
    """DOM ids of the joint sliders (the map's click types into their number boxes)."""
    return [handle_uuid(s) for s in sliders]
