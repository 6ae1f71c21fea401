"""The Jacobian itself: the numeric J at the current q, its symbolic form J(q), downloads, a projector view.

The numeric table has one coloured column per joint (the joint's slider
colour) and one row per twist component; rows outside the robot's task are
greyed. The symbolic form arrives from :class:`~app.symbolic.SymbolicService`
in the background; until then (or if the symbolic module is missing) a note
says so.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import viser

from kinematics import Robot

from .. import fmt
from ..palette import joint_hex
from .readouts import ROW_NAMES

if TYPE_CHECKING:
    from ..session import ClientSession

__all__ = ["matrix_html", "MatrixPanel"]


def matrix_html(J: np.ndarray, robot: Robot, rows: tuple[int, ...], frame: str, big: bool = False) -> str:
    """HTML table of J (6, n): coloured joint columns, [v; ω] rows, non-task rows greyed."""
    head = "".join(
        f'<th class="col" style="color:{joint_hex(i)};border-color:{joint_hex(i)}">'
        f"{fmt.escape(j.name.split()[0])}</th>"
        for i, j in enumerate(robot.joints)
    )
    body = []
    for r in range(6):
        classes = [c for c in ("off" if r not in rows else "", "split" if r == 3 else "") if c]
        cells = "".join(f"<td>{fmt.fixed(x, 3)}</td>" for x in J[r])
        body.append(f'<tr class="{" ".join(classes)}"><th class="row">{ROW_NAMES[r]}</th>{cells}</tr>')
    where = "base" if frame == "base" else "tool"
    units = "v rows: m/rad (revolute), m/m (prismatic); ω rows: rad/rad."
    caption = (
        f'<div class="jl-note">J(q) in {where} axes, rows [v; ω], v = velocity of the tool point. {units}'
        + (" Grey rows are outside the task." if len(rows) < 6 else "")
        + "</div>"
    )
    table = f'<table class="jl-matrix"><tr><th></th>{head}</tr>{"".join(body)}</table>'
    return (
        f'<div class="jl{" jl-big" if big else ""}"><div class="jl-matrix-wrap">{table}</div>{caption}</div>'
    )


def _mathml_html(inner: str, note: str = "") -> str:
    return f'<div class="jl"><div class="jl-mathml">{inner}</div><div class="jl-note">{note}</div></div>'


class MatrixPanel:
    """Numeric and symbolic J for one robot, with downloads and an enlarged view."""

    def __init__(
        self, gui: viser.GuiApi, session: ClientSession, robot: Robot, order: float, symbolic_order: float
    ) -> None:
        self.gui = gui
        self.session = session
        self.robot = robot
        self._modal: viser.GuiModalHandle | None = None
        self._modal_html: viser.GuiHtmlHandle | None = None
        self._last: tuple = (np.zeros((6, robot.dof)), (), "base", "")
        self._symbolic = ""
        self.root = gui.add_folder(None, order=order)
        with self.root:
            self.numeric = gui.add_html("")
            enlarge = gui.add_button("Enlarge J for the projector", icon=viser.Icon.ARROWS_MAXIMIZE)
            session.on_click(enlarge, self.open_large)
        self.symbolic_root = gui.add_folder("Symbolic J(q)", order=symbolic_order)
        with self.symbolic_root:
            self.symbolic = gui.add_html(_mathml_html("", "computing the symbolic form…"))
            self.download = gui.add_button_group("Download J(q)", ("LaTeX", "Python", "JSON"))
            session.on_click_value(self.download, session.download)

    def update(self, J: np.ndarray, rows: tuple[int, ...], frame: str, status: str) -> None:
        """Show the numeric J, and in the enlarged view (if open) J under the ``status`` banner."""
        self.numeric.content = matrix_html(J, self.robot, rows, frame)
        self._last = (J, rows, frame, status)
        if self._modal_html is not None:
            self._modal_html.content = self._big()

    def _big(self) -> str:
        J, rows, frame, status = self._last
        symbolic = f'<div class="jl jl-big">{self._symbolic}</div>' if self._symbolic else ""
        return status + matrix_html(J, self.robot, rows, frame, big=True) + symbolic

    def show_symbolic(self, mathml: str | None, note: str) -> None:
        """Show the symbolic J(q) (``None``: only the note), here and in the enlarged view."""
        self.symbolic.content = _mathml_html(mathml or "", note)
        self._symbolic = _mathml_html(mathml, note) if mathml else ""
        if self._modal_html is not None:
            self._modal_html.content = self._big()

    def open_large(self) -> None:
        """Open the projector view of the numeric J (a wide modal, updated live)."""
        if self._modal is not None:
            return
        with self.gui.add_modal(f"Jacobian J(q) of the {self.robot.title or self.robot.name}") as modal:
            self._modal = modal
            self._modal_html = self.gui.add_html(self._big())
            close = self.gui.add_button("Close", icon=viser.Icon.X)
            self.session.on_click(close, self.close_large)

    def close_large(self) -> None:
        if self._modal is not None:
            self._modal.close()
        self._modal = None
        self._modal_html = None

    def remove(self) -> None:
        self.close_large()
        self.root.remove()
        self.symbolic_root.remove()
