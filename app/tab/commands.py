"""The command runner of one tab: it carries out what is not a change of state.

:meth:`CommandRunner.run` takes one :data:`~app.core.commands.Command` (told apart by type) and
returns what the session's loop does next: a reducible action (a loaded robot becomes
:class:`~app.core.actions.SetRobot`), :class:`~app.core.commands.Redraw` (the tab looks different
though its state did not change: a recording started), or ``None``. Slow work (the nearest
singularity, the IK solutions of a pose, a symbolic export, a demo zip) runs away from the drawing
thread and comes back as a dispatched action or a download. The runner touches no view: what it
changes is drawn by the session's next draw.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future
from typing import Any

import numpy as np

from ..core.actions import Action, SetRobot, Wait
from ..core.build_table import robot_file
from ..core.commands import (
    CLASSROOM,
    ChooseChain,
    ChooseRobot,
    Command,
    FindIkSolutions,
    FindSingularity,
    Message,
    Redraw,
    RequestDownload,
    ToggleRecording,
    UploadRobot,
)
from ..core.i18n import N_
from ..core.snapshot import Snapshot
from ..core.state import LabState
from ..services.background import background, ik_solutions, nearest_path
from ..services.symbolic_service import SymbolicService, SymbolicUnavailable
from ..views.panel.question import COUNTS, bar_words, question_words
from .following import Following
from .notices import Notices
from .recorder import TabRecorder, demo_zip
from .robots import TabCatalog, display_name
from .symbolic_words import told

__all__ = ["CommandRunner", "LOOKING", "MAX_QUEUED_DOWNLOADS"]

LOOKING = N_("looking for the nearest singularity…")
"""What the status says while the nearest singularity is looked for (in the state in English, like every
``stopped``; :func:`app.core.refusals.say` finds it in the catalogs)."""


MAX_QUEUED_DOWNLOADS = 4
"""Symbolic downloads one tab may have waiting behind the one being prepared."""


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
        self._jobs_lock = threading.Lock()
        self._upload_job = 0
        self._upload_future: Future[SetRobot] | None = None
        self._building = False
        self._downloads: deque[str] = deque()  # this tab's downloads waiting behind the one in flight
        self._download_busy = False

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
            self._upload(command)
            return None
        if isinstance(command, RequestDownload) and command.label == COUNTS:
            self._download_counts()
        elif isinstance(command, RequestDownload):
            self._download(state, command.label)
        elif isinstance(command, CLASSROOM):
            self.following.command(command, state)
        elif isinstance(command, ToggleRecording):
            self._toggle_recording(state)
            return Redraw()  # the record button says what a click does next
        elif isinstance(command, FindSingularity):
            self._find_singularity(state)
            return Wait(LOOKING)
        elif isinstance(command, FindIkSolutions):
            self._find_ik_solutions(state)
            return Wait("")  # the arm holds still: the solutions found belong to this pose
        else:
            raise ValueError(f"{type(command).__name__} is drawn by the session, not run as a command")
        return None

    # ------------------------------------------------------------------ uploads
    @property
    def building(self) -> bool:
        """Whether an uploaded robot is being read and built (the tab shows "Building…")."""
        with self._jobs_lock:
            return self._building

    def _upload(self, command: UploadRobot) -> None:
        """Read and build an uploaded robot away from the drawing thread (its cost grows with the file),
        one at a time per tab: a newer upload cancels the older (whose result is dropped)."""
        with self._jobs_lock:
            self._upload_job += 1
            self._building = True
            job, older = self._upload_job, self._upload_future
        if older is not None:  # outside the lock: cancelling runs its done callback here, which takes it
            older.cancel()
        shown = display_name(command.filename)
        _ = self.notices.tr.gettext
        remove_note = self.notices.preparing(_("Building…"), _("the robot of {file}").format(file=shown))

        def build() -> SetRobot:
            name = self.catalog.add_upload(command.filename, command.content, command.refused_size)
            return SetRobot(name, self.catalog.load(name))

        def done(future: Future[SetRobot]) -> None:
            remove_note()
            with self._jobs_lock:
                stale = job != self._upload_job
            try:
                if not (stale or future.cancelled() or self._closed()):
                    self._dispatch(future.result())
            except Exception as exc:
                self.notices.error(exc)
            finally:
                if not stale:
                    with self._jobs_lock:
                        self._building = False

        future = background().submit(build)
        with self._jobs_lock:
            self._upload_future = future
        future.add_done_callback(done)

    # ------------------------------------------------------------------ the nearest singularity
    def _find_singularity(self, state: LabState) -> None:
        """Descend to the nearest singularity away from the drawing thread, then play the descent."""
        self._search(state, nearest_path, state.robot, np.array(state.q))

    def _find_ik_solutions(self, state: LabState) -> None:
        """Search the IK solutions of the tool's pose away from the drawing thread, then show them."""
        self._search(state, ik_solutions, state.robot, state.robot_name, np.array(state.q))

    def _search(self, state: LabState, fn: Callable[..., Any], *args: Any) -> None:
        """Run ``fn(*args)`` in the background pool and dispatch the action it returns, unless the tab
        closed or shows another robot meanwhile (an error is said in the tab)."""
        robot = state.robot

        def done(future: Future[Any]) -> None:
            if self._closed() or self._shown()[0].robot is not robot:
                return
            try:
                self._dispatch(future.result())
            except Exception as exc:
                self.notices.error(exc)

        background().submit(fn, *args).add_done_callback(done)

    # ------------------------------------------------------------------ recording
    def _toggle_recording(self, state: LabState) -> None:
        """Start recording this tab, or stop and send the demo (built away from the drawing thread)."""
        if not self.recorder.recording:
            self.recorder.start(state, self._shown()[1])
            return
        frames = self.recorder.stop()
        if len(frames) < 2:
            _ = self.notices.tr.gettext
            self.notices.notify(
                _("Nothing recorded"), _("Move something between starting and stopping the recording.")
            )
            return
        title = self.notices.tr.gettext("{robot} — recorded in Jacobian Lab").format(
            robot=state.robot.title or state.robot.name
        )
        tr = self.notices.tr
        frames_text = tr.npgettext("recording", "{n} frame", "{n} frames", len(frames)).format(n=len(frames))
        remove_note = self.notices.preparing(tr.gettext("Preparing the demo…"), frames_text)

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

        background().submit(demo_zip, frames, title, self.notices.tr).add_done_callback(done)

    # ------------------------------------------------------------------ downloads
    def _download_counts(self) -> None:
        """The presenter's download of the room's counts (no names, no answers): CSV."""
        classroom = self.following.classroom
        if classroom is None:
            return
        tr = self.notices.tr
        text = classroom.questions.csv(
            self.following.key, lambda q: (question_words(q, tr), bar_words(q, tr))
        )
        if text is not None:
            self.client.send_file_download(COUNTS, text.encode("utf-8"), save_immediately=True)

    def _download(self, state: LabState, label: str) -> None:
        """Send the robot's file at once, or queue its symbolic J: one of this tab's exports is with the
        symbolic worker at a time, the others wait here (at most :data:`MAX_QUEUED_DOWNLOADS`), so one
        tab's downloads queue behind each other, not in front of other tabs'."""
        file = robot_file(state.robot, label)  # the robot itself (robot file, URDF); else its symbolic J
        if file is not None:
            self.client.send_file_download(*file, save_immediately=True)
            return
        with self._jobs_lock:
            if len(self._downloads) >= MAX_QUEUED_DOWNLOADS:
                waiting = len(self._downloads)
            else:
                self._downloads.append(label)
                waiting = 0
        if waiting:
            tr = self.notices.tr
            self.notices.notify(
                tr.gettext("Download not queued"),
                tr.ngettext(
                    "{n} download of this tab is waiting: try again once it is done.",
                    "{n} downloads of this tab are waiting: try again once they are done.",
                    waiting,
                ).format(n=waiting),
            )
            return
        self._next_download(state)

    def _next_download(self, state: LabState) -> None:
        with self._jobs_lock:
            if self._download_busy or not self._downloads:
                return
            self._download_busy = True
            label = self._downloads.popleft()
        robot, frame = state.robot, state.options.jacobian_frame
        _ = self.notices.tr.gettext
        remove_note = self.notices.preparing(
            _("Preparing J(q) as {format}…").format(format=label),
            (_("{robot}, base axes") if frame == "base" else _("{robot}, tool axes")).format(
                robot=robot.title or robot.name
            ),
        )

        def ready(future: Future[tuple[str, bytes]]) -> None:
            remove_note()
            with self._jobs_lock:
                self._download_busy = False
            if self._closed():
                return
            try:
                filename, content = future.result()
            except SymbolicUnavailable as exc:
                self.notices.notify(self.notices.tr.gettext("Download not available"), str(exc))
            except Exception as exc:
                words = told("download", exc, robot.dof, label, self.notices.tr)
                if words is not None:  # stopped at a limit of the server's, or not attempted
                    self.notices.notify(*words)
                else:
                    self.notices.error(exc)
            else:
                self.client.send_file_download(filename, content, save_immediately=True)
            self._next_download(state)

        try:
            self.symbolic.export(robot, label, frame).add_done_callback(ready)
        except Exception:
            with self._jobs_lock:
                self._download_busy = False
            remove_note()
            raise
