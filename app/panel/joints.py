"""Joint sliders (degrees for revolute joints, metres for prismatic ones) and configuration buttons.

Built once per robot inside a header-less folder, so a robot switch removes
the whole group at once. Each slider is coloured like its joint's axis and
column arrow.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import viser

from kinematics import Robot

from .. import fmt
from ..palette import joint_hex
from .common import sync_value
from .style import slider_css

if TYPE_CHECKING:
    from ..session import ClientSession

__all__ = ["JointsPanel", "joint_range", "to_slider", "from_slider", "unit_of"]

_REVOLUTE_FALLBACK = (-180.0, 180.0)
_PRISMATIC_FALLBACK = (-1.0, 1.0)


def unit_of(kind: str) -> str:
    """Slider unit of a joint kind: "°" or "m"."""
    return "°" if kind == "revolute" else "m"


def to_slider(kind: str, value: float) -> float:
    """Joint value [rad | m] in slider units [° | m]."""
    return math.degrees(value) if kind == "revolute" else float(value)


def from_slider(kind: str, value: float) -> float:
    """Slider value [° | m] in joint units [rad | m]."""
    return math.radians(value) if kind == "revolute" else float(value)


def joint_range(robot: Robot, i: int) -> tuple[float, float, float]:
    """(min, max, step) of joint ``i``'s slider in slider units, from its limits.

    The ends are rounded inwards to the slider's display precision (0.01° or 0.1 mm), so the
    slider never leaves the limits and its number box shows no float noise.
    """
    joint = robot.joints[i]
    if joint.qlim is not None:
        lo, hi = (to_slider(joint.kind, v) for v in joint.qlim)
    else:
        lo, hi = _REVOLUTE_FALLBACK if joint.kind == "revolute" else _PRISMATIC_FALLBACK
    step, scale = (0.5, 100) if joint.kind == "revolute" else (0.001, 10_000)
    return math.ceil(lo * scale - 1e-9) / scale, math.floor(hi * scale + 1e-9) / scale, step


def display_round(kind: str, value: float) -> float:
    """A slider value rounded to the display precision (0.01° or 0.1 mm)."""
    return round(value, 2 if kind == "revolute" else 4)


def clamp(value: float, lo: float, hi: float) -> float:
    """``value`` within the slider's range (a named configuration may lie outside the limits)."""
    return float(min(max(value, lo), hi))


class JointsPanel:
    """Sliders for q and buttons for the robot's named configurations."""

    def __init__(self, gui: viser.GuiApi, session: ClientSession, robot: Robot, order: float) -> None:
        self.robot = robot
        self.root = gui.add_folder(None, order=order)
        css = []
        with self.root:
            gui.add_markdown("**Joint values** — degrees for revolute, metres for prismatic joints")
            self.sliders = []
            for i, joint in enumerate(robot.joints):
                lo, hi, step = joint_range(robot, i)
                value = clamp(display_round(joint.kind, to_slider(joint.kind, robot.home[i])), lo, hi)
                label = f"{joint.name} [{unit_of(joint.kind)}]"
                slider = gui.add_slider(
                    label,
                    min=lo,
                    max=hi,
                    step=step,
                    initial_value=value,
                    marks=((lo, fmt.number(lo)), (hi, fmt.number(hi))),
                    hint=f"{joint.name}: {joint.kind} joint, limits {lo:g} to {hi:g} {unit_of(joint.kind)}",
                )
                session.on_update(slider, self._joint_setter(session, i))
                css.append(slider_css(slider._impl.uuid, joint_hex(i)))
                self.sliders.append(slider)
            gui.add_html(f"<style>{''.join(css)}</style>")
            self.buttons = {}
            home = gui.add_button("Home", icon=viser.Icon.HOME, hint="Go to the robot's home configuration")
            session.on_click(home, lambda: session.go_to("home"))
            self.buttons["home"] = home
            named = [c for c in robot.configurations if c.name != "home"]
            if named:
                gui.add_markdown("**Named configurations** (red: singular)")
            for conf in named:
                button = gui.add_button(
                    conf.name.replace("_", " "),
                    color="red" if conf.singular else None,
                    hint=conf.description or None,
                )
                session.on_click(button, lambda name=conf.name: session.go_to(name))
                self.buttons[conf.name] = button

    @staticmethod
    def _joint_setter(session: ClientSession, i: int):
        def set_joint(handle: viser.GuiSliderHandle) -> None:
            session.set_joint(i, from_slider(session.state.robot.joints[i].kind, handle.value))

        return set_joint

    def show(self, q: np.ndarray) -> None:
        """Put ``q`` on the sliders (callbacks muted by the session)."""
        for i, (slider, joint) in enumerate(zip(self.sliders, self.robot.joints, strict=True)):
            sync_value(slider, clamp(to_slider(joint.kind, q[i]), slider.min, slider.max))

    def remove(self) -> None:
        self.root.remove()
