"""One browser tab as a loop: queue, visit, commit, close.

    view input ─► dispatch(message) ─► queue ─► visit: reduce(state, action) ─► state
                                                       └ commands.run(state, command)
                 commit: compute(state) ─► snapshot ─► views draw(state, snapshot) ─► effects

:meth:`ClientSession.dispatch` is the only way in (views, the :class:`~app.tab.ticker.Ticker`, the
classroom): it queues. The server's one :class:`~app.services.renderer.Renderer` thread visits tabs
in turn and takes all a tab queued into one :class:`~app.tab.batch.Batch` before drawing once (at
most :data:`MAX_REDRAWS_PER_SECOND`). Actions (:mod:`app.core.actions`) go to the pure reducer,
commands (:mod:`app.core.commands`) to the :class:`~app.tab.commands.CommandRunner`; no view is
touched until the draw (:class:`~app.tab.screen.Screen`). After the draw: the ticker, the symbolic
results wanted (:class:`~app.tab.symbols.TabSymbols`), the camera (:class:`~app.tab.camera.TabCamera`)
and the subscribers (the classroom, a recorder). An error in any message is shown to this tab only.
"""

from __future__ import annotations

import contextlib
import logging
import threading
from collections.abc import Callable

import viser

from ..core.actions import Action, Step
from ..core.build_table import BUILT_NAME
from ..core.commands import (
    ChooseLanguage,
    LabelsPlaced,
    Message,
    Mirror,
    OpenTab,
    PageReport,
    QuestionShown,
    Redraw,
    ResetView,
    SymbolicResult,
)
from ..core.i18n import DEFAULT, is_language, negotiate, translations
from ..core.role import Role
from ..core.snapshot import Snapshot, compute
from ..core.state import LabState
from ..services.catalog import RobotCatalog
from ..services.classroom import Classroom
from ..services.renderer import Renderer
from ..services.scene_slot import SceneSlot
from ..services.symbolic_service import SymbolicService
from ..views.panel import TAB_LABELS, PanelView
from ..views.scene import SceneView
from .batch import MAX_REDRAWS_PER_SECOND, Batch, Queued, VisitPace, coalesced
from .camera import TabCamera
from .commands import CommandRunner
from .following import Following
from .labels import TabLabels
from .notices import Notices
from .page import PageLink, address_language
from .recorder import TabRecorder
from .ride import Riding
from .robots import TabCatalog
from .screen import Screen
from .subscribers import Subscribers
from .symbols import TabSymbols
from .ticker import Ticker

__all__ = ["ClientSession", "MAX_REDRAWS_PER_SECOND"]

log = logging.getLogger(__name__)


class ClientSession(Riding, Queued):
    """State, views and effects of one connected tab: ``state`` (frozen :class:`~app.core.state.LabState`)
    is what it has chosen, ``snapshot`` what is on screen, ``redraws`` counts draws (one per batch)."""

    def __init__(
        self,
        client: viser.ClientHandle,
        catalog: RobotCatalog,
        symbolic: SymbolicService,
        robot_name: str,
        ticker: Ticker | None = None,
        renderer: Renderer | None = None,
        classroom: Classroom | None = None,
        language: str = "",
        accept_language: str = "",
        user_agent: str = "",
    ) -> None:
        self.client, self.key, self.symbolic = client, client.client_id, symbolic
        self.catalog = TabCatalog(catalog)  # the shared robots plus this tab's own (uploads, Build tab)
        self.lock = threading.RLock()
        self.redraws = 0
        self._queue: list[Message] = []
        self._queue_lock = threading.Lock()
        self._scheduled = self._closed = False
        self._own_renderer = renderer is None
        self.renderer = renderer if renderer is not None else Renderer()
        self._drawing = threading.local()
        self._tab_to_open = ""  # a panel tab to open in the page once drawn (OpenTab)
        self.pace = VisitPace()
        self.subscribers = Subscribers(self.key)
        self.notices = Notices(client, lambda: self._closed)
        self.ticker = ticker if ticker is not None else Ticker(self.dispatch)
        self.camera = TabCamera(client)
        self.following = Following(
            self.key, classroom, self.dispatch, self.notices, self.ticker.stop, self.camera,
            self.subscribe, lambda: self.latest, lambda: self.screen.scene_messages,
        )  # fmt: skip
        self.page = PageLink(
            client, self.dispatch, self.catalog.names, self.catalog.load,
            lambda title, body: self.notices.notify(title, body), lambda: self._closed, self._page_languages,
        )  # fmt: skip
        # Its language: its own (address, menu) > the room's (--lang) > its browser's (handshake) > English.
        self.room_language = language if is_language(language) else ""
        self.browser_language = negotiate(accept_language, default="") if accept_language else ""
        self.language = self._wanted_language = self._decide_language()
        self.page.tr = self.notices.tr = translations(self.language)
        self.labels = TabLabels(
            client, self.camera, lambda: self.page.window, self.lock, lambda: getattr(self, "screen", None),
            lambda: self._closed, lambda placed: self.following.labels_placed(placed), user_agent=user_agent,
        )  # fmt: skip
        self.page.following, self.following.page = self.following, self.page
        self.following.rider = self  # a follower may be sent another's frame (ride_key, take_ride)
        self._leading: list[tuple[SceneSlot, tuple]] = []  # relayed states whose frame we draw for others
        self._ridden = None  # the frame of this visit's draw, for those that wait for it
        self.rides = 0  # frames taken from another follower's draw
        self.following.labels = self.labels
        self.symbols = TabSymbols(symbolic, self.dispatch, self.notices.notify, lambda: self.notices.tr)
        self.recorder = TabRecorder(self.subscribe)
        self.commands = CommandRunner(
            client, self.catalog, symbolic, self.recorder, self.following, self.notices,
            self.dispatch, lambda: self.latest, lambda: self._closed,
        )  # fmt: skip
        self.snapshot: Snapshot | None = None
        with self.lock:
            self.state = LabState.initial(robot_name, catalog.load(robot_name))
            first = compute(self.state)

            def arm_first(scene: SceneView) -> None:  # a phone's first picture: the arm before the panel
                scene.update(first, self.state)
                self.camera.after_commit(scene, self.state, self.state, True, True, first)

            self.screen = Screen(
                client, self.dispatch, self.catalog, self.state, classroom is not None, self.page.tr,
                self.camera.view, first=arm_first,
            )  # fmt: skip
            self.screen.layout, self.screen.canvas = self.labels.layout, self.labels.canvas
            self.camera.moved = self.labels.moved  # from the first frame on (placed before the panel)
            self._commit(self.state, rebuild=True, jump=True, snap=first)
        client.camera.on_update(self._camera_moved)

    # ------------------------------------------------------------------ queue
    def dispatch(self, message: Message) -> None:
        """Queue ``message`` (from a view, the ticker or the classroom); the renderer takes and draws it.

        Safe from any thread; returns at once. Echoes of the session's own redraw (inputs it sets)
        are ignored. :meth:`settle` waits until everything dispatched is on screen.
        """
        if getattr(self._drawing, "active", False) or self._closed:
            return
        with self._queue_lock:
            self._queue.append(message)
            if self._scheduled:
                return  # the renderer will take it with the others on its next visit
            self._scheduled = True
        self.renderer.schedule(self)

    def next_visit(self) -> float:
        """When this tab may be redrawn again [monotonic s] (:class:`~app.tab.batch.VisitPace`)."""
        return self.pace.next_visit()

    # ------------------------------------------------------------------ visit
    def visit(self) -> bool:
        """Take every queued message and redraw once (the renderer's thread); True when more arrived."""
        with self._queue_lock:
            messages, self._queue = coalesced(self._queue), []
            leading, self._leading = self._leading, []
        self.pace.start()
        try:
            self._visit(messages, leading)
        finally:
            self._send_rides(leading)
        self.pace.finish()
        with self._queue_lock:
            if self._queue and not self._closed:
                return True
            self._scheduled = False
            return False

    def _visit(self, messages: list[Message], leading: list[tuple[SceneSlot, tuple]]) -> None:
        if messages and not self._closed:
            with self.lock:
                batch = Batch(self.state)
                for message in messages:
                    try:
                        self._take(batch, message)
                    except Exception as exc:  # one tab's bad input never reaches the server or other tabs
                        self.notices.error(exc)
                try:
                    if batch.state is not self.state or batch.force:
                        snap, scene = batch.mirrored()
                        rebuild = batch.state.robot is not self.state.robot
                        lead = batch.lead if scene is None and snap is not None else None
                        shared = batch.mirror_shared() if snap is not None and not rebuild else None
                        ride = next((r for r in leading if r[0] is shared), None)
                        self._commit(batch.state, rebuild, batch.jump, snap, scene, lead, ride)
                    elif batch.symbolic or batch.question:
                        self.screen.draw_symbols(self.symbols, self.role if batch.question else None)
                    for placed in batch.placed:  # placed in the drawing now on screen: after it
                        self.labels.replay(placed)
                except Exception as exc:  # the tab keeps its last good state on screen
                    self.notices.error(exc)

    def _take(self, batch: Batch, message: Message) -> None:
        """Take one message into ``batch``: reduce an action, run a command, draw a mirror."""
        if isinstance(message, Mirror):
            if getattr(message.scene, "look", look := self.screen.look()) != look:  # other words, or
                message = Mirror(message.state, message.snapshot, shared=message.shared)  # another screen
            if message.state.robot is not self.state.robot:  # only then may it be unknown here
                self.catalog.keep_shown(message.state.robot_name, message.state.robot)
            batch.take_mirror(message, self.screen.scene is not None, look)
        elif isinstance(message, LabelsPlaced):
            batch.take_placed(message.placed)
        elif isinstance(message, Redraw):
            batch.force = True
        elif isinstance(message, QuestionShown):
            batch.question = True
        elif isinstance(message, SymbolicResult):
            batch.symbolic = self.symbols.take(message) or batch.symbolic
        elif isinstance(message, ChooseLanguage):  # the tab's own, a follower's too: never the state's
            if is_language(message.code):
                self.page.lang = message.code
                self._wanted_language = self._decide_language()
                batch.force = True
        elif isinstance(message, OpenTab):
            if message.label in TAB_LABELS and message.label != self.page.tab:
                self.page.tab = self._tab_to_open = message.label  # filled by this draw, opened in its frame
                batch.force = True
        elif self.following.refuses(message):
            batch.force = batch.force or not isinstance(message, Step)  # undo what the input shows
        elif isinstance(message, Action):
            batch.take(message)
        elif isinstance(message, ResetView):
            self.camera.reset(self.screen.scene, batch.state)
        elif isinstance(message, PageReport):
            shown, window = self.page.tab, self.page.window
            self.page.take(message.text)
            if self.page.window != window:
                self.labels.place()  # another canvas: the labels placed in it
                batch.force = batch.force or self.screen.own_scene is None  # replayed for another: our own
            if self.page.tab != shown or self._wanted_language != self.language:
                batch.force = True  # the tab opened is drawn with the state on screen
        else:
            result = self.commands.run(batch.state, message)
            if isinstance(result, Redraw):
                batch.force = True
            elif result is not None:
                batch.take(result)

    # ------------------------------------------------------------------ commit
    def _commit(
        self,
        state: LabState,
        rebuild: bool,
        jump: bool,
        snap: object = None,
        scene: list | None = None,
        lead: SceneSlot | None = None,
        ride: tuple[SceneSlot, tuple] | None = None,
    ) -> None:
        """Take ``state``: compute its snapshot once (unless given: the presenter's), draw in one
        batch, then run the effects. ``scene``: the presenter's scene messages to replay instead of
        drawing the scene (a follower's scene then shows the presenter's nodes); ``lead``: a relayed
        state's slot, filled with the scene messages of this drawing for the worker's other followers;
        ``ride``: a relayed state's slot and the key of the followers that wait for this whole frame
        (:meth:`ride_key`, checked again here), sent to them once drawn (:meth:`_send_rides`)."""
        old, following = self.state, self.following.following
        if not isinstance(snap, Snapshot):  # a forced redraw of the state shown (a role change) reuses it
            snap = self.snapshot if state is self.state and self.snapshot is not None else compute(state)
        if state.robot_name == BUILT_NAME and not following:
            self.catalog.remember_built(state.robot)  # the dropdown can go back to the Build tab's robot
        if self._wanted_language != self.language:  # the whole page again, in the tab's new language
            self.language = self._wanted_language
            self.page.tr = self.notices.tr = translations(self.language)
            self.screen.relanguage(self.page.tr, state)
            self._tab_to_open = self.page.tab  # the rebuilt panel opens on its first tab
            rebuild = True
        if ride is not None and (self._ride_parts() != ride[1] or not following):
            ride = None  # it changed since it joined: the others draw their own
        self.symbols.update(state, None if rebuild else old)  # what it shows is drawn below
        self.screen.panel.open_tab = self.page.tab  # only the open tab's readouts are filled
        riding = self._capture_ride(ride)
        atomic: contextlib.AbstractContextManager[object] = self.client.atomic()
        with riding as captured, atomic:  # the page's address, when due, rides in the redraw's frame
            self._drawing.active = True
            try:
                recording = self.recorder.recording
                same = state is old and scene is None and lead is None  # a forced redraw of what is shown
                self.screen.draw(
                    state, snap, rebuild, scene, self.role, recording, self.symbols, lead is not None, same
                )
            finally:
                self._drawing.active = False
            if self._tab_to_open:  # after its readouts, in the same frame: never shown stale
                self.page.show_tab(self._tab_to_open)
                self._tab_to_open = ""
            self.page.update(state)  # a reload or a server restart comes back to this robot and q
        if lead is not None and not rebuild:  # what our browser showed before is the others' base
            lead.fill(self.screen.scene_messages.look, old, self.screen.scene_messages)
        if ride is not None and isinstance(snap, Snapshot):
            self._keep_ride(ride, old, state, snap, captured)
        self.state, self.snapshot = state, snap
        self.redraws += 1
        self.pace.redrawn()
        if state.playing and not following:  # a follower moves with the presenter's clock
            self.ticker.start()
        else:
            self.ticker.stop()
        if not following:  # a follower's camera is the presenter's
            self.camera.after_commit(self.screen.scene, state, old, rebuild, jump, snap)
        self.subscribers.tell(state, snap)

    # ------------------------------------------------------------------ language
    def _decide_language(self) -> str:
        return self.page.lang or self.room_language or self.browser_language or DEFAULT

    def _page_languages(self, lang: str, browser: tuple[str, ...]) -> None:
        """The page (re)connected: the language its address asks for (``?lang=``), the browser's."""
        if browser and not self.browser_language:
            self.browser_language = negotiate(list(browser), default="")
        if lang:
            self.page.lang, unknown = address_language(lang)
            if unknown is not None:
                self.notices.notify(*unknown)
        self._wanted_language = self._decide_language()

    def subscribe(self, fn: Callable[[LabState, Snapshot], None]) -> Callable[[], None]:
        """Call ``fn(state, snapshot)`` after every commit (the classroom, a recorder); returns the undo."""
        return self.subscribers.add(fn)

    # ------------------------------------------------------------------ what the tab shows
    @property
    def panel(self) -> PanelView:
        return self.screen.panel

    @property
    def scene(self) -> SceneView | None:
        return self.screen.scene

    @property
    def role(self) -> Role:
        """The tab's classroom role."""
        return self.following.role

    @property
    def latest(self) -> tuple[LabState, Snapshot | None]:
        """The state and snapshot on screen."""
        return self.state, self.snapshot

    def _camera_moved(self, camera: viser.CameraHandle) -> None:
        """The presenter's camera is relayed; a reshaped canvas keeps everything in view."""
        try:
            self.following.camera_moved(camera)
            with self.lock:
                if not self._closed:
                    self.camera.canvas_moved(float(camera.aspect), self.screen.scene)
            self.labels.moved()
        except Exception as exc:
            self.notices.error(exc)

    # ------------------------------------------------------------------ close
    @property
    def closed(self) -> bool:
        """Whether the tab has gone (its session no longer draws)."""
        return self._closed

    @property
    def errors(self) -> int:
        """Number of errors shown to this tab."""
        return self.notices.errors

    def close(self) -> None:
        """Forget the tab (it has gone: its handles went with its connection). Stops its ticker."""
        self._closed = True
        self._let_go()  # those that wait for our frame draw their own
        self.following.close()
        self.ticker.close()
        if self._own_renderer:
            self.renderer.close()
        self.camera.close()
        self.labels.close()
        self.page.close()
        with self.lock:
            self.symbols.release()
            self.subscribers.clear()
