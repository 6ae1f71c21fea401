"""Two of the course's motions in the Motion tab: the null joint motion at a singularity (Ker J), said in
words and played, and the Jacobian IK along a path y(t) (a line or a circle through the tool point).

At a singularity some joint rates move nothing at the tool (J q̇ = 0): the Puma's wrist at q₅ = 0
turns q₄ and q₆ against each other. The snapshot holds that motion (``snap.null``); this folder
says it and its button plays it back and forth (the arm moves, the tool stands still).
"""

from __future__ import annotations

import viser

from ...core.actions import FollowToolPath, PlayNullMotion
from ...core.i18n import N_, Translator
from ...core.self_motion import null_motion_text
from ...core.snapshot import Snapshot
from ...core.tool_path import SHAPES
from .. import fmt
from .common import Dispatch

__all__ = ["NullMotionPanel", "PathPanel", "CourseMotion"]


class NullMotionPanel:
    """The null-motion folder: its words and its Play button (disabled where J has full rank)."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator) -> None:
        self.tr = tr
        _ = tr.gettext
        with gui.add_folder(_("Null motion at a singularity (Ker J)"), expand_by_default=False):
            self.words = gui.add_html("")
            self.button = gui.add_button(
                _("Play the null motion"), icon=viser.Icon.PLAYER_PLAY, disabled=True
            )
            self.button.on_click(lambda _: dispatch(PlayNullMotion()))
        self._shown: str | None = None

    def draw(self, snap: Snapshot) -> None:
        html = self.html(snap)
        if html != self._shown:
            self._shown = html
            self.words.content = html
            self.button.disabled = snap.null is None

    def html(self, snap: Snapshot) -> str:
        """The folder's words for ``snap``."""
        _ = self.tr.gettext
        if snap.null is None:
            text = _(
                "J has full rank here: every joint motion moves the tool. At a singularity, some do not."
            )
            return f'<div class="jl"><div class="jl-note">{fmt.escape(text)}</div></div>'
        motion = null_motion_text(snap.null.direction, lambda c: fmt.number(c, 4, self.tr))
        text = _(
            "At this singularity the joint motion {motion} lies in Ker J: J q̇ = 0, "
            "the joints move and the tool stands still."
        ).format(motion=motion)
        return f'<div class="jl"><div class="jl-note">{fmt.escape(text)}</div></div>'


SHAPE_WORDS = {"line": N_("a line"), "circle": N_("a circle")}
"""The path menu's entries, in English (shown in the tab's language)."""


class PathPanel:
    """The path folder: the course's method in words, a menu of paths and a Follow button."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator) -> None:
        _ = tr.gettext
        self._shapes = {_(SHAPE_WORDS[s]): s for s in SHAPES}  # the menu's words → the shape
        with gui.add_folder(_("Follow a path y(t): the Jacobian method"), expand_by_default=False):
            text = _(
                "Newton finds q(t₀) with k(q(t₀)) = y(t₀); then q̇ = J⁻¹ẏ(t) (J⁺ẏ(t) + (I − J⁺J)ω(t) "
                "for a redundant arm, here ω = 0) carries the tool along the path, through the tool point. "
                "The rates chart shows q̇(t); near a singularity they blow up and the tool leaves the path."
            )
            gui.add_html(f'<div class="jl"><div class="jl-note">{fmt.escape(text)}</div></div>')
            self.shape = gui.add_dropdown(
                _("Path"), tuple(self._shapes), initial_value=next(iter(self._shapes))
            )
            self.button = gui.add_button(_("Follow the path"), icon=viser.Icon.ROUTE)
            self.button.on_click(lambda _: self._follow(dispatch))

    def _follow(self, dispatch: Dispatch) -> None:
        shape = self._shapes.get(str(self.shape.value))  # a value the menu offers, else nothing
        if shape is not None:
            dispatch(FollowToolPath(shape))


class CourseMotion:
    """The null-motion and path folders of the Motion tab."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator) -> None:
        self.null = NullMotionPanel(gui, dispatch, tr)
        self.path = PathPanel(gui, dispatch, tr)

    def draw(self, snap: Snapshot) -> None:
        self.null.draw(snap)
