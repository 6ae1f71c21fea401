"""The Motion tab's null joint motion at a singularity (Ker J): said in words and played.

At a singularity some joint rates move nothing at the tool (J q̇ = 0): the Puma's wrist at q₅ = 0
turns q₄ and q₆ against each other. The snapshot holds that motion (``snap.null``); this folder
says it and its button plays it back and forth (the arm moves, the tool stands still).
"""

from __future__ import annotations

import viser

from ...core.actions import PlayNullMotion
from ...core.i18n import Translator
from ...core.self_motion import null_motion_text
from ...core.snapshot import Snapshot
from .. import fmt
from .common import Dispatch

__all__ = ["NullMotionPanel"]


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
