"""The GUI of one client: robot choice, status, joints, velocity and force views, display options, J.

Layout: the main control panel (right) holds the robot dropdown, the status
banner and four tabs (Joints, Velocity, Force, View); a second panel docked
on the left shows the Jacobian (frame choice, numeric J, measures, symbolic
J(q) and downloads). Robot-independent parts are built once per client;
robot-dependent parts (:meth:`PanelView.build_robot`) are rebuilt on a robot
switch in place.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

import viser

from kinematics import Robot

from ..snapshot import Snapshot
from ..state import LabState, Options
from .common import sync_value
from .joints import JointsPanel
from .matrix import MatrixPanel
from .rates import ForcePanel, VelocityPanel
from .readouts import measures_html, status_html
from .style import BASE_CSS, SLIDER_KEYS_JS

if TYPE_CHECKING:
    from ..session import ClientSession

__all__ = ["PanelView"]

log = logging.getLogger(__name__)

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


class PanelView:
    """Every GUI handle of one client, grouped by tab."""

    def __init__(
        self, client: viser.ClientHandle, session: ClientSession, robot_names: list[str], state: LabState
    ):
        self.gui = gui = client.gui
        self.session = session
        gui.configure_theme(control_width="large", show_share_button=False, brand_color=(66, 99, 235))
        gui.set_panel_label("Jacobian Lab")
        gui.main_panel.dock_right()
        gui.main_panel.set_width(400)
        gui.add_html(BASE_CSS, order=0)
        _run_javascript(client, SLIDER_KEYS_JS)
        self.robot = gui.add_dropdown("Robot", robot_names, initial_value=state.robot_name, order=1)
        session.on_update(self.robot, lambda h: session.set_robot(h.value))
        self.status = gui.add_html("", order=2)
        tabs = gui.add_tab_group(order=3)
        self.tab_joints = tabs.add_tab("Joints", viser.Icon.ADJUSTMENTS)
        self.tab_velocity = tabs.add_tab("Velocity", viser.Icon.ARROW_UP_RIGHT)
        self.tab_force = tabs.add_tab("Force", viser.Icon.WEIGHT)
        self.tab_view = tabs.add_tab("View", viser.Icon.EYE)
        with self.tab_view:
            self.toggles = {}
            for key, label, hint in _TOGGLES:
                box = gui.add_checkbox(label, initial_value=getattr(state.options, key), hint=hint)
                session.on_update(box, lambda h, key=key: session.set_option(**{key: bool(h.value)}))
                self.toggles[key] = box
            self.scale = gui.add_slider(
                "Arrow & ellipsoid scale",
                min=0.1,
                max=3.0,
                step=0.05,
                initial_value=state.options.scale,
                hint="1: a column of 1 m/rad is drawn 0.5 m long",
            )
            session.on_update(self.scale, lambda h: session.set_option(scale=float(h.value)))
            gui.add_markdown(
                "**Colours.** Each joint has one colour: slider, axis, column arrow and bars. "
                "Ellipsoid and links: blue regular, amber near singular, red singular. "
                "Lost direction (σmin): dark red arrow for its v part, purple for its ω part. "
                "Black arrow: v = J q̇, green: ω; pink: the applied force."
            )
        side = gui.add_panel()
        self.tab_jacobian = side.add_tab("Jacobian J(q)", viser.Icon.MATH)
        side.dock_left()
        self.side = side
        with self.tab_jacobian:
            self.frame = gui.add_dropdown(
                "Frame of J",
                ("base", "tool"),
                initial_value=state.options.jacobian_frame,
                order=10,
                hint="Axes in which the numeric and symbolic J are written",
            )
            session.on_update(self.frame, lambda h: session.set_option(jacobian_frame=h.value))
            self.measures = gui.add_html("", order=30)
        self.joints: JointsPanel | None = None
        self.velocity: VelocityPanel | None = None
        self.force: ForcePanel | None = None
        self.matrix: MatrixPanel | None = None

    def build_robot(self, robot: Robot, rows: tuple[int, ...]) -> None:
        """(Re)build the robot-dependent parts of every tab."""
        self.remove_robot()
        with self.tab_joints:
            self.joints = JointsPanel(self.gui, self.session, robot, order=100)
        with self.tab_velocity:
            self.velocity = VelocityPanel(self.gui, self.session, robot, rows, order=100)
        with self.tab_force:
            self.force = ForcePanel(self.gui, self.session, robot, order=100)
        with self.tab_jacobian:
            self.matrix = MatrixPanel(self.gui, self.session, robot, order=20, symbolic_order=40)
        self.side.set_width(420 + 60 * max(robot.dof - 6, 0))  # room for every column of J

    def remove_robot(self) -> None:
        for part in (self.joints, self.velocity, self.force, self.matrix):
            if part is not None:
                part.remove()
        self.joints = self.velocity = self.force = self.matrix = None

    def show_inputs(self, state: LabState) -> None:
        """Put the state on every input (called with the session's callbacks muted)."""
        assert self.joints and self.velocity and self.force
        sync_value(self.robot, state.robot_name)
        self.joints.show(state.q)
        self.velocity.show_inputs(state.qd, state.v_desired, state.options.damping)
        self.force.show_inputs(state.wrench)
        self.show_options(state.options)

    def show_options(self, options: Options) -> None:
        for key, box in self.toggles.items():
            sync_value(box, getattr(options, key))
        sync_value(self.scale, float(options.scale))
        sync_value(self.frame, options.jacobian_frame)

    def update(self, snap: Snapshot, state: LabState) -> None:
        """Refresh every readout from ``snap``."""
        assert self.velocity and self.force and self.matrix
        status = status_html(snap)
        self.status.content = status
        self.measures.content = measures_html(snap, state.robot)
        self.matrix.update(snap.J_shown, snap.rows, state.options.jacobian_frame, status)
        self.velocity.update(snap)
        self.force.update(snap)


def _run_javascript(client: viser.ClientHandle, source: str) -> None:
    """Run ``source`` in this client's page (viser's own message for it; no public API in viser 1.1)."""
    try:
        from viser._messages import RunJavascriptMessage

        client._websock_connection.queue_message(RunJavascriptMessage(source=source))
    except Exception:  # a page without the fix still works; only the arrow keys also turn the camera
        log.warning("cannot send page script to client %s", client.client_id, exc_info=True)
