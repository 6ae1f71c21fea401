"""Joint sliders (degrees for revolute joints, metres for prismatic ones) and named configurations.

Built once per robot inside a header-less folder, so a robot switch removes
the whole group at once. Each slider is coloured like its joint's axis and
column arrow; its range, step and snapping come from :mod:`app.core.ranges`.
"""

from __future__ import annotations

import contextlib
import functools
from typing import Any

import numpy as np
import viser

from kinematics import Robot

from ...core.actions import GoTo, SetJoint
from ...core.i18n import N_, Translator, translations
from ...core.ranges import Range, from_display, joint_ranges, to_display
from ...core.robot_texts import configuration_description
from ...viser_adapter import handle_uuid
from .. import fmt
from .common import Dispatch, bind, sync_value
from .style import slider_css

__all__ = ["JointsPanel", "slider_label", "configuration_label", "configurations_html", "MOVED"]

MOVED = N_("— (moved)")
"""What the configuration dropdown shows when the arm is at no named configuration."""


def slider_label(i: int, name: str, unit: str, robot_name: str = "") -> str:
    """A slider label: the joint's one name, qᵢ (as in the columns of J), with the describing words of
    its own name ("q3 boom", "q1", "q3 elbow") and the unit."""
    return f"{fmt.joint_label(i, name, robot_name)} [{unit}]"


def configuration_label(name: str) -> str:
    """A configuration's button text: "wrist_singular" → "wrist singular"."""
    return name.replace("_", " ")


class JointsPanel:
    """Sliders for q and buttons for the robot's named configurations."""

    def __init__(
        self,
        gui: viser.GuiApi,
        dispatch: Dispatch,
        robot: Robot,
        order: float,
        tr: Translator | None = None,
        menu_order: float | None = None,
    ) -> None:
        """``order``: the sliders' place in the panel; ``menu_order``: the Configuration menu's (default:
        under the sliders). The panel puts the menu above the status (issue 28, stumble 3): a singularity's
        description and decoupling lines pushed it below the fold."""
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.robot = robot
        self.ranges = joint_ranges(robot)
        self.root = gui.add_folder(None, order=order)
        self._menu_apart = menu_order is not None
        css = []
        with self.root:
            self.sliders = []
            for i, (joint, r) in enumerate(zip(robot.joints, self.ranges, strict=True)):
                value = min(max(to_display(r, robot.home[i]), r.lo), r.hi)
                slider = gui.add_slider(
                    slider_label(i, joint.name, r.unit, robot.name),
                    min=r.lo,
                    max=r.hi,
                    step=r.step,
                    initial_value=round(value, 6),
                    marks=(),
                    hint=(
                        _("{name}: revolute joint, {lo} to {hi} {unit}.")
                        if joint.kind == "revolute"
                        else _("{name}: prismatic joint, {lo} to {hi} {unit}.")
                    ).format(
                        name=joint.name, lo=fmt.number(r.lo, tr=tr), hi=fmt.number(r.hi, tr=tr), unit=r.unit
                    )
                    + " "
                    + _("Arrow keys: 10 steps; Shift + arrow: one fine step."),
                )
                bind(slider, dispatch, functools.partial(_set_joint, i, r))
                css.append(slider_css(handle_uuid(slider), i))
                self.sliders.append(slider)
            gui.add_html(f"<style>{''.join(css)}</style>")
        with contextlib.nullcontext() if menu_order is not None else self.root:
            names = ["home", *(c.name for c in robot.configurations if c.name != "home")]
            singular = {c.name for c in robot.configurations if c.singular}
            self._labels = {
                n: _("{name} (singular)").format(name=configuration_label(n))
                if n in singular
                else configuration_label(n)
                for n in names
            }
            self._moved = _(MOVED)
            by_label = {label: n for n, label in self._labels.items()}
            self.configuration = gui.add_dropdown(
                _("Configuration"),
                (self._moved, *self._labels.values()),
                initial_value=self._labels["home"],
                hint=_("Go to a named configuration; its description shows under the status."),
                order=menu_order,
            )
            bind(self.configuration, dispatch, lambda v: GoTo(by_label[str(v)]) if v in by_label else None)

    def show(self, q: np.ndarray, configuration: str) -> None:
        """Put ``q`` on the sliders and the configuration's name in the dropdown (echoes are ignored)."""
        sync_value(self.configuration, self._labels.get(configuration, self._moved))
        for i, (slider, r) in enumerate(zip(self.sliders, self.ranges, strict=True)):
            sync_value(slider, round(min(max(to_display(r, q[i]), r.lo), r.hi), 6))

    def remove(self) -> None:
        self.root.remove()
        if self._menu_apart:  # else removed with the folder
            self.configuration.remove()


def configurations_html(robot: Robot, tr: Translator | None = None) -> str:
    """Every named configuration with its description (singular ones marked)."""
    tr = tr or translations()
    _ = tr.gettext
    singular = fmt.escape(_("(singular)"))
    items = "".join(
        f"<li><b>{fmt.escape(configuration_label(c.name))}</b>"
        + (f" <span class='jl-warn'>{singular}</span>" if c.singular else "")
        + f": {fmt.escape(configuration_description(c, tr))}</li>"
        for c in robot.configurations
        if c.description
    )
    listing = f'<ul class="jl-conf">{items or "<li>" + fmt.escape(_("none")) + "</li>"}</ul>'
    return f'<div class="jl"><b>{fmt.escape(_("Named configurations"))}</b>{listing}</div>'


def _set_joint(i: int, r: Range, value: Any) -> SetJoint:
    return SetJoint(i, from_display(r, float(value)))
