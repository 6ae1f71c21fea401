"""One browser tab: its state, its scene and panel handles, its lock, and the one update path.

Every change goes the same way: a callback (in viser's thread pool) takes
the session's lock, changes :attr:`ClientSession.state`, and calls
:meth:`ClientSession.refresh`, which computes one
:class:`~app.snapshot.Snapshot` and redraws scene and panel in one
``atomic`` batch. Inputs the session sets itself (a configuration button
moving every slider) are written with callbacks muted, so one click is one
computation.

The public methods (:meth:`set_joint`, :meth:`set_configuration`,
:meth:`apply`, ...) are the session's API for future features too: a
classroom mode calls :meth:`apply` with the presenter's state on every
student session; IK target dragging and resolved-rate animation call
:meth:`set_configuration` from their own callbacks or threads (under the
lock, which is re-entrant); a DH editor or URDF upload lists its file with
:meth:`~app.catalog.RobotCatalog.add_file` and calls :meth:`set_robot`.

An exception in any callback is caught here: it is logged, shown to this
client as a notification, and never reaches the server or other clients.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import math
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import Future

import viser

from kinematics import as_configuration
from kinematics.analysis import task_rows

from . import fmt
from .catalog import RobotCatalog
from .panel import PanelView
from .scene import SceneView
from .snapshot import Snapshot, compute
from .state import LabState
from .symbolic import SymbolicService, SymbolicUnavailable

__all__ = ["ClientSession"]

log = logging.getLogger(__name__)


class ClientSession:
    """State and handles of one connected client.

    Attributes:
        client: The viser client handle.
        state: What this client has chosen (:class:`~app.state.LabState`).
        snapshot: The last computed snapshot (what is on screen).
        scene: The client's 3-D view.
        panel: The client's GUI.
        lock: Re-entrant lock guarding all of the above.
        errors: Number of callback errors shown to this client.
        refreshes: Number of redraws so far (one per event).
    """

    def __init__(
        self, client: viser.ClientHandle, catalog: RobotCatalog, symbolic: SymbolicService, robot_name: str
    ) -> None:
        self.client = client
        self.catalog = catalog
        self.symbolic = symbolic
        self.lock = threading.RLock()
        self.errors = 0
        self.refreshes = 0
        self._muted = 0
        self._closed = False
        self.snapshot: Snapshot | None = None
        self.scene: SceneView | None = None
        self._symbolic_wanted: tuple | None = None
        with self.lock:
            self.state = LabState.initial(robot_name, catalog.load(robot_name))
            self.panel = PanelView(client, self, catalog.names(), self.state)
            self._build()
        client.camera.on_update(self._camera_moved)

    # ------------------------------------------------------------- wiring
    def on_update(self, handle: viser.GuiInputHandle, fn: Callable[[viser.GuiInputHandle], None]) -> None:
        """Call ``fn(handle)`` when the user changes ``handle`` (guarded, locked, muted while syncing)."""
        handle.on_update(self._guarded(lambda event: fn(event.target)))

    def on_click(self, button: viser.GuiButtonHandle, fn: Callable[[], None]) -> None:
        """Call ``fn()`` when ``button`` is clicked (guarded and locked)."""
        button.on_click(self._guarded(lambda event: fn()))

    def on_click_value(self, group: viser.GuiButtonGroupHandle, fn: Callable[[str], None]) -> None:
        """Call ``fn(option)`` when a button of ``group`` is clicked (guarded and locked)."""
        group.on_click(self._guarded(lambda event: fn(event.target.value)))

    def _guarded(self, fn: Callable[[viser.GuiEvent], None]) -> Callable[[viser.GuiEvent], None]:
        def callback(event: viser.GuiEvent) -> None:
            try:
                with self.lock:
                    if self._closed or self._muted or event.target._impl.removed:
                        return
                    fn(event)
            except Exception as exc:  # one client's error must never reach the server or other clients
                self.report_error(exc)

        return callback

    @contextlib.contextmanager
    def muted(self) -> Iterator[None]:
        """Within this block, inputs the session sets do not call back."""
        with self.lock:
            self._muted += 1
            try:
                yield
            finally:
                self._muted -= 1

    def report_error(self, exc: BaseException) -> None:
        """Log ``exc`` and tell this client, in words, that its last action failed."""
        self.errors += 1
        log.error("client %s: %s", self.client.client_id, exc, exc_info=exc)
        with contextlib.suppress(Exception):
            self.client.add_notification(
                "That did not work", f"{type(exc).__name__}: {exc}", color="red", auto_close_seconds=10.0
            )

    # ------------------------------------------------------------- actions
    def set_joint(self, i: int, value: float) -> None:
        """Set joint ``i`` to ``value`` [rad | m] and redraw."""
        with self.lock:
            self.state.q[i] = _finite(value, "joint value")
            self.state.configuration = ""
            self._show_inputs()
            self.refresh()

    def go_to(self, name: str) -> None:
        """Move to the named configuration ``name`` ("home" or one of the robot's)."""
        robot = self.state.robot
        q = robot.home if name == "home" else robot.configuration(name)
        self.set_configuration(q, name)

    def set_configuration(self, q: object, name: str = "") -> None:
        """Move every joint to ``q`` (n,) [rad | m]: sliders follow, one redraw."""
        with self.lock:
            q = as_configuration(self.state.robot, q)
            if q.ndim != 1:
                raise ValueError(
                    f"expected one configuration of shape ({self.state.robot.dof},), got {q.shape}"
                )
            self.state.q = q.copy()
            self.state.configuration = name
            self._show_inputs()
            self.refresh()

    def set_rate(self, i: int, value: float) -> None:
        """Set joint rate q̇ᵢ [rad/s | m/s] of the forward view."""
        with self.lock:
            self.state.qd[i] = _finite(value, "joint rate")
            self._show_inputs()
            self.refresh()

    def stop_rates(self) -> None:
        """Set every joint rate of the forward view to zero."""
        with self.lock:
            self.state.qd[:] = 0.0
            self._show_inputs()
            self.refresh()

    def set_desired(self, row: int, value: float) -> None:
        """Set component ``row`` of the desired tool twist [m/s | rad/s]."""
        with self.lock:
            self.state.v_desired[row] = _finite(value, "tool velocity")
            self._show_inputs()
            self.refresh()

    def set_wrench(self, row: int, value: float) -> None:
        """Set component ``row`` of the wrench applied at the tool [N | N·m]."""
        with self.lock:
            self.state.wrench[row] = _finite(value, "force")
            self._show_inputs()
            self.refresh()

    def clear_wrench(self) -> None:
        """Remove the force and moment applied at the tool."""
        with self.lock:
            self.state.wrench[:] = 0.0
            self._show_inputs()
            self.refresh()

    def set_option(self, **changes: object) -> None:
        """Change display options (see :class:`~app.state.Options`) and redraw."""
        with self.lock:
            old = self.state.options
            for key in ("scale", "damping"):
                if key in changes:
                    changes[key] = _finite(changes[key], key)
            self.state.options = dataclasses.replace(old, **changes)
            if self.state.options.jacobian_frame != old.jacobian_frame:
                self._request_symbolic()
            self._show_inputs()
            self.refresh()

    def set_robot(self, name: str) -> None:
        """Switch to robot ``name`` of the catalogue: rebuild scene and panel, keep the display options."""
        with self.lock:
            if name == self.state.robot_name:
                return
            try:
                robot = self.catalog.load(name)
            except Exception:
                with self.muted():
                    self.panel.robot.value = self.state.robot_name
                raise
            self.apply(LabState.initial(name, robot, self.state.options))

    def apply(self, state: LabState) -> None:
        """Take over a whole state (e.g. a presenter's): rebuild if the robot differs, else update inputs."""
        with self.lock:
            rebuild = state.robot is not self.state.robot
            self.state = state.copy()
            if rebuild:
                self._build()
            else:
                self._show_inputs()
                self._request_symbolic()
                self.refresh()

    def download(self, label: str) -> None:
        """Send J(q) exported as ``label`` ("LaTeX", "Python" or "JSON") to this client when it is ready."""
        robot, frame = self.state.robot, self.state.options.jacobian_frame
        note = self.client.add_notification(
            f"Preparing J(q) as {label}…",
            f"{robot.title or robot.name}, {frame} axes",
            loading=True,
            with_close_button=False,
        )
        self.symbolic.export(robot, label, frame).add_done_callback(lambda f: self._download_ready(f, note))

    def _download_ready(self, future: Future[tuple[str, bytes]], note: viser.NotificationHandle) -> None:
        with contextlib.suppress(Exception):
            note.remove()
        if self._closed:
            return
        try:
            filename, content = future.result()
        except SymbolicUnavailable as exc:
            self.client.add_notification(
                "Download not available", str(exc), color="yellow", auto_close_seconds=8
            )
        except Exception as exc:
            self.report_error(exc)
        else:
            self.client.send_file_download(filename, content, save_immediately=True)

    # ------------------------------------------------------------- drawing
    def _show_inputs(self) -> None:
        """Put the state on every input, muted: inputs already showing their value send nothing."""
        with self.muted():
            self.panel.show_inputs(self.state)

    def refresh(self) -> None:
        """Compute the snapshot of the current state once and redraw everything in one batch."""
        with self.lock:
            if self._closed:
                return
            snap = compute(self.state)
            with self.client.atomic():
                self.scene.update(snap, self.state)
                self.panel.update(snap, self.state)
            self.snapshot = snap
            self.refreshes += 1

    def _build(self) -> None:
        """Build scene and robot-dependent panel parts for the current robot, then draw."""
        robot = self.state.robot
        with self.client.atomic():
            if self.scene is not None:
                self.scene.remove()
            self.scene = SceneView(self.client, robot)
            self.panel.build_robot(robot, task_rows(robot))
            self._show_inputs()
        self.refresh()
        self.scene.frame_camera(self.snapshot, robot.planar)
        self._request_symbolic()

    def _camera_moved(self, _camera: viser.CameraHandle) -> None:
        try:
            with self.lock:
                if not self._closed and self.scene is not None:
                    self.scene.follow_canvas()
        except Exception as exc:
            self.report_error(exc)

    def _request_symbolic(self) -> None:
        """Ask for the symbolic J(q) of the current robot and frame (releasing the previous request)."""
        robot, frame = self.state.robot, self.state.options.jacobian_frame
        if self._symbolic_wanted == (robot, frame):
            return
        self._release_symbolic()
        self._symbolic_wanted = (robot, frame)
        future = self.symbolic.mathml(robot, frame)
        if not future.done():
            self.panel.matrix.show_symbolic(
                None, "computing the symbolic form… (the numeric J above is live)"
            )
        future.add_done_callback(lambda f: self._symbolic_ready(f, robot, frame))

    def _release_symbolic(self) -> None:
        if self._symbolic_wanted is not None:
            self.symbolic.release(*self._symbolic_wanted)
            self._symbolic_wanted = None

    def _symbolic_ready(self, future: Future[str], robot, frame: str) -> None:
        try:
            with self.lock:
                if (
                    self._closed
                    or robot is not self.state.robot
                    or frame != self.state.options.jacobian_frame
                ):
                    return
                try:
                    mathml, note = future.result(), f"J(q) in {frame} axes, from kinematics.symbolic."
                except SymbolicUnavailable as exc:
                    mathml, note = None, str(exc)
                except Exception as exc:
                    mathml, note = None, f"symbolic form not available: {type(exc).__name__}: {exc}"
                self.panel.matrix.show_symbolic(mathml, note)
        except Exception as exc:
            self.report_error(exc)

    def close(self) -> None:
        """Forget the client (it has gone: its handles went with its connection)."""
        with self.lock:
            self._closed = True
            self._release_symbolic()


def _finite(value: object, what: str) -> float:
    """``value`` as a finite float, or ValueError naming ``what`` (state never holds NaN or ∞)."""
    x = float(value)  # type: ignore[arg-type]
    if not math.isfinite(x):
        raise ValueError(f"{what} must be a finite number, got {fmt.number(x)}")
    return x
