"""The GUI of one tab: robot choice, status, joints, and one tab per view of J.

Layout (one panel, docked right, so the 3-D view keeps most of the window):
the robot dropdown, the Configuration menu (above the status: a singularity's
description must not push it below the fold), the status banner (with the
visited configuration's description and the lost direction in words), the
joint sliders, then tabs
for J(q) (numeric J, measures, symbolic J and downloads), v = J q̇,
q̇ = J⁺ v, τ = Jᵀ F and the View options. The joint sliders stay visible
whichever tab is open, so a student moves a joint while watching any view.

Views never hold the session: they get ``dispatch`` and turn user input
into actions. :meth:`PanelView.draw` puts a state and its snapshot on
screen.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from typing import Any

import viser

import robots
from kinematics import Robot
from kinematics.urdf import ChainInfo

from ...core.commands import (
    ChooseChain,
    ChooseLanguage,
    ChooseRobot,
    Message,
    PageReport,
    ResetView,
    ToggleRecording,
)
from ...core.i18n import LANGUAGES, N_, Translator, translations
from ...core.options import options_of
from ...core.robot_menu import robot_menu
from ...core.role import Role
from ...core.snapshot import Snapshot
from ...core.state import LabState, Options
from ...viser_adapter import handle_uuid, run_javascript, set_page_title
from .. import fmt
from ..shared import once
from .classroom import ClassroomPanel, classroom_words_js, token_js
from .common import Dispatch, Tab, TabContext, TabView, bind, option_widget, show_option, sync_value
from .derive import DerivePanel
from .editor import EditorPanel, library_dh_robots
from .hint import hint_html
from .joints import JointsPanel, configurations_html
from .layout import LAYOUT_CSS, LAYOUT_JS, PANEL_WIDTH
from .live import live_html, shows_motion
from .mappings import ForcePanel, ForwardPanel, InversePanel
from .maps import MapsPanel, slider_ids
from .matrix import MatrixPanel
from .motion import MotionPanel
from .page import LOST_WORDS
from .page import page_js as page_state_js
from .question import HIDDEN_WORDS, HIDES_STATUS, QuestionPanel
from .readouts import source_html, status_html, status_lines
from .style import BASE_CSS, PAGE_TITLE, page_js, status_css, steps_js
from .typed import number_guard_js
from .viewport import PHONE_CSS

__all__ = ["PanelView", "PANEL_WIDTH", "TAB_LABELS"]


_LEGEND = N_(
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
        tr: Translator | None = None,
        report: bool = True,
    ):
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.gui = gui = client.gui
        self.client = client
        self.dispatch = dispatch
        gui.configure_theme(control_width="large", show_share_button=False, brand_color=(59, 91, 219))
        gui.set_panel_label("Jacobian Lab")
        gui.main_panel.dock_right()
        gui.main_panel.set_width(PANEL_WIDTH)
        more = _("▾ more below: scroll").replace("\\", "\\\\").replace('"', '\\"').replace("<", "\\3C ")
        more_css = f'.jl-more::after {{ content: "{more}"; }}'  # the band's words, in the tab's language
        gui.add_html(BASE_CSS + LAYOUT_CSS + PHONE_CSS + f"<style>{status_css()}{more_css}</style>", order=0)
        run_javascript(client, page_js())
        run_javascript(client, classroom_words_js() + LAYOUT_JS)
        run_javascript(client, number_guard_js(tr))
        # The page's channel back (its address, a presenter's reconnect key, the open tab): a text
        # input the page script hides and fills (app.views.panel.page).
        self.report = gui.add_text("page", "", order=10_000)
        bind(self.report, dispatch, lambda v: PageReport(str(v)) if str(v) else None)
        run_javascript(client, page_state_js(handle_uuid(self.report), _(LOST_WORDS), report))
        set_page_title(client, PAGE_TITLE)
        self.menu = robot_menu(robot_names, tr.code)
        self._menu_names = tuple(robot_names)
        self.robot = gui.add_dropdown(
            _("Robot"), self.menu.labels, initial_value=self.menu.label_of(state.robot_name), order=1
        )
        bind(self.robot, dispatch, self._chosen_robot)
        self.chain: viser.GuiDropdownHandle | None = None
        self.source = gui.add_html("", order=1.5, visible=False)
        self.status = gui.add_html("", order=2)
        self.live = gui.add_html("", order=2.5, visible=False)  # the motion's rates and κ, as numbers
        self.hint = gui.add_html("", order=2.6, visible=False)  # what to do first, over the 3-D view
        self.classroom = ClassroomPanel(gui, dispatch, order=0.5, tr=tr) if classroom else None
        self.question = QuestionPanel(gui, dispatch, tr, self._apply_shown_preset) if classroom else None
        if self.classroom is not None:  # masked, and filled from the presenter link
            run_javascript(client, token_js(handle_uuid(self.classroom.token)))
        # The views of J live in a second panel docked under the joints: both stay in sight.
        self.views = gui.add_panel()
        self.tabs = {tab.name: self.views.add_tab(_(tab.label), tab.icon) for tab in TABS}
        self.views.dock_below(gui.main_panel)
        with self.tabs["about"]:
            self.language = gui.add_dropdown(
                _("Language"), tuple(lang.name for lang in LANGUAGES), initial_value=tr.language.name
            )
            names = {lang.name: lang.code for lang in LANGUAGES}
            bind(self.language, dispatch, lambda v: ChooseLanguage(names[v]) if v in names else None)
            self.reset_view = gui.add_button(_("Reset view: frame the arm"), icon=viser.Icon.FOCUS_CENTERED)
            self.reset_view.on_click(lambda _: dispatch(ResetView()))
            self.toggles = {}
            for row in options_of("view"):
                if row.kind == "bool":
                    self.toggles[row.name] = option_widget(
                        gui, dispatch, row.name, getattr(state.options, row.name), tr
                    )
            self.scale = option_widget(gui, dispatch, "scale", state.options.scale, tr)
            gui.add_markdown(_(_LEGEND))
            self.record = gui.add_button(_("Record a demo"), icon=viser.Icon.PLAYER_RECORD)
            self.record.on_click(lambda event: dispatch(ToggleRecording()))
            note = _(
                "Records the 3-D view until you press again, then downloads it as a folder (zip) that plays "
                "from any web server, with no Python behind it."
            )
            gui.add_html(f'<div class="jl-note">{fmt.escape(note)}</div>')
        with self.tabs["build"]:
            self.editor = EditorPanel(gui, dispatch, library_dh_robots(), order=100, tr=tr)
        self.joints: JointsPanel | None = None
        self.parts: dict[str, TabView] = {}
        """The tabs' views for the current robot, by tab name (also ``panel.<name>``)."""
        self.open_tab = ""
        """The label of the tab the page has open, as it reported ("": not known, every tab is drawn).
        A redraw fills only that tab's readouts (and the tabs whose buttons keep what they show);
        the session redraws when the page reports another tab opened."""

    @property
    def open_name(self) -> str:
        """The name of the tab the page has open ("derive", "maps" …; "" when not known)."""
        return next((name for name, label in _LABELS.items() if label == self.open_tab), "")

    def __getattr__(self, name: str) -> Any:
        """``panel.matrix``, ``panel.derive`` …: the view of tab ``name`` (``None`` before a robot)."""
        if name in _TAB_NAMES:
            return self.__dict__.get("parts", {}).get(name)
        raise AttributeError(name)

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
            labels = {_chain_label(c, self.tr): c.tip_link for c in chains}
            self.chain = self.gui.add_dropdown(
                self.tr.gettext("Chain"),
                tuple(labels),
                initial_value=_chain_label(shown, self.tr) if shown else next(iter(labels)),
                order=1.2,
                hint=self.tr.gettext("The serial chain of the URDF shown: from its base link to a tip link."),
            )
            bind(self.chain, self.dispatch, lambda v: ChooseChain(labels[str(v)]) if v in labels else None)
        self.source.content = source_html(robot, shown, meshes)
        self.source.visible = bool(robot.urdf_path)
        self.joints = JointsPanel(self.gui, self.dispatch, robot, order=3, tr=self.tr, menu_order=1.3)
        context = TabContext(
            self.gui, self.dispatch, robot, rows, presets, slider_ids(self.joints.sliders), self.tr
        )
        for tab in TABS:
            if tab.build is not None:
                with self.tabs[tab.name]:
                    self.parts[tab.name] = tab.build(context)
        sliders = [*self.joints.sliders, self.scale]
        for part in self.parts.values():
            sliders += getattr(part, "stepped", ())
        run_javascript(self.client, steps_js({handle_uuid(s): float(s.step) for s in sliders}))

    def set_robot_names(self, names: Sequence[str]) -> None:
        """List ``names`` in the tab's robot dropdown (its own robots first, see app.tab.robots), each
        by its label (a library robot's title and name). The menu is worked out again only when the
        names changed (every redraw passes them; a label asks the library whether the name is its)."""
        if tuple(names) != self._menu_names:
            self.menu, self._menu_names = robot_menu(names, self.tr.code), tuple(names)
        if tuple(self.robot.options) != self.menu.labels:
            self.robot.options = self.menu.labels

    def _chosen_robot(self, value: Any) -> Message | None:
        name = self.menu.name_of(value)
        return None if name is None else ChooseRobot(name)

    def remove_robot(self) -> None:
        if self.chain is not None:
            self.chain.remove()
            self.chain = None
        for part in (self.joints, *self.parts.values()):
            if part is not None:
                part.remove()
        self.joints = None
        self.parts = {}

    def draw(self, state: LabState, snap: Snapshot, following: bool = False) -> None:
        """Put ``state`` on every input and ``snap`` on every readout (the session ignores echoes).
        ``following``: the tab follows a presenter, its buttons refused, so a closed Motion or Derive tab
        waits to be opened (or the tab to explore) to be drawn."""
        assert self.joints is not None
        always = () if following else _ALWAYS_DRAWN
        sync_value(self.robot, self.menu.label_of(state.robot_name))
        self.joints.show(state.q, state.configuration)
        self._show_options(state.options)
        self.status.content = once(snap, status_html, snap, state, self.tr)
        for name, part in self.parts.items():
            if not self.open_tab or name in always or _LABELS[name] == self.open_tab:
                part.draw(state, snap)
        live = self.live_content(state, snap)
        if live != self.live.content:
            self.live.content = live
        if self.live.visible != bool(live):
            self.live.visible = bool(live)
        hint = hint_html(state, self.tr)
        if hint != self.hint.content:
            self.hint.content = hint
        if self.hint.visible != bool(hint):
            self.hint.visible = bool(hint)

    def live_content(self, state: LabState, snap: Snapshot, role: Role | None = None) -> str:
        """The motion's readout over the 3-D view for ``state`` ("" when it is not shown: no motion on
        screen, or ``role``'s question hides it while the room answers)."""
        if role is not None and role.question is not None and role.question.masks in HIDES_STATUS:
            return ""
        lines = once(snap, status_lines, snap, state, self.tr) if shows_motion(state) else ""
        return live_html(state, self.tr, lines)

    def show_recording(self, recording: bool) -> None:
        """The record button says what a click does next."""
        _ = self.tr.gettext
        self.record.label = _("Stop and download the demo") if recording else _("Record a demo")
        self.record.color = "red" if recording else None

    def _apply_shown_preset(self) -> None:
        """The preset the Motion tab shows, applied (a question about its motion is about that one)."""
        motion = getattr(self, "parts", {}).get("motion")
        pending = getattr(motion, "pending", None)
        if motion is not None and pending is not None:
            motion.pending = None
            self.dispatch(pending)

    def show_role(self, role: Role) -> None:
        """The tab's classroom role (nothing without a presenter mode)."""
        if self.classroom is not None:
            self.classroom.show(role)
        if self.question is not None:
            self.question.show(role)
        masks = role.question.masks if role.question is not None else ""
        if masks in HIDES_STATUS:  # the room is answering: what would give the answer away waits
            hidden = self.tr.gettext(HIDDEN_WORDS)
            self.status.content = f'<div class="jl-note">{html.escape(hidden)}</div>'
            self.live.visible = False

    def _show_options(self, options: Options) -> None:
        for key, box in self.toggles.items():
            show_option(box, key, getattr(options, key), self.tr)
        show_option(self.scale, "scale", options.scale, self.tr)


class About:
    """The View tab's list of the robot's named configurations."""

    def __init__(self, c: TabContext) -> None:
        self.html = c.gui.add_html(configurations_html(c.robot, c.tr), order=200)

    @property
    def content(self) -> str:
        return str(self.html.content)

    def draw(self, state: LabState, snap: Snapshot) -> None:
        pass

    def remove(self) -> None:
        self.html.remove()


def _matrix(c: TabContext) -> MatrixPanel:
    c.gui.add_html('<div class="jl-views-marker"></div>', order=0)
    return MatrixPanel(c.gui, c.dispatch, c.robot, order=100, tr=c.tr)


TABS: tuple[Tab, ...] = (
    Tab("matrix", "J(q)", viser.Icon.MATH, _matrix),
    Tab(
        "forward",
        "v = J q̇",
        viser.Icon.ARROW_UP_RIGHT,
        lambda c: ForwardPanel(c.gui, c.dispatch, c.robot, 100, c.tr),
    ),
    Tab(
        "inverse",
        "q̇ = J⁺v",
        viser.Icon.ARROW_BACK_UP,
        lambda c: InversePanel(c.gui, c.dispatch, c.robot, c.rows, order=100, presets=c.presets, tr=c.tr),
    ),
    Tab("force", "τ = JᵀF", viser.Icon.WEIGHT, lambda c: ForcePanel(c.gui, c.dispatch, c.robot, 100, c.tr)),
    Tab(
        "motion",
        N_("Motion"),
        viser.Icon.PLAYER_PLAY,
        lambda c: MotionPanel(c.gui, c.dispatch, c.robot, c.presets, 100, c.tr),
    ),
    Tab(
        "maps",
        N_("Maps"),
        viser.Icon.MAP,
        lambda c: MapsPanel(c.gui, c.dispatch, c.robot, c.joint_sliders, 100, c.tr),
    ),
    Tab(
        "derive",
        N_("Derive"),
        viser.Icon.STAIRS,
        lambda c: DerivePanel(c.gui, c.dispatch, c.robot, order=100, tr=c.tr),
    ),
    Tab("about", N_("View"), viser.Icon.EYE, About),
    Tab("build", N_("Build"), viser.Icon.TOOL, None),
)

TAB_LABELS = tuple(tab.label for tab in TABS)
"""The tabs of the views of J, in order (the page keeps the open one in its address)."""
"""The panel's tabs, in the order they are shown. A tab is one module (its view) and one entry here;
its options are rows of :data:`app.core.options.OPTIONS`. The View tab ("about") also holds the
option table's glyph toggles and the Build tab the robot editor, both built once per tab."""
_TAB_NAMES = frozenset(tab.name for tab in TABS)
_LABELS = {tab.name: tab.label for tab in TABS}
_ALWAYS_DRAWN = frozenset({"motion", "derive"})
"""Tabs drawn even when not open: their buttons act on what their last draw kept (the preset a
click applies, the step a click moves from); not in a following tab, whose buttons are refused (a room
of followers would draw them hundreds of times a move for nobody)."""


def _chain_label(chain: ChainInfo, tr: Translator) -> str:
    joints = tr.ngettext("{n} joint", "{n} joints", chain.dof).format(n=chain.dof)
    return f"{chain.base_link} → {chain.tip_link} ({joints})"
