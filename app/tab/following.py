"""One tab in the classroom: its role, its classroom commands, and what a follower may not do.

:class:`Following` is the tab's :class:`~app.services.classroom.Member`: the server's
:class:`~app.services.classroom.Classroom` tells it the tab's :class:`~app.core.role.Role`
(:meth:`Following.role_changed`), hands it the presenter's state to draw (:meth:`Following.mirror`,
queued as a :class:`~app.core.commands.Mirror`) and the presenter's camera
(:meth:`Following.mirror_camera`), and reads what the tab shows while it presents. A follower's own
inputs are read-only (:meth:`Following.refuses`, with a reminder now and then) except the classroom
commands, a download and a recording. A typed presenter token is tried once the typing pauses
(:data:`TOKEN_PAUSE`), so a browser that sends every keystroke does not use up the tab's tries.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from ..core import questions
from ..core.actions import Play, Step
from ..core.commands import (
    CLASSROOM,
    AnswerHandover,
    AnswerRoom,
    AskRoom,
    ClaimPresenter,
    EndQuestion,
    ExploreAlone,
    FollowPresenter,
    LabelsPlaced,
    Message,
    Mirror,
    OpenTab,
    PageReport,
    QuestionShown,
    Redraw,
    RequestDownload,
    StopPresenting,
    ToggleRecording,
)
from ..core.poll import Seen
from ..core.role import Role
from ..core.snapshot import Snapshot, compute
from ..core.state import LabState
from ..services.background import background
from ..services.classroom import TOO_MANY_TRIES, WAITING, Classroom
from ..services.question_desk import NOT_PRESENTING
from ..services.scene_slot import SceneSlot
from .camera import TabCamera
from .notices import Notices

__all__ = ["Following", "TOKEN_PAUSE", "READ_ONLY_EVERY"]

TOKEN_PAUSE = 0.6
"""A typed presenter token is tried once the typing has paused this long [s]."""
READ_ONLY_EVERY = 5.0
"""A follower that moves an input is reminded at most this often [s] that its inputs follow."""
_ALWAYS = (*CLASSROOM, RequestDownload, ToggleRecording, PageReport)
"""What a follower may still send."""


class Following:
    """The classroom side of one tab.

    Args:
        key: The tab's client id (its key in the classroom).
        classroom: The server's classroom (``None``: no presenter mode).
        dispatch: The session's way in (a settled token, a redraw when the role changes).
        notices: The tab's notices.
        stop_ticker: Stops the tab's clock (a follower moves with the presenter's).
        camera: The tab's camera (a follower looks where the presenter looks).
        subscribe: The session's ``subscribe`` (the classroom relays the presenter's commits).
        shown: The state and snapshot on screen.
        scene_messages: The scene messages of the tab's last draw.
    """

    def __init__(
        self,
        key: int,
        classroom: Classroom | None,
        dispatch: Callable[[Message], None],
        notices: Notices,
        stop_ticker: Callable[[], None],
        camera: TabCamera,
        subscribe: Callable[[Callable[[LabState, Snapshot], None]], Callable[[], None]],
        shown: Callable[[], tuple[LabState, Snapshot | None]],
        scene_messages: Callable[[], tuple],
    ) -> None:
        self.key = key
        self.classroom = classroom
        self.role = Role()
        self._dispatch = dispatch
        self._notices = notices
        self._stop_ticker = stop_ticker
        self._camera = camera
        self.subscribe = subscribe
        self._shown, self._scene_messages = shown, scene_messages
        self._closed = False
        self._told_read_only = 0.0
        self._typed_token = ""
        self._token_timer: threading.Timer | None = None
        self.page: Any = None  # the tab's PageLink (app.tab.page), set by the session
        self.labels: Any = None  # the tab's TabLabels (app.tab.labels), set by the session
        self.rider: Any = None  # the session, when followers' frames may be shared (ride_key, leads)

    @property
    def following(self) -> bool:
        return self.role.following

    def refuses(self, message: Message) -> bool:
        """Whether ``message`` is an input a follower may not make (it is told so, now and then)."""
        if not self.role.following or isinstance(message, _ALWAYS):
            return False
        now = time.monotonic()
        if not isinstance(message, Step) and now - self._told_read_only >= READ_ONLY_EVERY:
            self._told_read_only = now
            _ = self._notices.tr.gettext
            self._notices.notify(
                _("You follow the presenter"),
                _("Your inputs follow the presenter: press “{button}” first.").format(
                    button=_("Explore on my own")
                ),
            )
        return True

    # ------------------------------------------------------------------ what the classroom asks
    @property
    def latest(self) -> tuple[LabState, Snapshot | None]:
        """The state and snapshot on screen."""
        return self._shown()

    @property
    def scene_messages(self) -> tuple:
        """The scene messages of this tab's last redraw (collected only while it presents)."""
        return self._scene_messages()

    def mirror(self, state: LabState, snapshot: Snapshot, scene: tuple = (), shared: object = None) -> None:
        """Draw the presenter's state (queued like any message; the latest of a burst wins; the scene
        messages of every one are replayed, in order; ``shared``: the worker's slot for a relayed state's
        scene)."""
        rider = self.rider
        if isinstance(shared, SceneSlot) and rider is not None:
            key = rider.ride_key()
            if key is not None and not shared.join(key, (rider, Mirror(state, snapshot, scene, shared))):
                return  # another follower showing the same draws it; its frame is sent to this tab too
            if key is not None:
                rider.leads(shared, key)
        self._dispatch(Mirror(state, snapshot, scene, shared))

    def mirror_camera(self, position: tuple, look_at: tuple, up: tuple) -> None:
        """Look where the presenter looks."""
        if not self._closed and self.role.following:
            self._camera.look(position, look_at, up)

    def mirror_labels(self, placed: Any) -> None:
        """The tab whose drawing we replay placed its labels again: ours move alike."""
        if not self._closed and self.role.following and self.labels is not None:
            if not self.labels.replay(placed):  # its drawing not on screen yet: after it, in order
                self._dispatch(LabelsPlaced(placed))

    def labels_placed(self, placed: Any) -> None:
        """Our labels were placed again, in a drawing other tabs replay: theirs move alike."""
        if self.classroom is not None:
            self.classroom.labels(self.key, placed)

    def mirror_tab(self, label: str) -> None:
        """Open the tab the presenter has open (queued: the session fills it, then opens it)."""
        if not self._closed and self.role.following:
            self._dispatch(OpenTab(label))

    # ------------------------------------------------------------------ the page (app.tab.page)
    def resume(self, key: str) -> bool:
        """The page came back with a presenter's reconnect key: present again (with the state shown
        before) if the classroom takes it; True when it did."""
        if self.classroom is None or self.classroom.resume(self.key, key) is False:
            if self.page is not None:
                self.page.remember("")  # stale: forget it
            return False
        if self.page is not None:
            self.page.remember(key)
        return True

    def tab_opened(self, label: str) -> None:
        """The user opened tab ``label``: a presenter's followers open it too."""
        if self.classroom is not None and self.role.presenting:
            self.classroom.tab(self.key, label)

    def role_changed(self, role: Role) -> None:
        """The classroom says what this tab now is (redrawn on the renderer's next visit)."""
        before = self.role
        self.role = role = replace(role, question=before.question)
        if role.note:
            _ = self._notices.tr.gettext
            self._notices.notify(_("Classroom"), _(role.note))
        if role.following and not before.following:
            self._stop_ticker()
        if role.presenting and not before.presenting and self.classroom is not None and self.page is not None:
            # Presenting now (its token, its reconnect key, or a hand-over it asked for): the page keeps
            # the reconnect key, and the followers open the tab it has open.
            self.page.remember(self.classroom.resume_key(self.key))
            if self.page.tab:
                self.classroom.tab(self.key, self.page.tab)
        self._dispatch(Redraw())

    def question_changed(self, seen: Seen | None) -> None:
        """The room's question as this tab shows it changed: its box is updated; the whole tab is drawn
        again when what the screens hide until the reveal changed (a new question, its reveal)."""
        before = self.role.question
        self.role = replace(self.role, question=seen)
        whole = (before.masks, before.number) if before else None, (seen.masks, seen.number) if seen else None
        self._dispatch(Redraw() if whole[0] != whole[1] else QuestionShown())

    # ------------------------------------------------------------------ the tab's commands
    def command(self, command: Any, state: LabState | None = None) -> None:
        """Carry out a classroom command (:data:`app.core.commands.CLASSROOM`; ``state``: the tab's, with
        the messages taken before this one in the same batch)."""
        if self.classroom is None:
            raise ValueError(
                "this server has no presenter mode (start it with --presenter or --presenter-token)"
            )
        if isinstance(command, (AskRoom, AnswerRoom, EndQuestion)):
            self._question(command, state)
        elif isinstance(command, ClaimPresenter):
            self._claim(command)
        elif isinstance(command, StopPresenting):
            self.classroom.resign(self.key)
            if self.page is not None:
                self.page.remember("")
        elif isinstance(command, ExploreAlone):
            self.classroom.explore_alone(self.key)
        elif isinstance(command, FollowPresenter):
            self.classroom.follow(self.key)
        elif isinstance(command, AnswerHandover):  # the classroom ignores it unless this tab presents
            self.classroom.answer(self.key, command.accept)

    def _question(self, command: AskRoom | AnswerRoom | EndQuestion, now: LabState | None) -> None:
        """Ask the room (the question made away from the drawing thread), answer, close or reveal."""
        assert self.classroom is not None
        desk, tr = self.classroom.questions, self._notices.tr
        if isinstance(command, AnswerRoom):
            why = desk.answer(self.key, command.number, command.value, tr)
        elif isinstance(command, EndQuestion):
            why = desk.end(self.key, command.reveal)
            asked = desk.round.question if desk.round is not None else None
            if not why and command.reveal and asked is not None and asked.kind == "blowup":
                self._dispatch(Play(True, "resolved_rate"))  # the picture settles it: the motion runs
            why = tr.gettext(why) if why else ""
        elif not self.role.presenting:
            why = tr.gettext(NOT_PRESENTING)
        else:
            shown, snap = self._shown()
            state = now or shown
            view = self._camera.view()
            sight = None if view is None else view.look_at - view.position
            job = background().submit(
                _make, command, state, snap if state is shown else None, desk.next_number, sight
            )
            job.add_done_callback(lambda done: self._asked(done.result, desk))
            return
        if why:
            self._notices.notify(tr.gettext("Question"), why, seconds=6.0)

    def _asked(self, result: Callable[[], questions.Question], desk: Any) -> None:
        """The question is made: the room is asked (or the presenter told why not)."""
        tr = self._notices.tr
        try:
            why = desk.ask(self.key, result())
        except questions.QuestionError as e:
            why = str(e)
        why = tr.gettext(why) if why else ""
        if why and not self._closed:
            self._notices.notify(tr.gettext("Question"), why, seconds=6.0)

    def _claim(self, command: ClaimPresenter) -> None:
        assert self.classroom is not None
        if not command.settled:  # wait until the typing pauses, then try the latest text once
            self._typed_token = command.token
            if self._token_timer is not None:
                self._token_timer.cancel()
            settled = ClaimPresenter(command.token, settled=True)
            self._token_timer = threading.Timer(TOKEN_PAUSE, self._dispatch, (settled,))
            self._token_timer.daemon = True
            self._token_timer.start()
            return
        if command.token != self._typed_token:
            return  # typing went on: a later try comes
        why = self.classroom.claim(self.key, command.token)
        if why == WAITING:
            return  # the classroom told the tab (a note with its role); its token box is hidden meanwhile
        if why:
            self._notices.notify(
                self._notices.tr.gettext("Not the presenter"), self._refusal(why), seconds=6.0
            )
        elif self.page is not None:  # the page keeps the reconnect key (never the token)
            self.page.remember(self.classroom.resume_key(self.key))
            if self.page.tab:
                self.classroom.tab(self.key, self.page.tab)

    def _refusal(self, why: str) -> str:
        """Why a claim was refused (the classroom's English), in the tab's language."""
        tr = self._notices.tr
        tries = self.classroom.wrong_tries(self.key) if self.classroom is not None else 0
        if why == TOO_MANY_TRIES.format(tries=tries):
            return tr.ngettext(
                "this tab has typed {tries} wrong token: reload the page to try again",
                "this tab has typed {tries} wrong tokens: reload the page to try again",
                tries,
            ).format(tries=tries)
        return tr.gettext(why)

    def camera_moved(self, camera: Any) -> None:
        """The presenter's camera moved: relay it to the followers."""
        if self.classroom is not None and self.role.presenting:
            pose = tuple(camera.position), tuple(camera.look_at), tuple(camera.up_direction)
            self.classroom.camera(self.key, *pose)

    def close(self) -> None:
        """The tab has gone: no token is tried any more."""
        self._closed = True
        if self._token_timer is not None:
            self._token_timer.cancel()


def _make(
    command: AskRoom, state: LabState, snap: Snapshot | None, seed: int, sight: object = None
) -> questions.Question:
    """The question ``command`` asks about ``state`` (its snapshot computed here when not given)."""
    snap = snap if snap is not None else compute(state)
    return questions.make(
        command.kind, state.robot, np.array(state.q), configuration=state.configuration, losses=snap.losses,
        twist=np.array(state.v_desired), frame=state.options.twist_frame, prompt=command.prompt,
        choices=command.choices, right=command.right, seed=seed, sight=sight,
    )  # fmt: skip
