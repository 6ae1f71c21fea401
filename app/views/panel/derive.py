"""The Derive tab: the DH table, then the course's derivations walked through joint by joint.

The DH table always shows the current joint variables (θᵢ or dᵢ, in the joint's colour).
A dropdown picks what to walk through (:data:`kinematics.steps.METHODS`); a slider and
Previous/Next buttons pick the step (joint i); the step's numbers at q are shown with the
check against J, its vectors are drawn in the 3-D view (:mod:`app.views.scene.derive`) and, below,
the same step in symbols (:func:`kinematics.symbolic.derivation_steps`, typeset in the symbolic
worker process).
"""

from __future__ import annotations

from typing import Any

import viser

from kinematics import Robot

from ...core.actions import SetOption
from ...core.i18n import Translator, translations
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ..shared import once
from .common import Dispatch, bind, option_widget, show_option, sync_value
from .derive_html import dh_table_html, formulas_html, step_html

__all__ = ["DerivePanel"]


class DerivePanel:
    """The Derive tab's handles for one robot."""

    def __init__(
        self, gui: viser.GuiApi, dispatch: Dispatch, robot: Robot, order: float, tr: Translator | None = None
    ) -> None:
        self.robot = robot
        self.dispatch = dispatch
        self.tr = tr = tr or translations()
        _ = tr.gettext
        self._step = 0
        self._method = ""
        self.method = option_widget(gui, dispatch, "derive", order=order, tr=tr)
        self.step = gui.add_slider(
            _("Joint i"),
            min=1,
            max=max(robot.dof, 2),
            step=1,
            initial_value=1,
            order=order + 2,
            disabled=robot.dof < 2,
        )
        bind(self.step, dispatch, lambda v: SetOption("derive_step", int(round(v)) - 1))
        self._back = _("◀ Previous")
        self.buttons = gui.add_button_group(_("Step"), (self._back, _("Next ▶")), order=order + 3)
        self.buttons.on_click(self._clicked)
        self.body = gui.add_html("", order=order + 4)
        self.formula = gui.add_html("", order=order + 6, visible=False)
        self._formulas: tuple | None = None
        self._formula_note = ""
        self._walking = False
        self.table = gui.add_html("", order=order + 7)
        self._parts: list[Any] = [
            self.table,
            self.method,
            self.step,
            self.buttons,
            self.body,
            self.formula,
        ]

    def _clicked(self, event: viser.GuiEvent) -> None:
        delta = -1 if str(event.target.value) == self._back else 1
        self.dispatch(SetOption("derive_step", self._step + delta))

    @property
    def stepped(self) -> list[Any]:
        """Its sliders whose step the page honours."""
        return [self.step]

    def draw(self, state: LabState, snap: Snapshot) -> None:
        options = state.options
        self._step = options.derive_step
        self._method = options.derive
        walking = bool(options.derive)
        self.table.content = once(
            snap, dh_table_html, self.robot, snap.q, options.derive_step if walking else None, self.tr
        )
        show_option(self.method, "derive", options.derive, self.tr)
        top = max(self.robot.dof + (1 if options.derive == "dh" else 0), 2)  # DH: the tool frame's row
        if self.step.max != top:
            self.step.max = top
        sync_value(self.step, float(options.derive_step + 1))
        self.step.visible = self.buttons.visible = walking
        self.body.visible = walking
        if snap.derive is not None:
            self.body.content = once(snap, step_html, self.robot, snap.derive, snap, self.tr)
        self._walking = walking
        self._show_formula()

    def show_formulas(self, steps: tuple | None, note: str) -> None:
        """The steps of the derivation in symbols, (joint, key, caption HTML, MathML) each (from the
        symbolic worker), or ``None`` with a note while they are worked out or when they cannot be (the
        note in the tab's language when the catalogs have it: the waiting note; an error stays as it is)."""
        self._formulas, self._formula_note = steps, self.tr.gettext(note) if note else note
        self._show_formula()

    def _show_formula(self) -> None:
        self.formula.visible = self._walking
        if self._walking:
            self.formula.content = formulas_html(
                self._formulas,
                self._formula_note,
                self._method,
                self._step,
                self._step == self.robot.dof - 1,
                self.tr,
                tool=self._method == "dh" and self._step >= self.robot.dof,
            )

    def remove(self) -> None:
        for part in self._parts:
            part.remove()
