"""The GUI of one tab: robot choice, status, joints, and one tab per view of J.

Layout (one panel, docked right, so the 3-D view keeps most of the window):
the robot dropdown, the status banner (with the visited configuration's
description and the lost direction in words), the joint sliders, then tabs
for J(q) (numeric J, measures, symbolic J and downloads), v = J q̇,
q̇ = J⁺ v, τ = Jᵀ F and the View options. The joint sliders stay visible
whichever tab is open, so a student moves a joint while watching any view.

Views never hold the session: they get ``dispatch`` and turn user input
into actions. :meth:`PanelView.draw` puts a state and its snapshot on
screen.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Any

import viser

import robots
from kinematics import Robot
from kinematics.urdf import ChainInfo

from ...core.actions import SetOption
from ...core.commands import ChooseChain, ChooseRobot, ToggleRecording
from ...core.role import Role
from ...core.snapshot import Snapshot
from ...core.state import LabState, Options
from ...viser_adapter import handle_uuid, run_javascript, set_page_title
from .classroom import ClassroomPanel
from .common import Dispatch, bind, sync_value
from .derive import DerivePanel
from .editor import EditorPanel, library_dh_robots
from .joints import JointsPanel, configurations_html
from .mappings import ForcePanel, ForwardPanel, InversePanel
from .matrix import MatrixPanel
from .motion import MapsPanel, MotionPanel, slider_ids
from .readouts import measures_html, source_html, status_html
from .style import BASE_CSS, PAGE_TITLE, page_js, status_css, steps_js

__all__ = ["PanelView", "PANEL_WIDTH"]

PANEL_WIDTH = 400
"""Width of the docked panel [px]: at 1280×720 the 3-D view keeps 69 % of the window."""

_TOGGLES = (
    (
        "velocity_ellipsoid",
        "Velocity ellipsoid",
        "Translational manipulability ellipsoid at the tool point: "
        "semi-axes σᵢ along the left singular vectors of the base-frame linear rows of J.",
    ),
    ("rotational_ellipsoid", "Rotational ellipsoid", "Angular-velocity ellipsoid (ω rows of J)."),
    (
        "force_ellipsoid",
        "Force ellipsoid",
        "Semi-axes 1/σᵢ along the same directions (capped at a singularity).",
    ),
    ("columns", "Columns Jᵢ (linear part)", "Tool-point velocity produced by each joint alone at unit rate."),
    ("angular_columns", "Columns Jᵢ (angular part)", "Drawn on each joint axis."),
    ("frames", "Frames 0…n and tool", "A triad for every DH / link frame and the tool frame."),
    ("labels", "Joint labels", "Name each joint axis in the 3-D view."),
)

_LEGEND = (
    "**Colours.** Each joint has one colour: slider, axis, column arrow and bars. "
    "Ellipsoid and links: blue regular, amber near singular, red singular. "
    "Lost direction (dark crimson): an arrow for a lost translation, "
    "an axis with a ring for a lost rotation. "
    "Black arrow: v = J q̇; umber: ω; light grey: the desired v; navy: the applied force and moment; "
    "violet: J̇ q̇, the tool's acceleration at constant joint rates."
)


class PanelView:
    """Every GUI handle of one tab."""

    def __init__(
        self,
        client: viser.ClientHandle,
        dispatch: Dispatch,
        robot_names: list[str],
        state: LabState,
        classroom: bool = False,
    ):
        self.gui = gui = client.gui
        self.client = client
        self.dispatch = dispatch
        gui.configure_theme(control_width="large", show_share_button=False, brand_color=(59, 91, 219))
        gui.set_panel_label("Jacobian Lab")
        gui.main_panel.dock_right()
        gui.main_panel.set_width(PANEL_WIDTH)
        gui.add_html(BASE_CSS + f"<style>{status_css()}</style>", order=0)
        run_javascript(client, page_js())
        set_page_title(client, PAGE_TITLE)
        self.robot = gui.add_dropdown("Robot", robot_names, initial_value=state.robot_name, order=1)
        bind(self.robot, dispatch, lambda v: ChooseRobot(str(v)))
        self.chain: viser.GuiDropdownHandle | None = None
        self.source = gui.add_html("", order=1.5, visible=False)
        self.status = gui.add_html("", order=2)
        self.classroom = ClassroomPanel(gui, dispatch, order=0.5) if classroom else None
        # The views of J live in a second panel docked under the joints: both stay in sight.
        self.views = gui.add_panel()
        self.tab_matrix = self.views.add_tab("J(q)", viser.Icon.MATH)
        self.tab_forward = self.views.add_tab("v = J q̇", viser.Icon.ARROW_UP_RIGHT)
        self.tab_inverse = self.views.add_tab("q̇ = J⁺v", viser.Icon.ARROW_BACK_UP)
        self.tab_force = self.views.add_tab("τ = JᵀF", viser.Icon.WEIGHT)
        self.tab_motion = self.views.add_tab("Motion", viser.Icon.PLAYER_PLAY)
        self.tab_maps = self.views.add_tab("Maps", viser.Icon.MAP)
        self.tab_derive = self.views.add_tab("Derive", viser.Icon.STAIRS)
        self.tab_view = self.views.add_tab("View", viser.Icon.EYE)
        self.tab_build = self.views.add_tab("Build", viser.Icon.TOOL)
        self.views.dock_below(gui.main_panel)
        with self.tab_view:
            self.toggles = {}
            for key, label, hint in _TOGGLES:
                box = gui.add_checkbox(label, initial_value=getattr(state.options, key), hint=hint)
                bind(box, dispatch, functools.partial(_option, key))
                self.toggles[key] = box
            self.scale = gui.add_slider(
                "Glyph scale",
                min=0.1,
                max=3.0,
                step=0.05,
                initial_value=state.options.scale,
                hint="1: a column of 1 m/rad is drawn 0.5 m long",
            )
            bind(self.scale, dispatch, lambda v: SetOption("scale", float(v)))
            gui.add_markdown(_LEGEND)
            self.record = gui.add_button("Record a demo", icon=viser.Icon.PLAYER_RECORD)
            self.record.on_click(lambda _: dispatch(ToggleRecording()))
            gui.add_html(
                '<div class="jl-note">Records the 3-D view until you press again, then downloads it as a '
                "folder (zip) that plays from any web server, with no Python behind it.</div>"
            )
        with self.tab_build:
            self.editor = EditorPanel(gui, dispatch, library_dh_robots(), order=100)
        self.joints: JointsPanel | None = None
        self.forward: ForwardPanel | None = None
        self.inverse: InversePanel | None = None
        self.force: ForcePanel | None = None
        self.matrix: MatrixPanel | None = None
        self.motion: MotionPanel | None = None
        self.maps: MapsPanel | None = None
        self.derive: DerivePanel | None = None
        self.about: viser.GuiHtmlHandle | None = None

    def build_robot(
        self,
        robot: Robot,
        rows: tuple[int, ...],
        chains: Sequence[ChainInfo] = (),
        chain: str = "",
        meshes: tuple[int, list[str]] = (0, []),
        presets: Sequence[robots.MotionPreset] = (),
    ) -> None:
        """(Re)build the robot-dependent parts.

        Args:
            robot: The robot.
            rows: Its task rows.
            chains: The serial chains of its URDF file (a picker is shown when there are several).
            chain: Tip link of the chain shown ("" for the default one).
            meshes: (found, not found) mesh files of its URDF.
            presets: Its resolved-rate presets (the Motion tab).
        """
        self.remove_robot()
        shown = next((c for c in chains if c.tip_link == chain), None) or next(
            (c for c in chains if c.is_default), None
        )
        if len(chains) > 1:
            labels = {_chain_label(c): c.tip_link for c in chains}
            self.chain = self.gui.add_dropdown(
                "Chain",
                tuple(labels),
                initial_value=_chain_label(shown) if shown else next(iter(labels)),
                order=1.2,
                hint="The serial chain of the URDF shown: from its base link to a tip link.",
            )
            bind(self.chain, self.dispatch, lambda v: ChooseChain(labels[str(v)]) if v in labels else None)
        self.source.content = source_html(robot, shown, meshes)
        self.source.visible = bool(robot.urdf_path)
        self.joints = JointsPanel(self.gui, self.dispatch, robot, order=3)
        with self.tab_matrix:
            self.gui.add_html('<div class="jl-views-marker"></div>', order=0)
            self.matrix = MatrixPanel(self.gui, self.dispatch, robot, order=100)
        with self.tab_forward:
            self.forward = ForwardPanel(self.gui, self.dispatch, robot, order=100)
        with self.tab_inverse:
            self.inverse = InversePanel(self.gui, self.dispatch, robot, rows, order=100, presets=presets)
        with self.tab_force:
            self.force = ForcePanel(self.gui, self.dispatch, robot, order=100)
        with self.tab_motion:
            self.motion = MotionPanel(self.gui, self.dispatch, robot, presets, order=100)
        with self.tab_maps:
            self.maps = MapsPanel(self.gui, self.dispatch, robot, slider_ids(self.joints.sliders), order=100)
        with self.tab_derive:
            self.derive = DerivePanel(self.gui, self.dispatch, robot, order=100)
        with self.tab_view:
            self.about = self.gui.add_html(configurations_html(robot), order=200)
        sliders = [*self.joints.sliders, *self.forward.sliders, *self.inverse.sliders.values()]
        sliders += [*self.force.sliders.values(), self.inverse.damping, self.scale, self.motion.speed]
        sliders.append(self.derive.step)
        if self.motion.self_slider is not None:
            sliders.append(self.motion.self_slider)
        run_javascript(self.client, steps_js({handle_uuid(s): float(s.step) for s in sliders}))

    def set_robot_names(self, names: Sequence[str]) -> None:
        """List ``names`` in the tab's robot dropdown (its own robots first, see app.tab.robots)."""
        names = tuple(names)
        if tuple(self.robot.options) != names:
            self.robot.options = names

    def remove_robot(self) -> None:
        if self.chain is not None:
            self.chain.remove()
            self.chain = None
        parts = (
            self.joints,
            self.forward,
            self.inverse,
            self.force,
            self.matrix,
            self.motion,
            self.maps,
            self.derive,
            self.about,
        )
        for part in parts:
            if part is not None:
                part.remove()
        self.joints = self.forward = self.inverse = self.force = self.matrix = self.about = None
        self.motion = self.maps = self.derive = None

    def draw(self, state: LabState, snap: Snapshot) -> None:
        """Put ``state`` on every input and ``snap`` on every readout (the session ignores echoes)."""
        assert self.joints and self.forward and self.inverse and self.force and self.matrix
        assert self.motion and self.maps and self.derive
        sync_value(self.robot, state.robot_name)
        self.joints.show(state.q, state.configuration)
        self.forward.show(state)
        self.inverse.show(state)
        self.force.show(state)
        self.matrix.show(state.options.jacobian_frame)
        self.matrix.show_course(state, snap)
        self._show_options(state.options)
        status = status_html(snap, state)
        self.status.content = status
        self.matrix.update(
            snap.J_shown, snap.rows, state.options.jacobian_frame, status, measures_html(snap, state.robot)
        )
        self.forward.update(snap, state)
        self.inverse.update(snap, state)
        self.force.update(snap, state)
        self.motion.draw(state, snap)
        self.maps.draw(state, snap)
        self.derive.draw(state, snap)

    def show_recording(self, recording: bool) -> None:
        """The record button says what a click does next."""
        self.record.label = "Stop and download the demo" if recording else "Record a demo"
        self.record.color = "red" if recording else None

    def show_role(self, role: Role) -> None:
        """The tab's classroom role (nothing without a presenter mode)."""
        if self.classroom is not None:
            self.classroom.show(role)

    def _show_options(self, options: Options) -> None:
        for key, box in self.toggles.items():
            sync_value(box, getattr(options, key))
        sync_value(self.scale, float(options.scale))


def _chain_label(chain: ChainInfo) -> str:
    return f"{chain.base_link} → {chain.tip_link} ({chain.dof} joints)"


def _option(key: str, value: Any) -> SetOption:
    return SetOption(key, bool(value))
