"""The course's velocity and force views: v = J q̇, q̇ = J⁺ v, τ = Jᵀ F.

* **Forward**: joint-rate sliders q̇ and the resulting tool twist (drawn as
  arrows at the tool, read out here).
* **Inverse**: a desired tool twist (task rows only) and the joint rates
  J⁺ v as bars, which saturate (hatched) and read out ever larger numbers
  as the arm nears a singularity; an optional damping λ bounds them.
* **Statics**: a force and moment at the tool and the joint torques Jᵀ F.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import viser

from kinematics import Robot

from .. import fmt
from ..palette import joint_hex
from ..snapshot import Snapshot
from .common import sync_value
from .readouts import ROW_NAMES
from .style import slider_css

if TYPE_CHECKING:
    from ..session import ClientSession

__all__ = ["VelocityPanel", "ForcePanel", "bars_html", "rate_display", "twist_html"]

_PLAIN_ROWS = ("vx", "vy", "vz", "ωx", "ωy", "ωz")
_WRENCH_ROWS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def rate_display(kind: str, value: float) -> tuple[float, str]:
    """A joint rate [rad/s | m/s] in display units: (°/s value, "°/s") or (m/s value, "m/s")."""
    return (math.degrees(value), "°/s") if kind == "revolute" else (float(value), "m/s")


def bars_html(values: list[tuple[float, str]], robot: Robot, full_scale: list[float], caption: str) -> str:
    """One centred bar per joint, coloured like the joint; a bar beyond ``full_scale`` is hatched.

    Args:
        values: (value, unit) per joint, in display units.
        robot: The robot (joint names).
        full_scale: Value at which each bar reaches the edge.
        caption: Text under the bars.
    """
    rows = []
    for i, ((v, unit), full) in enumerate(zip(values, full_scale, strict=True)):
        v = 0.0 if math.isnan(v) else float(v)
        frac = min(abs(v) / full, 1.0) if full > 0 else 0.0
        over = abs(v) > full
        left = 50.0 if v >= 0 else 50.0 - 50.0 * frac
        name, color = fmt.escape(robot.joints[i].name.split()[0]), joint_hex(i)
        bar_class = "jl-bar over" if over else "jl-bar"
        bar_style = f"left:{left:.2f}%;width:{50.0 * frac:.2f}%;background-color:{color}"
        rows.append(
            f'<tr><td class="name" style="color:{color}">{name}</td><td class="track"><div class="jl-bar-bg">'
            f'<div class="jl-bar-mid"></div><div class="{bar_class}" style="{bar_style}"></div></div></td>'
            f'<td class="val">{fmt.quantity(v, unit)}</td></tr>'
        )
    table = f'<table class="jl-bars">{"".join(rows)}</table>'
    return f'<div class="jl">{table}<div class="jl-note">{caption}</div></div>'


def twist_html(twist: np.ndarray) -> str:
    """The tool twist [v; ω] read out with units (ω in °/s, like the sliders)."""
    v = " ".join(f"{ROW_NAMES[r]}&nbsp;=&nbsp;{fmt.quantity(twist[r], 'm/s')}" for r in range(3))
    w = " ".join(
        f"{ROW_NAMES[r]}&nbsp;=&nbsp;{fmt.quantity(math.degrees(twist[r]), '°/s')}" for r in range(3, 6)
    )
    return f'<div class="jl jl-twist">Tool twist v = J q̇ (base axes):<br><b>{v}</b><br><b>{w}</b></div>'


def _row_slider(
    gui: viser.GuiApi, row: int, names: tuple[str, ...], linear: tuple[float, str], angular: tuple[float, str]
):
    limit, unit = linear if row < 3 else angular
    step = limit / 100
    return gui.add_slider(f"{names[row]} [{unit}]", min=-limit, max=limit, step=step, initial_value=0.0)


class VelocityPanel:
    """Joint rates → tool twist, and desired tool twist → joint rates."""

    def __init__(
        self, gui: viser.GuiApi, session: ClientSession, robot: Robot, rows: tuple[int, ...], order: float
    ):
        self.robot = robot
        self.root = gui.add_folder(None, order=order)
        css = []
        with self.root:
            with gui.add_folder("Forward: v = J q̇"):
                self.rate_sliders = []
                for i, joint in enumerate(robot.joints):
                    limit, unit = (90.0, "°/s") if joint.kind == "revolute" else (0.2, "m/s")
                    slider = gui.add_slider(
                        f"q̇{i + 1} [{unit}]",
                        min=-limit,
                        max=limit,
                        step=limit / 90,
                        initial_value=0.0,
                        hint=f"rate of {joint.name}",
                    )
                    session.on_update(slider, self._rate_setter(session, i))
                    css.append(slider_css(slider._impl.uuid, joint_hex(i)))
                    self.rate_sliders.append(slider)
                stop = gui.add_button("Stop (q̇ = 0)", icon=viser.Icon.PLAYER_STOP)
                session.on_click(stop, session.stop_rates)
                self.twist = gui.add_html("")
            with gui.add_folder("Inverse: q̇ = J⁺ v"):
                self.v_sliders = {}
                for r in rows:
                    slider = _row_slider(gui, r, _PLAIN_ROWS, (0.5, "m/s"), (90.0, "°/s"))
                    session.on_update(slider, self._desired_setter(session, r))
                    self.v_sliders[r] = slider
                self.damping = gui.add_slider(
                    "damping λ",
                    min=0.0,
                    max=0.2,
                    step=0.005,
                    initial_value=0.0,
                    hint="0: pseudo-inverse J⁺; > 0: damped least squares, "
                    "which keeps joint rates bounded near a singularity",
                )
                session.on_update(self.damping, lambda h: session.set_option(damping=float(h.value)))
                self.rates = gui.add_html("")
            gui.add_html(f"<style>{''.join(css)}</style>")

    @staticmethod
    def _rate_setter(session: ClientSession, i: int):
        def set_rate(handle: viser.GuiSliderHandle) -> None:
            kind = session.state.robot.joints[i].kind
            session.set_rate(i, math.radians(handle.value) if kind == "revolute" else float(handle.value))

        return set_rate

    @staticmethod
    def _desired_setter(session: ClientSession, row: int):
        def set_desired(handle: viser.GuiSliderHandle) -> None:
            session.set_desired(row, float(handle.value) if row < 3 else math.radians(handle.value))

        return set_desired

    def show_inputs(self, qd: np.ndarray, v: np.ndarray, damping: float) -> None:
        """Put the state's rates on the sliders (callbacks muted by the session)."""
        for slider, joint, value in zip(self.rate_sliders, self.robot.joints, qd, strict=True):
            sync_value(slider, float(np.clip(rate_display(joint.kind, value)[0], slider.min, slider.max)))
        for r, slider in self.v_sliders.items():
            sync_value(slider, float(np.clip(v[r] if r < 3 else math.degrees(v[r]), slider.min, slider.max)))
        sync_value(self.damping, float(damping))

    def update(self, snap: Snapshot) -> None:
        self.twist.content = twist_html(snap.twist)
        kinds = [j.kind for j in self.robot.joints]
        values = [rate_display(k, v) for k, v in zip(kinds, snap.rates, strict=True)]
        full = [180.0 if k == "revolute" else 0.5 for k in kinds]
        self.rates.content = bars_html(
            values,
            self.robot,
            full,
            "Joint rates for the desired tool twist; hatched: beyond 180 °/s (0.5 m/s). "
            "Near a singularity J⁺ v grows without bound.",
        )

    def remove(self) -> None:
        self.root.remove()


class ForcePanel:
    """Force and moment at the tool → joint torques τ = Jᵀ F."""

    def __init__(self, gui: viser.GuiApi, session: ClientSession, robot: Robot, order: float):
        self.robot = robot
        self.root = gui.add_folder(None, order=order)
        rows = (0, 1, 5) if robot.planar else range(6)
        with self.root:
            gui.add_markdown("**Wrench at the tool point** (base axes)")
            self.sliders = {}
            for r in rows:
                slider = _row_slider(gui, r, _WRENCH_ROWS, (20.0, "N"), (10.0, "N·m"))
                session.on_update(slider, self._setter(session, r))
                self.sliders[r] = slider
            zero = gui.add_button("Remove the force (F = 0)")
            session.on_click(zero, session.clear_wrench)
            self.torques = gui.add_html("")

    @staticmethod
    def _setter(session: ClientSession, row: int):
        return lambda handle: session.set_wrench(row, float(handle.value))

    def show_inputs(self, wrench: np.ndarray) -> None:
        for r, slider in self.sliders.items():
            sync_value(slider, float(np.clip(wrench[r], slider.min, slider.max)))

    def update(self, snap: Snapshot) -> None:
        units = ["N·m" if j.kind == "revolute" else "N" for j in self.robot.joints]
        values = list(zip(snap.torques, units, strict=True))
        self.torques.content = bars_html(
            values,
            self.robot,
            [20.0] * self.robot.dof,
            "Joint torques τ = Jᵀ F that hold the wrench (full bar: 20 N·m or 20 N). "
            "At a singularity the lost direction needs no torque.",
        )

    def remove(self) -> None:
        self.root.remove()
