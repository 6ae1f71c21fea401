"""What one tab's browser shows: its panel and its scene, drawn together in one atomic batch.

:meth:`Screen.draw` puts a state and its snapshot on every view (the robot-dependent parts rebuilt
when the robot changed), with what the tab itself knows beside the state: its robot list, its
classroom role, whether it records, the symbolic results that arrived. A follower replays the
presenter's scene messages instead of drawing its own scene; a presenter's scene messages are
collected for the room.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from typing import TYPE_CHECKING

import viser

from kinematics.analysis import task_rows

from ..core.i18n import Translator, translations
from ..core.role import Role
from ..core.snapshot import Snapshot
from ..core.state import LabState
from ..views.camera import View
from ..views.panel import PanelView
from ..views.panel.common import Dispatch
from ..views.panel.hint import hint_html
from ..views.scene import SceneView
from ..views.scene.labels import Layout
from ..viser_adapter import capture_scene, replay_scene

if TYPE_CHECKING:
    from .robots import TabCatalog
    from .symbols import TabSymbols

__all__ = ["Screen", "SceneMessages"]


class SceneMessages(tuple):
    """A presenter's scene messages and the look they were drawn for (:meth:`Screen.look`: the language
    of their 3-D labels and the screen the labels were placed for): a follower whose look differs (it
    speaks another language, or a phone follows a projector) draws its own scene from the presenter's
    state instead of replaying them (the presenter shares state, not words nor label places)."""

    look: str = ""


class Screen:
    """The views of one tab.

    Args:
        client: The tab's viser client.
        dispatch: The session's way in (the views turn input into messages).
        catalog: The tab's robots (names, chains, meshes, presets of the robot shown).
        state: The first state (the panel's initial values).
        classroom: Whether the server has a presenter mode (the classroom controls are shown).
        tr: The tab's language.

    Attributes:
        panel: The GUI (:class:`~app.views.panel.PanelView`).
        scene: The 3-D view (:class:`~app.views.scene.SceneView`), once drawn.
        scene_messages: The scene messages of the last draw (collected only while presenting).
    """

    def __init__(
        self,
        client: viser.ClientHandle,
        dispatch: Dispatch,
        catalog: TabCatalog,
        state: LabState,
        classroom: bool,
        tr: Translator | None = None,
        view: Callable[[], View | None] = lambda: None,
        first: Callable[[SceneView], None] | None = None,
    ) -> None:
        self.client, self.dispatch, self.catalog, self.view = client, dispatch, catalog, view
        self.classroom, self.tr = classroom, tr or translations()
        self.scene: SceneView | None = None
        self._first: object = None  # the robot of the scene drawn before the panel (its first draw keeps it)
        if first is not None:  # the arm first, in a frame of its own: a phone draws it before the panel
            with client.atomic():
                self.scene = SceneView(client, state.robot, dispatch, tr=self.tr, view=view)
                first(self.scene)
            client.flush()
            self._first = state.robot
        self.panel = PanelView(client, dispatch, catalog.names(), state, classroom, self.tr)
        self.scene_messages = SceneMessages()
        self.shown, self.leads = state, False  # the state on screen; whether other tabs replay our scene
        self._foreign = False  # the browser shows the presenter's scene nodes, not our SceneView's
        self._foreign_look = ""  # the look they were drawn for (another one: we draw our own)
        self.layout: Callable[[], Layout | None] = lambda: None  # the labels' camera and canvas
        self.canvas: Callable[[], tuple | None] = lambda: None  # the labels' canvas alone (TabLabels.canvas)
        self.live = ""  # the motion's readout over the 3-D view as last drawn (its labels keep out of it)
        self.hint = ""  # the first hint over the 3-D view as last drawn (its labels keep out of it too)

    def draw(
        self,
        state: LabState,
        snap: Snapshot,
        rebuild: bool,
        replay: list | None,
        role: Role,
        recording: bool,
        symbols: TabSymbols,
        capture: bool = False,
        keep_scene: bool = False,
    ) -> None:
        """Draw ``state`` and ``snap`` (``replay``: the presenter's scene messages instead of our scene;
        ``capture``: keep our scene messages for others, as a presenter's are; ``keep_scene``: the state
        on screen drawn again for a role or question change: a follower showing the presenter's scene keeps
        it, the presenter's next frame brings what changes)."""
        capturing: contextlib.AbstractContextManager[list] = (
            capture_scene(self.client) if role.presenting or capture else contextlib.nullcontext([])
        )
        with self.client.atomic(), capturing as captured:
            self.live = self.panel.live_content(state, snap, role)  # before the labels are placed
            self.hint = hint_html(state, self.tr)
            if rebuild or self.scene is None:
                name, robot, catalog = state.robot_name, state.robot, self.catalog
                self.panel.build_robot(
                    robot, task_rows(robot), catalog.chains(name), state.chain,
                    catalog.meshes(name), catalog.presets(name),
                )  # fmt: skip
            look = self.look()  # the screen the scene is drawn (or replayed) for: live and hint are set
            if replay is not None and self.scene is not None:
                replay_scene(self.client, replay)  # the presenter's scene, drawn once for the room
                self._foreign = True  # our SceneView no longer knows what the browser shows
                self._foreign_look = look  # the screen its labels were placed for
            elif keep_scene and self._foreign and role.following and self._foreign_look == look:
                pass  # the state shown, drawn again for its panel: a follower's view stays the presenter's
            else:
                kept, self._first = state.robot is self._first, None
                if (rebuild and not kept) or self.scene is None or self._foreign:
                    if self.scene is not None:
                        self.scene.remove()
                    self.scene = SceneView(
                        self.client, state.robot, self.dispatch, tr=self.tr, view=self.view
                    )
                    self._foreign = False
                self.scene.open_tab = self.panel.open_name  # a tab's own glyphs only while it is open
                self.scene.layout = self.layout  # where its labels are seen
                self.scene.question = role.question
                self.scene.update(snap, state)
            self.panel.set_robot_names(self.catalog.names())
            self.panel.draw(state, snap, following=role.following)
            self.panel.show_role(role)
            self.panel.show_recording(recording)
            symbols.draw(self.panel, everything=rebuild)
        self.scene_messages = SceneMessages(captured)
        self.scene_messages.look = look
        self.shown, self.leads = state, bool(role.presenting or capture)

    def look(self) -> str:
        """What a drawing of the scene depends on besides the state: the tab's language and the screen its
        labels are placed for (the canvas and its visible part [CSS px]; the camera is the presenter's
        for every follower). Tabs of the same look can be sent the same scene messages."""
        canvas = self.canvas()
        if canvas is None:
            return self.tr.code
        width, height = canvas[0], canvas[1]
        return f"{self.tr.code} {width:.0f}x{height:.0f} 0,0,{width:.0f},{height:.0f}"

    @property
    def foreign(self) -> tuple[bool, str]:
        """Whether the browser shows scene nodes our SceneView did not draw, and the look they were for."""
        return self._foreign, self._foreign_look

    def rode(self, state: LabState, look: str, live: str, hint: str) -> None:
        """The browser was sent another follower's frame of ``state`` (drawn for ``look``): it shows that
        follower's scene nodes, not our SceneView's."""
        self._foreign, self._foreign_look = True, look
        self.scene_messages = SceneMessages()
        self.scene_messages.look = look
        self.shown, self.leads, self.live, self.hint = state, False, live, hint

    @property
    def own_scene(self) -> SceneView | None:
        """The scene this tab draws, None while the browser shows the presenter's nodes (a follower)."""
        return None if self._foreign else self.scene

    def relanguage(self, tr: Translator, state: LabState) -> None:
        """Speak ``tr``'s language: the whole panel is built again in it (its widgets' labels are set
        once), and the scene with the next draw (which must rebuild)."""
        self.tr = tr
        with self.client.atomic():
            self.client.gui.reset()
            if self.scene is not None:
                self.scene.remove()
                self.scene = None
            self.panel = PanelView(
                self.client, self.dispatch, self.catalog.names(), state, self.classroom, tr, report=False
            )

    def draw_symbols(self, symbols: TabSymbols, role: Role | None = None) -> None:
        """Put the symbolic results that arrived on the panel, and the room's question if ``role`` is
        given (nothing else changed)."""
        with self.client.atomic():
            symbols.draw(self.panel, everything=False)
            if role is not None:
                self.panel.show_role(role)
