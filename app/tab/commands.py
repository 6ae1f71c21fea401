"""The command runner of one tab: it carries out what is not a change of state.

:meth:`CommandRunner.run` takes one :data:`~app.core.commands.Command` (told apart by type) and
returns what the session's loop does next: a reducible action (a loaded robot becomes
:class:`~app.core.actions.SetRobot`), :class:`~app.core.commands.Redraw` (the tab looks different
though its state did not change: a recording started), or ``None``. Slow work (the nearest
singularity, a symbolic export, a demo zip) runs away from the drawing thread and comes back as a
dispatched action or a download. The runner touches no view: what it changes is drawn by the
session's next draw.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from typing import Any

import numpy as np

from ..core.actions import Action, FollowPath, SetRobot, Wait
from ..core.build_table import robot_file
from ..core.commands import (
    ChooseChain,
    ChooseRobot,
    ClaimPresenter,
    Command,
    ExploreAlone,
    FindSingularity,
    FollowPresenter,
    Message,
    Redraw,
    RequestDownload,
    StopPresenting,
    ToggleRecording,
    UploadRobot,
)
from ..core.snapshot import Snapshot
from ..core.state import LabState
from ..services.background import background, nearest_path
from ..services.symbolic_service import SymbolicService, SymbolicUnavailable
from .following import Following
from .notices import Notices
from .recorder import TabRecorder, demo_zip
from .robots import TabCatalog

__all__ = ["CommandRunner", "LOOKING"]

LOOKING = "looking for the nearest singularity…"
"""What the status says while the nearest singularity is looked for."""


class CommandRunner:
    """Carries out one tab's commands.

    Args:
        client: The tab's viser client (``send_file_download``).
        catalog: The tab's robots.
        symbolic: The shared symbolic service (exports).
        recorder: The tab's recorder.
        following: The tab's classroom side.
        notices: The tab's notices.
        dispatch: The session's way in (results that come back later).
        shown: The state and snapshot on screen.
        closed: Whether the tab has gone.
    """

    def __init__(
        self,
        client: Any,
        catalog: TabCatalog,
        symbolic: SymbolicService,
        recorder: TabRecorder,
        following: Following,
        notices: Notices,
        dispatch: Callable[[Message], None],
        shown: Callable[[], tuple[LabState, Snapshot | None]],
        closed: Callable[[], bool],
    ) -> None:
        self.client, self.catalog, self.symbolic = client, catalog, symbolic
        self.recorder, self.following, self.notices = recorder, following, notices
        self._dispatch, self._shown, self._closed = dispatch, shown, closed

    def run(self, state: LabState, command: Command) -> Action | Redraw | None:
        """Carry out ``command`` on ``state`` (the state reduced so far in this batch)."""
        if isinstance(command, ChooseRobot):
            if command.name == state.robot_name:
                return None
            return SetRobot(command.name, self.catalog.load(command.name))
        if isinstance(command, ChooseChain):
            chains = self.catalog.chains(state.robot_name)
            default = next((c.tip_link for c in chains if c.is_default), "")
            if command.tip_link == (state.chain or default):
                return None
            robot = self.catalog.load_chain(state.robot_name, command.tip_link)
            return SetRobot(state.robot_name, robot, chain=command.tip_link)
        if isinstance(command, UploadRobot):
            name = self.catalog.add_upload(command.filename, command.content, command.refused_size)
            return SetRobot(name, self.catalog.load(name))
        if isinstance(command, RequestDownload):
            self._download(state, command.label)
        elif isinstance(command, (ClaimPresenter, StopPresenting, ExploreAlone, FollowPresenter)):
            self.following.command(command)
        elif isinstance(command, ToggleRecording):
            self._toggle_recording(state)
            return Redraw()  # the record button says what a click does next
        elif isinstance(command, FindSingularity):
            self._find_singularity(state)
            return Wait(LOOKING)
        else:
            raise ValueError(f"{type(command).__name__} is drawn by the session, not run as a command")
        return None

    # ------------------------------------------------------------------ the nearest singularity
    def _find_singularity(self, state: LabState) -> None:
        """Descend to the nearest singularity away from the drawing thread, then play the descent."""
        robot, q = state.robot, np.array(state.q)

        def done(future: Future[FollowPath]) -> None:
            if self._closed() or self._shown()[0].robot is not robot:
                return
            try:
                self._dispatch(future.result())
            except Exception as exc:
                self.notices.error(exc)

        background().submit(nearest_path, robot, q).add_done_callback(done)

    # ------------------------------------------------------------------ recording
    def _toggle_recording(self, state: LabState) -> None:
        """Start recording this tab, or stop and send the demo (built away from the drawing thread)."""
        if not self.recorder.recording:
            self.recorder.start(state, self._shown()[1])
            return
        frames = self.recorder.stop()
        if len(frames) < 2:
            self.notices.notify(
                "Nothing recorded", "Move something between starting and stopping the recording."
            )
            return
        title = f"{state.robot.title or state.robot.name} — recorded in Jacobian Lab"
        remove_note = self.notices.preparing("Preparing the demo…", f"{len(frames)} frames")

        def done(future: Future[bytes]) -> None:
            remove_note()
            if self._closed():
                return
            try:
                self.client.send_file_download(
                    "jacobian-lab-demo.zip", future.result(), save_immediately=True
                )
            except Exception as exc:
                self.notices.error(exc)

        background().submit(demo_zip, frames, title).add_done_callback(done)

    # ------------------------------------------------------------------ downloads
    def _download(self, state: LabState, label: str) -> None:
        robot, frame = state.robot, state.options.jacobian_frame
        file = robot_file(robot, label)  # the robot itself (robot file, URDF); else its symbolic J
        if file is not None:
            self.client.send_file_download(*file, save_immediately=True)
            return
        remove_note = self.notices.preparing(
            f"Preparing J(q) as {label}…", f"{robot.title or robot.name}, {frame} axes"
        )

        def ready(future: Future[tuple[str, bytes]]) -> None:
            remove_note()
            if self._closed():
                return
            try:
                filename, content = future.result()
            except SymbolicUnavailable as exc:
                self.notices.notify("Download not available", str(exc))
            except Exception as exc:
                self.notices.error(exc)
            else:
                self.client.send_file_download(filename, content, save_immediately=True)

        self.symbolic.export(robot, label, frame).add_done_callback(ready)
