"""The Maps tab: w over two joints as a heat map with its axes and colour bar (click to go there), and
the workspace cloud with the legend of its colours.

The figure is HTML around the map's PNG: the y axis (joint j, its name and unit, ticks at its slider's
ends and middle) on the left, the x axis (joint i) under it, the colour bar of w (0 to the map's
largest w, viridis as :func:`app.core.snapshot.maps.colormap` colours the cells) on the right. The page
script turns a click on ``.jl-map`` into the two joints' values (:mod:`.style`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import viser

from kinematics import Robot

from ...core.actions import SetOption
from ...core.i18n import Translator, translations
from ...core.ranges import joint_ranges
from ...core.snapshot import Snapshot
from ...core.snapshot.maps import (
    CLOUD_POINTS,
    LIMIT_RGB,
    SINGULAR_RATIO,
    SINGULAR_RGB,
    Cloud,
    JointMap,
    colormap,
)
from ...core.state import LabState
from ...viser_adapter import handle_uuid
from .. import fmt
from .common import Dispatch, bind, option_widget, show_option, sync_value

__all__ = ["MapsPanel", "slider_ids", "map_html", "cloud_legend_html", "COLOUR_STOPS"]

COLOUR_STOPS = tuple("#{:02x}{:02x}{:02x}".format(*c) for c in colormap(np.linspace(0.0, 1.0, 9)))
"""The colours of w = 0, w_max/8, …, w_max (the bar's gradient, bottom to top)."""

MAP_CSS = """<style>
.jl-mapfig { display: grid; grid-template-columns: 1.3em auto minmax(0, 240px) 14px auto 1em;
  grid-template-rows: auto auto auto; column-gap: 4px; justify-content: center; margin: 4px 0;
  font-size: 12.5px; color: #1f2328; font-variant-numeric: tabular-nums; }
.jl-mapfig .jl-map { grid-column: 3; grid-row: 1; margin: 0; max-width: none; }
.jl-mapfig .ylabel { grid-column: 1; grid-row: 1; writing-mode: vertical-rl; transform: rotate(180deg);
  text-align: center; font-weight: 700; white-space: nowrap; }
.jl-mapfig .yticks, .jl-mapfig .wticks { grid-row: 1; display: flex; flex-direction: column;
  justify-content: space-between; margin: -0.6em 0; }
.jl-mapfig .yticks { grid-column: 2; text-align: right; }
.jl-mapfig .wticks { grid-column: 5; text-align: left; }
.jl-mapfig .bar { grid-column: 4; grid-row: 1; border: 1px solid #868e96; }
.jl-mapfig .xticks { grid-column: 3; grid-row: 2; display: flex; justify-content: space-between;
  margin: 1px -0.8em 0; }
.jl-mapfig .xlabel { grid-column: 3; grid-row: 3; text-align: center; font-weight: 700; white-space: nowrap; }
.jl-mapfig .wlabel { grid-column: 6; grid-row: 1; align-self: center; font-weight: 700; font-style: italic; }
.jl-cloudkey { display: flex; align-items: center; gap: 6px; font-size: 12.5px; color: #1f2328;
  padding: 0 8px; }
.jl-cloudkey .bar { flex: 1 1 auto; height: 12px; border: 1px solid #868e96; }
</style>"""


def _gradient(direction: str) -> str:
    return f"linear-gradient(to {direction}, {', '.join(COLOUR_STOPS)})"


def _tick(x: float, tr: Translator) -> str:
    return fmt.number(float(x), 3, tr) if abs(x) >= 1e-9 else "0"


def _axis(robot: Robot, k: int) -> str:
    """A joint's axis title: its name and unit ("q2 shoulder [°]")."""
    return f"{fmt.escape(robot.joints[k].name)} [{joint_ranges(robot)[k].unit}]"


def map_html(
    jm: JointMap, robot: Robot, q: np.ndarray, ids: Sequence[str], tr: Translator | None = None
) -> str:
    """The joint map with its axes, ticks (written as ``tr``'s language writes numbers), colour bar and
    the arm's q as a ring."""
    tr = tr or translations()
    _ = tr.gettext
    ranges = joint_ranges(robot)
    ri, rj = ranges[jm.i], ranges[jm.j]
    xi = math.degrees(q[jm.i]) if ri.degrees else float(q[jm.i])
    xj = math.degrees(q[jm.j]) if rj.degrees else float(q[jm.j])
    left = min(max(100.0 * (xi - jm.lo[0]) / (jm.hi[0] - jm.lo[0]), 0.0), 100.0)
    top = min(max(100.0 * (1.0 - (xj - jm.lo[1]) / (jm.hi[1] - jm.lo[1])), 0.0), 100.0)
    data = f'data-i="{ids[jm.i]}" data-j="{ids[jm.j]}" ' + " ".join(
        f'data-{k}="{v:.6g}"' for k, v in zip(("ilo", "jlo", "ihi", "jhi"), (*jm.lo, *jm.hi), strict=True)
    )
    mid_i, mid_j = (jm.lo[0] + jm.hi[0]) / 2, (jm.lo[1] + jm.hi[1]) / 2
    x_ticks = "".join(f"<span>{_tick(v, tr)}</span>" for v in (jm.lo[0], mid_i, jm.hi[0]))
    y_ticks = "".join(f"<span>{_tick(v, tr)}</span>" for v in (jm.hi[1], mid_j, jm.lo[1]))
    w_ticks = "".join(f"<span>{_tick(v, tr)}</span>" for v in (jm.w_max, jm.w_max / 2, 0.0))
    names = _("w over {first} and {second}").format(
        first=fmt.escape(robot.joints[jm.i].name), second=fmt.escape(robot.joints[jm.j].name)
    )
    note = _(
        "Colour: manipulability w of the task rows (bar on the right); white ring: the arm now. "
        "Click the map to go there."
    )
    return (
        f'<div class="jl">{MAP_CSS}<div class="jl-mapfig">'
        f'<div class="ylabel">{_axis(robot, jm.j)}</div><div class="yticks">{y_ticks}</div>'
        f'<div class="jl-map" {data}><img alt="{names}" src="data:image/png;base64,{jm.png}">'
        f'<div class="jl-map-dot" style="left:{left:.2f}%;top:{top:.2f}%"></div></div>'
        f'<div class="bar" style="background:{_gradient("top")}"></div><div class="wticks">{w_ticks}</div>'
        f'<div class="wlabel">w</div><div class="xticks">{x_ticks}</div>'
        f'<div class="xlabel">{_axis(robot, jm.i)}</div></div>'
        f'<div class="jl-note">{note}</div></div>'
    )


def cloud_legend_html(cloud: Cloud | None, tr: Translator | None = None) -> str:
    """The key of the workspace cloud's colours ("" when the cloud is not shown)."""
    if cloud is None:
        return ""
    tr = tr or translations()
    points = f"{CLOUD_POINTS:,}".replace(",", "\u2009")
    what = tr.gettext(
        "Cloud: the tool point of {points} random configurations within the sliders, coloured by w:"
    ).format(points=points)
    return (
        f'<div class="jl">{MAP_CSS}<div class="jl-note">{what}</div>'
        f'<div class="jl-cloudkey"><span>w = 0</span><div class="bar" style="background:'
        f'{_gradient("right")}"></div><span>{_tick(cloud.w_max, tr)}</span></div>'
        f"{_critical_key(cloud, tr)}</div>"
    )


def _critical_key(cloud: Cloud, tr: Translator) -> str:
    """The key of the two kinds of critical points the cloud marks (002: singular and joint-limit points)."""
    singular = tr.gettext("near a singularity (σmin/σmax < {ratio})").format(
        ratio=fmt.number(SINGULAR_RATIO, 2, tr)
    )
    limits = tr.ngettext(
        "{count} points with a joint at a limit",
        "{count} points with a joint at a limit",
        cloud.limits,
    ).format(count=f"{cloud.limits:,}".replace(",", "\u2009"))
    title = tr.gettext("Critical points:")
    swatch = '<span style="display:inline-block;width:10px;height:10px;background:rgb{rgb}"></span>'
    return (
        f'<div class="jl-note">{fmt.escape(title)} {swatch.format(rgb=SINGULAR_RGB)} {fmt.escape(singular)}; '
        f"{swatch.format(rgb=LIMIT_RGB)} {fmt.escape(limits)}</div>"
    )


class MapsPanel:
    """The Maps tab: w over two joints (click to go there) and the workspace cloud."""

    def __init__(
        self,
        gui: viser.GuiApi,
        dispatch: Dispatch,
        robot: Robot,
        slider_ids: Sequence[str],
        order: float,
        tr: Translator | None = None,
    ):
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.robot = robot
        self.slider_ids = list(slider_ids)
        self.root = gui.add_folder(None, order=order)
        names = [f"q{i + 1}" for i in range(robot.dof)]
        with self.root:
            self.cloud = option_widget(gui, dispatch, "workspace", tr=tr)
            self.cloud_key = gui.add_html("")
            self.show_map = option_widget(gui, dispatch, "joint_map", tr=tr, disabled=robot.dof < 2)
            self.i = gui.add_dropdown(_("x axis"), names, initial_value=names[1 if robot.dof >= 3 else 0])
            bind(self.i, dispatch, functools.partial(_map_joint, "map_i", names))
            self.j = gui.add_dropdown(
                _("y axis"), names, initial_value=names[2 if robot.dof >= 3 else min(1, robot.dof - 1)]
            )
            bind(self.j, dispatch, functools.partial(_map_joint, "map_j", names))
            self.map = gui.add_html("")
        self._shown: str | None = None

    def draw(self, state: LabState, snap: Snapshot) -> None:
        o = state.options
        names = [f"q{i + 1}" for i in range(self.robot.dof)]
        show_option(self.cloud, "workspace", o.workspace, self.tr)
        show_option(self.show_map, "joint_map", o.joint_map, self.tr)
        sync_value(self.i, names[o.map_i])
        sync_value(self.j, names[o.map_j])
        key = cloud_legend_html(snap.cloud, self.tr)
        if self.cloud_key.content != key:
            self.cloud_key.content = key
        jm = snap.joint_map
        if jm is None:
            _ = self.tr.gettext
            note = _("Tick the box to compute w over two joints (the others held where they are).")
            if o.joint_map and o.map_i == o.map_j:
                note = _("Choose two different joints.")
            html = f'<div class="jl-note">{note}</div>'
        else:
            html = map_html(jm, self.robot, np.asarray(state.q), self.slider_ids, self.tr)
        if html != self._shown:
            self._shown = html
            self.map.content = html

    def remove(self) -> None:
        self.root.remove()


def _map_joint(option: str, names: list[str], value: Any) -> SetOption | None:
    return SetOption(option, names.index(str(value))) if str(value) in names else None


def slider_ids(sliders: Sequence[viser.GuiSliderHandle]) -> list[str]:
    """DOM ids of the joint sliders (the map's click types into their number boxes)."""
    return [handle_uuid(s) for s in sliders]
