"""The Jacobian itself: the numeric J at the current q, measures, its symbolic form J(q), downloads,
and an enlarged projector view.

The numeric table has one coloured column per joint headed q1…qn (the
joint's own name on hover) and one row per twist component; rows outside
the robot's task are greyed. The enlarged view is a modal that stays live
and closes with Escape, its × or a click outside (see the page script).
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np
import viser

from kinematics import Robot

from ...core.actions import GoToRepresentationSingularity, SetOption
from ...core.commands import RequestDownload
from ...core.downloads import EXPORT_FORMATS
from ...core.i18n import Translator, translations
from ...core.robot_texts import robot_title
from ...core.snapshot import Snapshot
from ...core.state import LabState
from .. import fmt
from ..palette import joint_hex, joint_text_hex
from ..shared import once
from .common import Dispatch, bind_click, option_widget, show_option
from .course import analytic_html
from .readouts import ROW_NAMES, measures_html, status_html
from .style import CLOSE

__all__ = ["matrix_html", "MatrixPanel"]


def _head(robot: Robot) -> str:
    """The header cells of J's table: q1…qn in the joints' colours, each joint's name on hover."""
    return "".join(
        f'<th class="col" style="color:{joint_text_hex(i)};border-color:{joint_hex(i)}" '
        f'title="{fmt.escape(j.name)}">q{i + 1}</th>'
        for i, j in enumerate(robot.joints)
    )


def matrix_html(
    J: np.ndarray,
    robot: Robot,
    rows: tuple[int, ...],
    frame: str,
    big: bool = False,
    head: str = "",
    tr: Translator | None = None,
) -> str:
    """HTML table of J (6, n): coloured joint columns headed q1…qn, [v; ω] rows, non-task rows greyed.

    ``head``: the header cells as :func:`_head` writes them for ``robot`` (worked out when empty);
    ``tr``: the tab's language (its words and decimal mark).
    """
    tr = tr or translations()
    _ = tr.gettext
    head = head or _head(robot)
    values = fmt.cleaned(np.asarray(J, float).ravel().tolist())
    n = J.shape[1]
    body = []
    for r in range(6):
        classes = [c for c in ("off" if r not in rows else "", "split" if r == 3 else "") if c]
        cells = "".join([f"<td>{fmt.fixed(x, 3, tr)}</td>" for x in values[r * n : (r + 1) * n]])
        body.append(f'<tr class="{" ".join(classes)}"><th class="row">{ROW_NAMES[r]}</th>{cells}</tr>')
    words = (
        _(
            "J(q) in base axes, rows [v; ω], v = velocity of the tool point; v rows in m/rad (m/m for a "
            "prismatic joint), ω rows in rad/rad."
        )
        if frame == "base"
        else _(
            "J(q) in tool axes, rows [v; ω], v = velocity of the tool point; v rows in m/rad (m/m for a "
            "prismatic joint), ω rows in rad/rad."
        )
    )
    if len(rows) < 6:
        words += " " + _("Grey rows are outside the task.")
    caption = f'<div class="jl-note">{words}</div>'
    table = f'<table class="jl-matrix"><tr><th></th>{head}</tr>{"".join(body)}</table>'
    return f'<div class="jl{" jl-big" if big else ""}">{table}{caption}</div>'


def _mathml_html(inner: str, note: str = "") -> str:
    note_html = f'<div class="jl-note">{fmt.escape(note)}</div>'
    return f'<div class="jl"><div class="jl-mathml">{inner}</div>{note_html}</div>'


class MatrixPanel:
    """Numeric and symbolic J for one robot, measures, downloads and an enlarged view."""

    def __init__(
        self, gui: viser.GuiApi, dispatch: Dispatch, robot: Robot, order: float, tr: Translator | None = None
    ) -> None:
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self.gui = gui
        self.robot = robot
        self._modal: Any = None  # viser's modal handle (not exported by name)
        self._modal_html: viser.GuiHtmlHandle | None = None
        self._last = ""
        self._last_args: tuple = (np.zeros((6, robot.dof)), (), "base", "")
        self._lock = threading.RLock()
        self._symbolic = ""
        self._head = _head(robot)  # the same for every redraw of this robot
        self.root = gui.add_folder(None, order=order)
        with self.root:
            self.frame = option_widget(gui, dispatch, "jacobian_frame", tr=tr)
            self.representation = option_widget(gui, dispatch, "representation", tr=tr)
            self.numeric = gui.add_html("")
            self.analytic = gui.add_html("")
            # At a representation singularity: switch to the convention that is regular here.
            self._instead = ""
            self.use_instead = gui.add_button(
                _("Use the regular angles"), icon=viser.Icon.ARROWS_EXCHANGE, visible=False
            )
            bind_click(self.use_instead, dispatch, lambda: SetOption("representation", self._instead))
            self.go_singular: viser.GuiButtonHandle | None = None
            self._convention = "zyx"
            if robot.dof >= 6:
                self.go_singular = gui.add_button(
                    _("Go to a representation singularity"), icon=viser.Icon.TARGET
                )
                bind_click(
                    self.go_singular, dispatch, lambda: GoToRepresentationSingularity(self._convention)
                )
            enlarge = gui.add_button(_("Enlarge J (Esc closes)"), icon=viser.Icon.ARROWS_MAXIMIZE)
            enlarge.on_click(lambda _event: self.open_large())
            self.measures = gui.add_html("")
            with gui.add_folder(_("Symbolic J(q)"), expand_by_default=False):
                self.letters: viser.GuiCheckboxHandle | None = None
                if robot.dh is not None:
                    self.letters = option_widget(gui, dispatch, "course_letters", tr=tr)
                self.symbolic = gui.add_html(_mathml_html("", _("computing the symbolic form…")))
                self.download = gui.add_button_group(_("Download J(q)"), tuple(EXPORT_FORMATS))
                self.download.on_click(lambda event: dispatch(RequestDownload(event.target.value)))

    def draw(self, state: LabState, snap: Snapshot) -> None:
        frame = state.options.jacobian_frame
        self.show(frame)
        self.show_course(state, snap)
        status = once(snap, status_html, snap, state, self.tr)
        measures = once(snap, measures_html, snap, state.robot, self.tr)
        self.update(snap.J_shown, snap.rows, frame, status, measures, snap)

    def show(self, frame: str) -> None:
        show_option(self.frame, "jacobian_frame", frame, self.tr)

    def show_course(self, state: LabState, snap: Snapshot) -> None:
        """The representation chosen, φ, M(φ) and J_A (or why J_A does not exist), the letters box."""
        o = state.options
        show_option(self.representation, "representation", o.representation, self.tr)
        if o.representation != "geometric":
            self._convention = o.representation
        if self.letters is not None:
            show_option(self.letters, "course_letters", o.course_letters, self.tr)
        self.analytic.content = once(
            snap, analytic_html, snap.analytic, self.robot, snap.rank, snap.rows, self.tr
        )
        instead = snap.analytic.regular_instead if snap.analytic is not None else ""
        if instead:
            self._instead = instead
            _ = self.tr.gettext
            label = _("Use Euler ZYZ here") if instead == "zyz" else _("Use roll-pitch-yaw (ZYX) here")
            if self.use_instead.label != label:
                self.use_instead.label = label
        if self.use_instead.visible != bool(instead):
            self.use_instead.visible = bool(instead)

    def update(
        self,
        J: np.ndarray,
        rows: tuple[int, ...],
        frame: str,
        status: str,
        measures: str,
        snap: object = None,
    ) -> None:
        """Show the numeric J and measures, and in the enlarged view (if open) J under the status
        (``snap``: the snapshot J comes from, whose other viewers share the HTML)."""
        self.numeric.content = (
            once(snap, matrix_html, J, self.robot, rows, frame, head=self._head, tr=self.tr)
            if snap is not None
            else matrix_html(J, self.robot, rows, frame, head=self._head, tr=self.tr)
        )
        self.measures.content = measures
        with self._lock:
            self._last_args = (J, rows, frame, status)
            if self._modal_html is not None:
                self._modal_html.content = self._big()

    def _big(self) -> str:
        J, rows, frame, status = self._last_args
        self._last = status + matrix_html(J, self.robot, rows, frame, big=True, head=self._head, tr=self.tr)
        symbolic = f'<div class="jl jl-big">{self._symbolic}</div>' if self._symbolic else ""
        title, word = fmt.escape(self.tr.gettext("Close (Esc)")), fmt.escape(self.tr.gettext("close"))
        close = (
            f'<div class="jl-close-row"><button class="jl-close-x" title="{title}">× {word}</button></div>'
        )
        return close + self._last + symbolic

    def show_symbolic(self, mathml: str | None, note: str) -> None:
        """Show the symbolic J(q) (``None``: only the note), here and in the enlarged view."""
        self.symbolic.content = _mathml_html(mathml or "", note)
        with self._lock:
            self._symbolic = _mathml_html(mathml, note) if mathml else ""
            if self._modal_html is not None:
                self._modal_html.content = self._big()

    @property
    def enlarged(self) -> bool:
        """Whether the enlarged view is open."""
        return self._modal is not None

    def open_large(self) -> None:
        """Open the projector view of J (a wide modal, updated live)."""
        with self._lock:
            if self._modal is None:
                self._open()

    def _open(self) -> None:
        title = self.tr.gettext("Jacobian J(q) of the {robot}").format(robot=robot_title(self.robot, self.tr))
        with self.gui.add_modal(title) as modal:
            self._modal = modal
            self._modal_html = self.gui.add_html(self._big())
            close = self.gui.add_button(self.tr.gettext(CLOSE), icon=viser.Icon.X)
            close.on_click(lambda _event: self.close_large())

    def close_large(self) -> None:
        """Close the enlarged view (no-op when closed)."""
        with self._lock:
            if self._modal is not None:
                self._modal.close()
            self._modal = None
            self._modal_html = None

    def remove(self) -> None:
        self.close_large()
        self.root.remove()
