"""One browser tab: its frozen state, one dispatch, one compute and one atomic redraw per event.

The flow is one-way::

    view input ─► dispatch(action) ─► reduce(state, action) ─► state ─► compute(state) ─► snapshot
                                                                          └──────► views draw(state, snapshot)

:meth:`ClientSession.dispatch` is the only way in, for the views, the
tab's :class:`~app.tab.ticker.Ticker` and the server's :class:`~app.services.classroom.Classroom`
alike. It only queues the action: the server's one :class:`~app.services.renderer.Renderer`
thread visits tabs in turn and reduces everything a tab queued since its last
visit before drawing it once, so a burst of slider messages costs one
computation, and redraws of one tab are at most :data:`MAX_REDRAWS_PER_SECOND`. Two actions are
*commands* the session carries out itself: loading a robot
(:class:`~app.core.actions.ChooseRobot`) and preparing a download.

After each change the session tells its subscribers (the classroom, a
recorder) the new state, starts or stops the ticker, asks for the symbolic
J when the robot or frame changed, and re-frames the camera when what is
drawn left the view after a jump (a named configuration, a robot switch, a
reshaped canvas).

An error in any action is logged and shown to this tab only, in words.
"""

from __future__ import annotations

import contextlib
import logging
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future

import numpy as np
import viser

from kinematics.analysis import task_rows

from ..core.actions import (
    CLASSROOM,
    Action,
    ChooseChain,
    ChooseRobot,
    ClaimPresenter,
    DriveTool,
    EditRobot,
    ExploreAlone,
    FindSingularity,
    FollowPath,
    FollowPresenter,
    GoTo,
    Mirror,
    Redraw,
    ReplaceState,
    RequestDownload,
    ResetView,
    SetConfiguration,
    SetJoint,
    SetRobot,
    Step,
    StopPresenting,
    ToggleRecording,
    UploadRobot,
)
from ..core.build_table import BUILT_NAME, robot_file
from ..core.reducer import reduce
from ..core.snapshot import Snapshot, compute
from ..core.state import LabState
from ..services.background import background, nearest_path
from ..services.catalog import RobotCatalog
from ..services.classroom import Classroom, Role
from ..services.renderer import Renderer
from ..services.symbolic_service import SymbolicService, SymbolicUnavailable
from ..views.camera import FROM_ABOVE, TabCamera, facing
from ..views.panel import PanelView
from ..views.scene import SceneView
from ..viser_adapter import capture_scene, replay_scene
from .recorder import TabRecorder, demo_zip
from .robots import TabCatalog
from .symbols import TabSymbols
from .ticker import Ticker

__all__ = ["ClientSession", "MAX_REDRAWS_PER_SECOND"]

log = logging.getLogger(__name__)

TOKEN_PAUSE = 0.6
"""A typed presenter token is tried once the typing has paused this long [s]."""
MAX_REDRAWS_PER_SECOND = 40.0
"""A tab is redrawn at most this often; faster input is coalesced (all of it is reduced, drawn once)."""
_JUMP = 0.35
"""A joint moving more than this [rad | m] in one action is a jump: the camera may re-frame."""


class ClientSession:
    """State, views and effects of one connected tab.

    Attributes:
        client: The viser client handle.
        state: What this tab has chosen (frozen :class:`~app.core.state.LabState`).
        snapshot: The last computed snapshot (what is on screen).
        ticker: The tab's clock (moves the joints while playing).
        errors: Number of errors shown to this tab.
        redraws: Number of redraws so far (one per batch of events).
    """

    def __init__(
        self,
        client: viser.ClientHandle,
        catalog: RobotCatalog,
        symbolic: SymbolicService,
        robot_name: str,
        ticker: Ticker | None = None,
        renderer: Renderer | None = None,
        classroom: Classroom | None = None,
    ) -> None:
        self.client = client
        self.key = client.client_id
        self.classroom = classroom
        self.role = Role()
        self._told_read_only = 0.0
        self.catalog = TabCatalog(catalog)  # the shared robots plus this tab's own (uploads, Build tab)
        self.symbolic = symbolic
        self.lock = threading.RLock()
        self.errors = 0
        self.redraws = 0
        self._queue: list[Action] = []
        self._queue_lock = threading.Lock()
        self._scheduled = False
        self._own_renderer = renderer is None
        self.renderer = renderer if renderer is not None else Renderer()
        self._drawing = threading.local()
        self._closed = False
        self._last_redraw = 0.0
        self._subscribers: list[Callable[[LabState, Snapshot], None]] = []
        self.symbols = TabSymbols(
            symbolic, lambda: self.panel, self.lock, lambda: self._closed, self.report_error
        )
        self.camera = TabCamera(client)
        self.recorder = TabRecorder(self.subscribe)
        self._scene_messages: tuple = ()
        self._typed_token = ""
        self._token_timer: threading.Timer | None = None
        self._scene_foreign = False
        self.ticker = ticker if ticker is not None else Ticker(self.dispatch)
        self.snapshot: Snapshot | None = None
        self.scene: SceneView | None = None
        with self.lock:
            self.state = LabState.initial(robot_name, catalog.load(robot_name))
            self.panel = PanelView(
                client, self.dispatch, self.catalog.names(), self.state, classroom is not None
            )
            self._commit(self.state, rebuild=True, jump=True)
        client.camera.on_update(self._camera_moved)

    # ------------------------------------------------------------------ the way in
    def dispatch(self, action: Action) -> None:
        """Queue ``action`` (from a view, the ticker or the classroom); the renderer reduces and draws it.

        Safe from any thread; returns at once. Echoes of the session's own redraw (inputs it sets)
        are ignored. :meth:`settle` waits until everything dispatched is on screen.
        """
        if getattr(self._drawing, "active", False) or self._closed:
            return
        with self._queue_lock:
            self._queue.append(action)
            if self._scheduled:
                return  # the renderer will take it with the others on its next visit
            self._scheduled = True
        self.renderer.schedule(self)

    def next_visit(self) -> float:
        """When this tab may be redrawn again [monotonic s] (at most MAX_REDRAWS_PER_SECOND)."""
        return self._last_redraw + 1.0 / MAX_REDRAWS_PER_SECOND

    def visit(self) -> bool:
        """Reduce every queued action and redraw once (called by the renderer thread).

        Returns:
            True when actions arrived meanwhile (the renderer visits again).
        """
        with self._queue_lock:
            actions, self._queue = _coalesced(self._queue), []
        if actions and not self._closed:
            with self.lock:
                state, jump, force = self.state, False, False
                given: Mirror | None = None
                replay: list | None = []  # the presenter's scene messages, in order (None: draw our own)
                for action in actions:
                    if isinstance(action, Mirror):  # the presenter's state, drawn as it is
                        state, given, jump = action.state, action, False  # the camera is the presenter's
                        new_robot = state.robot is not self.state.robot  # only then may it be unknown here
                        if new_robot and self.catalog.keep_shown(state.robot_name, state.robot):
                            self.panel.set_robot_names(self.catalog.names())
                        if replay is not None and action.scene and self.scene is not None:
                            replay.extend(action.scene)
                        else:
                            replay = None
                        continue
                    if isinstance(action, Redraw):
                        force = True
                        continue
                    if self.role.following and not isinstance(
                        action, (*CLASSROOM, RequestDownload, ToggleRecording)
                    ):
                        force = force or not isinstance(action, Step)  # undo what the input shows
                        self._tell_read_only(action)
                        continue
                    try:
                        before = state
                        state = self._apply(state, action)
                        jump = jump or _is_jump(before, state, action)
                    except Exception as exc:  # one tab's bad input never reaches the server or other tabs
                        self.report_error(exc)
                if state is not self.state or force:
                    mirrored = given is not None and given.state is state
                    snap = given.snapshot if given is not None and mirrored else None
                    scene = replay if mirrored and replay else None
                    try:
                        self._commit(
                            state,
                            rebuild=state.robot is not self.state.robot,
                            jump=jump,
                            snap=snap,
                            scene=scene,
                        )
                    except Exception as exc:  # the tab keeps its last good state on screen
                        self.report_error(exc)
        with self._queue_lock:
            if self._queue and not self._closed:
                return True
            self._scheduled = False
            return False

    def _apply(self, state: LabState, action: Action) -> LabState:
        """Reduce ``action``; carry out the commands (load a robot, prepare a download)."""
        if isinstance(action, ChooseRobot):
            if action.name == state.robot_name:
                return state
            return reduce(state, SetRobot(action.name, self.catalog.load(action.name)))
        if isinstance(action, ChooseChain):
            default = next((c.tip_link for c in self.catalog.chains(state.robot_name) if c.is_default), "")
            if action.tip_link == (state.chain or default):
                return state
            robot = self.catalog.load_chain(state.robot_name, action.tip_link)
            return reduce(state, SetRobot(state.robot_name, robot, chain=action.tip_link))
        if isinstance(action, (EditRobot, UploadRobot)):
            return self._own_robot(state, action)
        if isinstance(action, RequestDownload):
            self._download(state, action.label)
            return state
        if isinstance(action, (ClaimPresenter, StopPresenting, ExploreAlone, FollowPresenter)):
            self._classroom_command(action)
            return state
        if isinstance(action, ToggleRecording):
            self._toggle_recording(state)
            return state
        if isinstance(action, ResetView):
            self._reset_view(state)
            return state
        if isinstance(action, FindSingularity):
            self._find_singularity(state)
            return state.replace(playing=False, stopped="looking for the nearest singularity…")
        return reduce(state, action)

    def _own_robot(self, state: LabState, action: EditRobot | UploadRobot) -> LabState:
        """A robot only this tab has: the Build tab's table, or an uploaded URDF (listed first in its
        dropdown; :meth:`app.tab.robots.TabCatalog.share` would show it to every tab)."""
        if isinstance(action, EditRobot):
            self.catalog.remember_built(action.robot)
            after = reduce(state, action)
        else:
            name = self.catalog.add_upload(action.filename, action.content, action.refused_size)
            after = reduce(state, SetRobot(name, self.catalog.load(name)))
        self.panel.set_robot_names(self.catalog.names())
        return after

    def _find_singularity(self, state: LabState) -> None:
        """Descend to the nearest singularity away from the drawing thread, then play the descent."""
        robot, q = state.robot, np.array(state.q)

        def done(future: Future[FollowPath]) -> None:
            if self._closed or self.state.robot is not robot:
                return
            try:
                self.dispatch(future.result())
            except Exception as exc:
                self.report_error(exc)

        background().submit(nearest_path, robot, q).add_done_callback(done)

    @property
    def closed(self) -> bool:
        """Whether the tab has gone (its session no longer draws)."""
        return self._closed

    @property
    def pending(self) -> bool:
        """Whether actions of this tab wait for, or are in, the renderer's visit."""
        with self._queue_lock:
            return self._scheduled

    @property
    def queued(self) -> int:
        """How many actions wait to be reduced."""
        with self._queue_lock:
            return len(self._queue)

    def settle(self, timeout: float = 10.0) -> None:
        """Wait until every dispatched action has been drawn (for tests and scripts).

        Raises:
            TimeoutError: actions are still queued after ``timeout`` seconds.
        """
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with self._queue_lock:
                if not self._scheduled and not self._queue:
                    return
            time.sleep(0.005)
        raise TimeoutError(f"client {self.client.client_id}: actions still queued after {timeout} s")

    def subscribe(self, fn: Callable[[LabState, Snapshot], None]) -> Callable[[], None]:
        """Call ``fn(state, snapshot)`` after every change (the classroom, a recorder); returns the
        unsubscribe function."""
        with self.lock:
            self._subscribers.append(fn)

        def unsubscribe() -> None:
            with self.lock, contextlib.suppress(ValueError):
                self._subscribers.remove(fn)

        return unsubscribe

    # ------------------------------------------------------------------ commit and draw
    def _commit(
        self, state: LabState, rebuild: bool, jump: bool, snap: object = None, scene: list | None = None
    ) -> None:
        """Take ``state``: compute its snapshot once (unless given: the presenter's), redraw in one
        batch, then run the effects. ``scene``: the presenter's scene messages to replay instead of
        drawing the scene (a follower's scene then shows the presenter's nodes)."""
        old = self.state
        snap = snap if isinstance(snap, Snapshot) else compute(state)
        self._drawing.active = True
        capturing: contextlib.AbstractContextManager[list] = (
            capture_scene(self.client) if self.role.presenting else contextlib.nullcontext([])
        )
        try:
            with self.client.atomic(), capturing as captured:
                if rebuild or self.scene is None:
                    name = state.robot_name
                    self.panel.build_robot(
                        state.robot,
                        task_rows(state.robot),
                        self.catalog.chains(name),
                        state.chain,
                        self.catalog.meshes(name),
                        self.catalog.presets(name),
                    )
                if scene is not None and self.scene is not None:
                    replay_scene(self.client, scene)  # the presenter's scene, drawn once for the room
                    self._scene_foreign = True  # our SceneView no longer knows what the browser shows
                else:
                    if rebuild or self.scene is None or self._scene_foreign:
                        if self.scene is not None:
                            self.scene.remove()
                        self.scene = SceneView(self.client, state.robot, self.dispatch)
                        self._scene_foreign = False
                    self.scene.update(snap, state)
                self.panel.draw(state, snap)
                self.panel.show_role(self.role)
            self._scene_messages = tuple(captured)
        finally:
            self._drawing.active = False
        self.state, self.snapshot = state, snap
        self.redraws += 1
        self._last_redraw = time.monotonic()
        if state.playing and not self.role.following:  # a follower moves with the presenter's clock
            self.ticker.start()
        else:
            self.ticker.stop()
        self.symbols.update(state, None if rebuild else old)
        assert self.scene is not None
        if self.role.following:
            return self._tell_subscribers(state, snap)  # the camera is the presenter's
        pad = 0.18 * self.scene.size  # link meshes and labels reach beyond the points drawn
        edited = state.robot_name == old.robot_name == BUILT_NAME  # the Build tab: keep the user's view
        if rebuild and not edited:
            self._reset_view(state)
        elif jump or edited:
            self.camera.frame_if_needed(self.scene.extent, pad)
        self._tell_subscribers(state, snap)

    def _reset_view(self, state: LabState) -> None:
        """Frame the whole arm from the robot's default direction (as when it was chosen)."""
        if self.scene is not None:
            direction = FROM_ABOVE if state.robot.planar else facing(self.scene.extent)
            self.camera.frame(self.scene.extent, 0.18 * self.scene.size, direction, glide=False)

    def _tell_subscribers(self, state: LabState, snap: Snapshot) -> None:
        for fn in list(self._subscribers):
            try:
                fn(state, snap)
            except Exception:
                log.exception("a subscriber of client %s failed", self.client.client_id)

    # ------------------------------------------------------------------ classroom
    @property
    def latest(self) -> tuple[LabState, Snapshot | None]:
        """The state and snapshot on screen."""
        return self.state, self.snapshot

    def mirror(self, state: LabState, snapshot: Snapshot, scene: tuple = ()) -> None:
        """Draw the presenter's state (queued like any action; the latest of a burst wins; the scene
        messages of every one are replayed, in order)."""
        self.dispatch(Mirror(state, snapshot, scene))

    @property
    def scene_messages(self) -> tuple:
        """The scene messages of this tab's last redraw (collected only while it presents)."""
        return self._scene_messages

    def mirror_camera(self, position: tuple, look_at: tuple, up: tuple) -> None:
        """Look where the presenter looks."""
        if self._closed or not self.role.following:
            return
        with contextlib.suppress(Exception):
            with self.client.atomic():
                self.client.camera.up_direction = up
                self.client.camera.position = position
                self.client.camera.look_at = look_at

    def role_changed(self, role: Role) -> None:
        """The classroom says what this tab now is (redrawn on the renderer's next visit)."""
        following_before = self.role.following
        self.role = role
        if role.note and not role.presenting:
            self.notify("Classroom", role.note)
        if role.following and not following_before:
            self.ticker.stop()
        self.dispatch(Redraw())

    def _classroom_command(self, action: Action) -> None:
        if self.classroom is None:
            raise ValueError(
                "this server has no presenter mode (start it with --presenter or --presenter-token)"
            )
        if isinstance(action, ClaimPresenter):
            if not action.settled:  # wait until the typing pauses, then try the latest text once
                self._typed_token = action.token
                if self._token_timer is not None:
                    self._token_timer.cancel()
                settled = ClaimPresenter(action.token, settled=True)
                self._token_timer = threading.Timer(TOKEN_PAUSE, self.dispatch, (settled,))
                self._token_timer.daemon = True
                self._token_timer.start()
                return
            if action.token != self._typed_token:
                return  # typing went on: a later try comes
            why = self.classroom.claim(self.key, action.token)
            if why:
                self.client.add_notification("Not the presenter", why, color="yellow", auto_close_seconds=6.0)
        elif isinstance(action, StopPresenting):
            self.classroom.resign(self.key)
        elif isinstance(action, ExploreAlone):
            self.classroom.explore_alone(self.key)
        elif isinstance(action, FollowPresenter):
            self.classroom.follow(self.key)

    def _toggle_recording(self, state: LabState) -> None:
        """Start recording this tab, or stop and send the demo (built away from the drawing thread)."""
        if not self.recorder.recording:
            self.recorder.start(state, self.snapshot)
            self.panel.show_recording(True)
            return
        frames = self.recorder.stop()
        self.panel.show_recording(False)
        if len(frames) < 2:
            self.notify("Nothing recorded", "Move something between starting and stopping the recording.")
            return
        title = f"{state.robot.title or state.robot.name} — recorded in Jacobian Lab"
        note = self.client.add_notification(
            "Preparing the demo…", f"{len(frames)} frames", loading=True, with_close_button=False
        )

        def done(future: Future[bytes]) -> None:
            with contextlib.suppress(Exception):
                note.remove()
            if self._closed:
                return
            try:
                self.client.send_file_download(
                    "jacobian-lab-demo.zip", future.result(), save_immediately=True
                )
            except Exception as exc:
                self.report_error(exc)

        background().submit(demo_zip, frames, title).add_done_callback(done)

    def _tell_read_only(self, action: Action) -> None:
        """A follower moved an input: say once in a while that its inputs follow the presenter."""
        now = time.monotonic()
        if isinstance(action, Step) or now - self._told_read_only < 5.0:
            return
        self._told_read_only = now
        self.notify(
            "You follow the presenter", "Your inputs follow the presenter: press “Explore on my own” first."
        )

    def notify(self, title: str, body: str) -> None:
        """Show this tab a short notice (e.g. the symbolic worker was restarted)."""
        if self._closed:
            return
        with contextlib.suppress(Exception):
            self.client.add_notification(title, body[:300], color="yellow", auto_close_seconds=8.0)

    def report_error(self, exc: BaseException) -> None:
        """Log ``exc`` and tell this tab, in words, that its last action failed."""
        self.errors += 1
        log.error("client %s: %s", self.client.client_id, str(exc)[:300])
        with contextlib.suppress(Exception):
            self.client.add_notification(
                "That did not work",
                f"{type(exc).__name__}: {str(exc)[:300]}",
                color="red",
                auto_close_seconds=10.0,
            )

    # ------------------------------------------------------------------ camera
    def _camera_moved(self, camera: viser.CameraHandle) -> None:
        """The canvas changed shape (a panel collapsed, the window resized): keep everything in view.
        The presenter's camera is relayed to the followers."""
        try:
            if self.classroom is not None and self.role.presenting:
                pose = tuple(camera.position), tuple(camera.look_at), tuple(camera.up_direction)
                self.classroom.camera(self.key, *pose)
            if self.camera.canvas_changed(float(camera.aspect)):
                with self.lock:
                    if not self._closed and self.scene is not None:
                        self.camera.frame_if_needed(self.scene.extent, 0.18 * self.scene.size)
        except Exception as exc:
            self.report_error(exc)

    # ------------------------------------------------------------------ downloads
    def _download(self, state: LabState, label: str) -> None:
        robot, frame = state.robot, state.options.jacobian_frame
        file = robot_file(robot, label)  # the robot itself (robot file, URDF); else its symbolic J
        if file is not None:
            self.client.send_file_download(*file, save_immediately=True)
            return
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

    # ------------------------------------------------------------------ end
    def close(self) -> None:
        """Forget the tab (it has gone: its handles went with its connection). Stops its ticker."""
        self._closed = True
        if self._token_timer is not None:
            self._token_timer.cancel()
        self.ticker.close()
        if self._own_renderer:
            self.renderer.close()
        self.camera.close()
        with self.lock:
            self.symbols.release()
            self._subscribers.clear()


def _coalesced(actions: list[Action]) -> list[Action]:
    """``actions`` without drag events that a later one in the same batch supersedes (IK is solved once,
    for the latest pose of the handle)."""
    return [
        a
        for a, b in zip(actions, [*actions[1:], None], strict=True)
        if not (isinstance(a, DriveTool) and isinstance(b, DriveTool))
    ]


def _is_jump(before: LabState, after: LabState, action: Action) -> bool:
    """Whether ``action`` moved the arm far at once (the camera may need to follow)."""
    if isinstance(action, (GoTo, SetConfiguration, ReplaceState)):
        return True
    if isinstance(action, SetJoint) and before.robot is after.robot:
        return bool(np.max(np.abs(np.asarray(after.q) - np.asarray(before.q))) > _JUMP)
    return False
